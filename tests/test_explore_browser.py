"""``kreisel explore`` in a real browser: Debian's Chromium, headless, driven by Selenium
(`make test` installs chromium and chromium-driver when they are missing). One server and one
browser serve every test of the module; each test starts from a fresh page."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time

import _browser
import numpy as np
import pytest
from _browser import chromium, have_browser, open_page, wait_for

import kreisel
from kreisel._config import from_tables, preset

if not have_browser():
    if os.environ.get("CI"):
        raise RuntimeError("the browser tests need /usr/bin/chromium and /usr/bin/chromedriver")
    pytest.skip("no Chromium: `make test` installs Debian's chromium", allow_module_level=True)

from selenium.webdriver.common.action_chains import ActionChains  # noqa: E402
from selenium.webdriver.common.by import By  # noqa: E402
from selenium.webdriver.support.ui import Select  # noqa: E402

# The page of the tippe top's ball alone (the preset tippe-ball, whose s and rho the atlas
# moves); the tippe preset with its peg has a test of its own at the end.
BALL = "?preset=tippe-ball"

# the fixtures store (a folder of sweep stores) and server (kreisel explore --store it)
store, server = _browser.store_fixture, _browser.server_fixture


@pytest.fixture(scope="module")
def browser():
    d = chromium()
    yield d
    d.quit()


@pytest.fixture
def page(browser, server):
    """The page with the tippe top's first run: loaded anew unless the last test left it so
    (one run, no field marked bad); the console's messages so far are dropped."""
    fresh = browser.execute_script(
        "return !!(window.explore && window.explore.runs === 1"
        " && !document.querySelector('.field.bad'))"
    )
    browser.get_log("browser")
    if not fresh or not browser.current_url.startswith(server.url + BALL):
        open_page(browser, server.url + BALL)
    return browser


def text(driver, id_):
    return driver.find_element(By.ID, id_).text


def runs(driver) -> int:
    return int(text(driver, "run-count"))


def field(driver, table, name):
    return driver.find_element(By.ID, f"f-{table}-{name}")


def seek(driver, t):
    """Pauses the playback and moves the time slider to t (s), as a user drags it."""
    driver.execute_script(
        "if (window.explore.playing) document.getElementById('play').click();"
        "const s = document.getElementById('slider'); s.value = arguments[0];"
        "s.dispatchEvent(new Event('input'));",
        t,
    )


def assert_inversion_time(driver, expected: float):
    """The page shows ``expected`` (s) rounded to 4 significant digits, and keeps it whole in
    its tooltip and its run."""
    rounded = repr(float(f"{expected:.4g}")).removesuffix(".0")
    assert text(driver, "inversion-time") == f"{rounded} s"
    title = driver.find_element(By.ID, "inversion-time").get_attribute("title")
    assert title == f"{expected!r} s"
    assert driver.execute_script("return window.explore.run.inversion_time") == expected


def tab(driver, name):
    driver.find_element(By.CSS_SELECTOR, f"#tabs [data-tab={name}]").click()


def test_the_page_loads_with_no_console_error(browser, server):
    browser.get_log("browser")
    open_page(browser, server.url)
    page = browser
    errors = [e for e in page.get_log("browser") if e["level"] == "SEVERE"]
    assert errors == []
    # the default preset: the tippe top with its peg
    assert runs(page) == 1 and text(page, "top-repr").startswith("PlayTop(m=0.006")


def test_the_tippe_top_turns_over_at_the_inversion_time_of_kreisel_simulate(page):
    t = preset("tippe-ball")
    p = {k: v for k, v in t["top"].items() if k not in ("kind", "friction", "mu")}
    top = kreisel.PlayTop(**p, friction=kreisel.Viscous(t["top"]["mu"]))
    traj = kreisel.simulate(
        top,
        top.state(**t["state"]),
        8.0,
        rtol=1e-9,
        t_eval=np.linspace(0.0, 8.0, 2001),
        events=[kreisel.events.inversion(0.9)],
    )
    expected = traj.events[0].t
    assert_inversion_time(page, expected)
    # the top on the page turns over: the figure axis from down (u near -1) to up
    # and so does the body drawn: its figure axis e3 = R(q) (0, 0, 1)
    e3z = (
        "const body = window.explore.view.body;"
        "return body.up.clone().set(0, 0, 1).applyQuaternion(body.quaternion).z;"
    )
    seek(page, 0.0)
    assert float(text(page, "u-now")) < -0.99 and page.execute_script(e3z) < -0.99
    seek(page, 7.9)
    assert float(text(page, "u-now")) > 0.99 and page.execute_script(e3z) > 0.99


def test_the_3d_view_is_drawn_and_moves(page):
    canvas = page.find_element(By.CSS_SELECTOR, "#view3d canvas")
    seek(page, 0.5)
    first = canvas.screenshot_as_png
    seek(page, 2.7)
    second = canvas.screenshot_as_png
    assert first != second
    import io

    from PIL import Image

    img = np.asarray(Image.open(io.BytesIO(second)).convert("RGB")).reshape(-1, 3)
    colours = np.unique(img // 8, axis=0)
    assert len(colours) > 50  # a drawn scene, not a blank canvas


def test_the_camera_turns_with_the_mouse_while_paused(page):
    seek(page, 1.0)  # paused
    canvas = page.find_element(By.CSS_SELECTOR, "#view3d canvas")
    where = "return window.explore.view.camera.position.toArray()"
    before, image = page.execute_script(where), canvas.screenshot_as_png
    ActionChains(page).move_to_element(canvas).click_and_hold().move_by_offset(
        120, 30
    ).release().perform()
    wait_for(page, "return !window.explore.view.dirty")
    assert page.execute_script(where) != before
    assert canvas.screenshot_as_png != image


def test_a_bad_parameter_shows_the_api_message_and_runs_nothing(page):
    before = runs(page)
    shown = text(page, "inversion-time")
    m = field(page, "top", "m")
    m.clear()
    m.send_keys("-1")
    page.find_element(By.ID, "run").click()
    error = wait_for(
        page, "return document.querySelector('.field[data-field=m] .error').textContent"
    )
    t = preset("tippe-ball")["top"]
    p = {k: v for k, v in t.items() if k not in ("kind", "friction", "mu", "m")}
    with pytest.raises(kreisel.ParameterError) as e:
        kreisel.PlayTop(m=-1, **p, friction=kreisel.Viscous(1.0))
    assert error == str(e.value)
    time.sleep(0.3)
    assert runs(page) == before and text(page, "inversion-time") == shown


def test_a_click_on_the_atlas_changes_the_top_and_runs_it(page):
    tab(page, "atlas")
    before = runs(page)
    old = page.execute_script("return window.explore.run.atlas")
    canvas = page.find_element(By.ID, "atlas-plane")
    ActionChains(page).move_to_element_with_offset(canvas, 60, -120).click().perform()
    wait_for(page, f"return Number(document.getElementById('run-count').textContent) > {before}")
    new = page.execute_script("return window.explore.run.atlas")
    assert (new["alpha"], new["gamma"]) != (old["alpha"], old["gamma"])
    # the top run is the form's: alpha = s / rho, gamma = A / C
    values = page.execute_script("return window.explore.run.tables.top")
    assert new["alpha"] == pytest.approx(values["s"] / values["rho"], rel=1e-12)
    assert new["gamma"] == pytest.approx(values["A"] / values["C"], rel=1e-12)
    assert new["gamma"] > old["gamma"] and new["alpha"] > old["alpha"]


def test_a_sweep_cell_opens_its_run(page, store):
    tab(page, "sweeps")
    Select(page.find_element(By.ID, "store")).select_by_value("tippe.zarr")
    wait_for(page, "return document.getElementById('sweep-var').value === 'inversion_time'")
    before = runs(page)
    canvas = page.find_element(By.ID, "sweep-map")
    # the upper right cell: the last s (rows) and the last A (columns)
    size = canvas.size
    ActionChains(page).move_to_element_with_offset(
        canvas, size["width"] // 2 - 130, -size["height"] // 2 + 60
    ).click().perform()
    wait_for(page, f"return Number(document.getElementById('run-count').textContent) > {before}")
    ds = kreisel.open_sweep(str(store / "tippe.zarr"))
    assert float(field(page, "top", "s").get_attribute("value")) == ds["s"].values[-1]
    assert float(field(page, "top", "A").get_attribute("value")) == ds["A"].values[-1]
    assert_inversion_time(page, float(ds["inversion_time"].values[-1, -1]))


def test_the_exported_toml_reproduces_the_run_with_kreisel_run(page, tmp_path):
    tab(page, "export")
    toml = text(page, "toml")
    downloaded = page.execute_async_script(
        "const done = arguments[0];"
        "fetch('/api/export/toml', {method: 'POST', headers: {'content-type': 'application/json'},"
        " body: JSON.stringify({tables: window.explore.run.tables})})"
        ".then(r => r.text()).then(done);"
    )
    assert downloaded.strip() == toml.strip()
    path = tmp_path / "tippe.toml"
    path.write_text(toml)
    out = tmp_path / "out"
    cmd = [
        sys.executable,
        "-m",
        "kreisel",
        "run",
        str(path),
        "--out",
        str(out),
        "--no-figures",
        "--format",
        "csv",
    ]
    subprocess.run(cmd, check=True, capture_output=True)
    summary = json.loads((out / "summary.json").read_text())
    run = page.execute_script("return window.explore.run")
    assert summary["result"]["inversion_time"] == run["inversion_time"]
    assert summary["result"]["samples"] == len(run["t"])
    assert summary["result"]["final"]["u"] == run["series"]["u"][-1]


def test_the_tippe_preset_with_its_peg_turns_over_onto_the_peg(browser, server):
    """The tippe preset (Leine and Glocker's top, two spheres, Coulomb-Contensou friction):
    the inversion time shown is kreisel.simulate's; on its peg at 3 s; both parts drawn."""
    open_page(browser, server.url + "?preset=tippe")
    t = preset("tippe")
    problem = from_tables(t)
    traj = kreisel.simulate(problem.model, problem.state, 8.0, rtol=1e-9,
                            t_eval=np.linspace(0.0, 8.0, 2001),
                            events=[kreisel.events.inversion(0.9)])  # fmt: skip
    inversion = next(e.t for e in traj.events if e.name == "inversion")
    assert_inversion_time(browser, inversion)
    seek(browser, 3.0)
    assert float(text(browser, "u-now")) > 0.99
    parts = browser.execute_script("return window.explore.run.body.parts.map((p) => p.name)")
    assert {"ball", "peg"} <= set(parts)
    open_page(browser, server.url + BALL)  # as the other tests expect it


def test_the_toy_top_preset_lives_its_life_to_rest(browser, server):
    """The toy-top preset (kreisel.bodies.toy_top: tip, shoulder ring, handle): the page runs
    it to the event rest, lists kreisel's events (the shoulder's touchdown, both parts
    sticking, rest) at kreisel.simulate's times, ends rolling at the tilt its tip and shoulder
    fix, and draws its three parts."""
    open_page(browser, server.url + "?preset=toy-top")
    problem = from_tables(preset("toy-top"))
    s = problem.settings
    evs = [kreisel.events.inversion(0.9), kreisel.events.rest()]
    traj = kreisel.simulate(problem.model, problem.state, s.t_end, rtol=s.rtol, events=evs)
    want = [(e.name, e.part, round(e.t, 3)) for e in traj.events]
    assert want[0][:2] == ("touchdown", "shoulder") and want[-1][:2] == ("rest", None)
    got = browser.execute_script(
        "return window.explore.run.events.map((e) => [e.name, e.part, e.t])"
    )
    assert [(n, p, round(t, 3)) for n, p, t in got] == want
    shown = text(browser, "events")
    assert (
        f"touchdown shoulder {want[0][2]:.3f} s" in shown and f"rest {want[-1][2]:.3f} s" in shown
    )
    seek(browser, want[-1][2])
    assert text(browser, "mode-now") == "roll"
    assert float(text(browser, "u-now")) == pytest.approx(traj.u[-1], abs=1e-4)
    parts = browser.execute_script("return window.explore.run.body.parts.map((p) => p.name)")
    assert {"tip", "shoulder", "handle"} <= set(parts)
    open_page(browser, server.url + BALL)  # as the other tests expect it


# ------------------------------------------------------------------------------------------
# the explorer as a viewer: framing, the form, the player's keys and buttons, files and links
# ------------------------------------------------------------------------------------------


def _saved_bytes(driver) -> tuple[str, bytes]:
    """(name, content) of the last file the page saved (window.saved)."""
    import base64

    name, data = driver.execute_async_script(
        "const done = arguments[0]; const s = window.saved;"
        "const r = new FileReader(); r.onload = () => done([s.name, r.result.split(',')[1]]);"
        "r.readAsDataURL(s.blob);"
    )
    return name, base64.b64decode(data)


def _no_downloads(driver):
    """The browser saves no file to disk (the page's window.saved keeps what it saved)."""
    driver.execute_cdp_cmd("Browser.setDownloadBehavior", {"behavior": "deny"})


@pytest.mark.parametrize("name", ["euler-disk", "coin"])
def test_a_disk_and_a_coin_are_framed_by_their_size(browser, server, name):
    """The whole disk fits in the view with room around it: the camera is at least as far as
    the distance at which the disk's diameter fills the view's height, and at most 4 times."""
    open_page(browser, server.url + f"?preset={name}")
    shape = preset(name)["top"]["shape"]
    radius = max(p.get("major", 0) + p.get("minor", 0) or p.get("radius", 0) for p in shape)
    fov, distance = browser.execute_script(
        "const v = window.explore.view;"
        "return [v.camera.fov, v.camera.position.distanceTo(v.controls.target)];"
    )
    fits = radius / np.tan(np.radians(fov) / 2)  # the diameter fills the height at this distance
    assert fits <= distance <= 4 * fits
    open_page(browser, server.url + BALL)


def test_the_egg_is_drawn_without_z_fighting(browser, server):
    """The egg's outline and its spheroid were two coincident surfaces: the view showed the
    outline's blue through the spheroid's red and yellow stripes. Now none of the body's pixels
    is the outline's blue."""
    import io

    from PIL import Image

    open_page(browser, server.url + "?preset=egg")
    browser.find_element(By.ID, "traces").click()  # no trace over the body
    browser.find_element(By.ID, "forces").click()  # nor the contact's arrows (a blue one)
    seek(browser, 0.0)
    png = browser.find_element(By.CSS_SELECTOR, "#view3d canvas").screenshot_as_png
    rgb = np.asarray(Image.open(io.BytesIO(png)).convert("RGB")).astype(int)
    r, g, b = rgb[..., 0], rgb[..., 1], rgb[..., 2]
    stripes = ((r > g + 40) & (r > b + 40)).sum()  # the spheroid's red and yellow
    blue = ((b > r + 80) & (b > g + 30)).sum()  # the outline's blue (#2e86c1)
    assert stripes > 2000 and blue < 0.005 * stripes
    open_page(browser, server.url + BALL)


def test_the_peg_shows_when_the_tippe_top_stands_on_it(browser, server):
    """At 3 s the tippe top stands inverted on its peg: from the default camera, rays to the
    peg's points reach the peg first (the ball does not hide it)."""
    open_page(browser, server.url + "?preset=tippe")
    seek(browser, 3.0)
    assert float(text(browser, "u-now")) > 0.99
    seen = browser.execute_async_script(
        "const done = arguments[0];"
        "import('three').then((THREE) => {"
        "  const v = window.explore.view; v.render();"
        "  const peg = v.body.getObjectByName('peg'); peg.updateWorldMatrix(true, false);"
        "  const pos = peg.geometry.attributes.position; const ray = new THREE.Raycaster();"
        "  let hits = 0; const p = new THREE.Vector3();"
        "  for (let k = 0; k < pos.count; k += 7) {"
        "    p.fromBufferAttribute(pos, k).applyMatrix4(peg.matrixWorld);"
        "    const dir = p.clone().sub(v.camera.position); const far = dir.length();"
        "    ray.set(v.camera.position, dir.normalize()); ray.far = far * 1.0001;"
        "    const first = ray.intersectObjects(v.body.children, false)[0];"
        "    if (first && first.object === peg && first.distance > far * 0.9999) hits += 1;"
        "  }"
        "  done(hits);"
        "});"
    )
    assert seen >= 3
    open_page(browser, server.url + BALL)


def test_an_unknown_preset_is_named_with_the_known_ones(browser, server):
    open_page(browser, server.url + "?preset=nonsense")
    with pytest.raises(kreisel.ParameterError) as e:
        preset("nonsense")
    assert text(browser, "notice").startswith(str(e.value))
    open_page(browser, server.url + BALL)


# the units of the fields, as the classes' docstrings give them
UNITS = {
    ("top", "m"): "kg",
    ("top", "A"): "kg m²",
    ("top", "C"): "kg m²",
    ("top", "s"): "m",
    ("top", "rho"): "m",
    ("top", "g"): "m/s²",
    ("top", "air_drag"): "N m s",
    ("state", "theta"): "rad",
    ("state", "psi_dot"): "rad/s",
    ("state", "vx"): "m/s",
    ("simulation", "t_end"): "s",
    ("simulation", "dt"): "s",
}


def test_every_field_has_a_readable_label_a_unit_and_a_tooltip(page):
    rows = page.execute_script(
        "return [...document.querySelectorAll('#form .field')].map((r) => [r.dataset.table,"
        " r.dataset.field, r.querySelector('label').textContent,"
        " r.querySelector('.unit').textContent, r.title]);"
    )
    assert len(rows) == 15 + 9 + 7  # a play top's fields
    no_unit = {"friction", "method", "exact"}
    for _, name, label, unit, tip in rows:
        assert label != name or len(name) > 3, name  # words, not the bare symbol
        assert (unit == "") == (name in no_unit), name
        assert tip.startswith(f"{name}: ") and len(tip) > len(name) + 10, name
    units = {(t, n): u for t, n, _, u, _ in rows}
    for key, unit in UNITS.items():
        assert units[key] == unit, key


def test_results_are_rounded_and_the_form_keeps_exact_values(browser, server):
    """The toy top's inertia comes from its body (many digits): the form shows 6 significant
    digits, runs the exact values, and the inversion time reads 4 significant digits."""
    open_page(browser, server.url + "?preset=toy-top")
    tables = from_tables(preset("toy-top")).tables
    long = [k for k, v in tables["top"].items() if isinstance(v, float) and len(repr(v)) > 10]
    assert long  # the preset has such numbers
    for k in long:
        shown = field(browser, "top", k).get_attribute("value")
        assert float(shown) == pytest.approx(tables["top"][k], rel=1e-6)
        digits = shown.split("e")[0].replace("-", "").replace(".", "").lstrip("0")
        assert len(digits) <= 6, (k, shown)
    before = runs(browser)
    browser.find_element(By.ID, "run").click()
    wait_for(browser, f"return Number(document.getElementById('run-count').textContent) > {before}")
    assert browser.execute_script("return window.explore.run.tables.top") == tables["top"]
    open_page(browser, server.url + BALL)
    t = browser.execute_script("return window.explore.run.inversion_time")
    assert len(repr(t)) > 8  # a time of many digits...
    assert text(browser, "inversion-time") == f"{t:.4g} s"  # ...shown with 4


def test_the_shape_is_edited_part_by_part(browser, server):
    open_page(browser, server.url + "?preset=tippe")
    shape = preset("tippe")["top"]["shape"]
    rows = browser.find_elements(By.CSS_SELECTOR, "#f-top-shape .part")
    assert len(rows) == len(shape) == 2
    for row, part in zip(rows, shape):
        values = {
            i.get_attribute("data-key"): i.get_attribute("value")
            for i in row.find_elements(By.CSS_SELECTOR, "input.part-value")
        }
        assert values["name"] == part["name"]
        assert float(values["radius"]) == part["radius"] and float(values["z"]) == part["z"]
    peg = rows[1].find_element(By.CSS_SELECTOR, "input[data-key=radius]")
    peg.clear()
    peg.send_keys("0.004")
    # a third part, a torus: its fields are a torus's
    browser.find_element(By.ID, "add-part").click()
    new = browser.find_elements(By.CSS_SELECTOR, "#f-top-shape .part")[-1]
    Select(new.find_element(By.CSS_SELECTOR, ".part-kind")).select_by_value("torus")
    keys = [i.get_attribute("data-key") for i in new.find_elements(By.CSS_SELECTOR, "input")]
    assert keys == ["name", "major", "minor", "z"]
    new.find_element(By.CSS_SELECTOR, ".remove").click()
    before = runs(browser)
    browser.find_element(By.ID, "run").click()
    wait_for(browser, f"return Number(document.getElementById('run-count').textContent) > {before}")
    edited = [dict(shape[0]), {**shape[1], "radius": 0.004}]
    assert browser.execute_script("return window.explore.run.tables.top.shape") == edited
    open_page(browser, server.url + BALL)


def test_the_3d_view_has_a_legend_of_its_traces(browser, server, page):
    colours = page.execute_script(
        "const v = window.explore.view;"
        "const swatch = (n) => getComputedStyle(document.querySelector("
        "  `#legend [data-trace=${n}] .swatch`)).borderTopColor;"
        "return [swatch('tip'), swatch('contact'), '#' + v.tipLine.material.color.getHexString(),"
        " '#' + v.contactLine.material.color.getHexString()];"
    )

    def rgb(h):
        return f"rgb({int(h[1:3], 16)}, {int(h[3:5], 16)}, {int(h[5:7], 16)})"

    assert colours[0] == rgb(colours[2]) and colours[1] == rgb(colours[3])
    assert page.find_element(By.ID, "legend").is_displayed()
    open_page(browser, server.url + "?preset=gyroscope")  # a top on a pivot: no contact point
    contact = browser.find_element(By.CSS_SELECTOR, "#legend [data-trace=contact]")
    assert not contact.is_displayed()
    open_page(browser, server.url + BALL)


def test_the_sweep_map_reads_out_the_cell_under_the_mouse(page, store):
    tab(page, "sweeps")
    Select(page.find_element(By.ID, "store")).select_by_value("tippe.zarr")
    wait_for(page, "return document.getElementById('sweep-var').value === 'inversion_time'")
    canvas = page.find_element(By.ID, "sweep-map")
    size = canvas.size
    ActionChains(page).move_to_element_with_offset(
        canvas, size["width"] // 2 - 130, -size["height"] // 2 + 60
    ).perform()
    readout = wait_for(page, "return document.getElementById('sweep-readout').textContent")
    ds = kreisel.open_sweep(str(store / "tippe.zarr"))
    import re

    m = re.fullmatch(r"s = (\S+), A = (\S+): inversion_time = (\S+)( s)?", readout)
    assert m, readout
    assert float(m[1]) == pytest.approx(ds["s"].values[-1], rel=1e-3)
    assert float(m[2]) == pytest.approx(ds["A"].values[-1], rel=1e-3)
    assert float(m[3]) == pytest.approx(float(ds["inversion_time"].values[-1, -1]), rel=1e-3)


def test_the_arrow_keys_and_buttons_step_one_sample_and_space_plays(page):
    seek(page, 1.0)
    t = page.execute_script("return window.explore.run.t")
    i = int(np.searchsorted(t, 1.0, side="right")) - 1  # the sample at or before 1 s
    body = page.find_element(By.TAG_NAME, "body")
    now = "return window.explore.t"
    body.send_keys("\ue014")  # right arrow
    assert page.execute_script(now) == t[i + 1]
    body.send_keys("\ue014")
    assert page.execute_script(now) == t[i + 2]
    body.send_keys("\ue012")  # left arrow
    assert page.execute_script(now) == t[i + 1]
    page.find_element(By.ID, "step-back").click()
    assert page.execute_script(now) == t[i]
    page.find_element(By.ID, "step-forward").click()
    assert page.execute_script(now) == t[i + 1]
    assert float(text(page, "clock").split()[2]) == pytest.approx(t[i + 1], abs=5e-4)
    assert not page.execute_script("return window.explore.playing")
    body.send_keys(" ")
    assert page.execute_script("return window.explore.playing")
    assert text(page, "play") == "Pause"
    body.send_keys(" ")
    assert not page.execute_script("return window.explore.playing")


def test_the_camera_resets_and_looks_from_the_side_and_the_top(page):
    seek(page, 0.0)
    where = (
        "const v = window.explore.view;"
        "return [v.camera.position.toArray(), v.controls.target.toArray()];"
    )
    home = page.execute_script(where)
    page.find_element(By.ID, "view-top").click()
    eye, target = (np.array(x) for x in page.execute_script(where))
    d = eye - target
    assert d[2] / np.linalg.norm(d) > np.cos(np.radians(0.1))  # straight down
    page.find_element(By.ID, "view-side").click()
    eye, target = (np.array(x) for x in page.execute_script(where))
    assert abs(eye[2] - target[2]) < 1e-9 * np.linalg.norm(eye - target) + 1e-12  # level
    canvas = page.find_element(By.CSS_SELECTOR, "#view3d canvas")
    ActionChains(page).move_to_element(canvas).click_and_hold().move_by_offset(
        80, 40
    ).release().perform()
    page.find_element(By.ID, "view-reset").click()
    eye, target = page.execute_script(where)
    assert eye == pytest.approx(home[0], rel=1e-9) and target == pytest.approx(home[1])


def test_a_link_reproduces_the_edited_run(browser, server, page):
    psi = field(page, "state", "psi_dot")
    psi.clear()
    psi.send_keys("170")
    before = runs(page)
    page.find_element(By.ID, "run").click()
    wait_for(page, f"return Number(document.getElementById('run-count').textContent) > {before}")
    edited = page.execute_script("return window.explore.run")
    page.find_element(By.ID, "copy-link").click()
    link = page.find_element(By.ID, "link").get_attribute("value")
    assert link.startswith(server.url + "?run=")
    open_page(browser, link)
    again = browser.execute_script("return window.explore.run")
    assert again["tables"] == edited["tables"] and again["tables"]["state"]["psi_dot"] == 170
    # the run of those tables is kreisel's
    problem = from_tables(edited["tables"])
    s = problem.settings
    evs = [kreisel.events.inversion(0.9), kreisel.events.rest()]
    traj = kreisel.simulate(problem.model, problem.state, s.t_end, rtol=s.rtol, atol=s.atol,
                            t_eval=np.linspace(0, s.t_end, 2001), events=evs)  # fmt: skip
    inversion = next(e.t for e in traj.events if e.name == "inversion")
    assert again["inversion_time"] == inversion
    open_page(browser, server.url + BALL)


def test_a_toml_file_is_loaded_and_run(page, tmp_path):
    path = tmp_path / "fast.toml"
    path.write_text(
        '[top]\npreset = "tippe-ball"\nm = 0.021\n\n[state]\npsi_dot = 160.0\n\n'
        "[simulation]\nt_end = 6.0\nsamples = 1201\n"
    )
    before = runs(page)
    page.find_element(By.ID, "load-toml").send_keys(str(path))
    wait_for(page, f"return Number(document.getElementById('run-count').textContent) > {before}")
    import tomllib

    problem = from_tables(tomllib.loads(path.read_text()))
    run = page.execute_script("return window.explore.run")
    assert run["tables"] == problem.tables
    assert len(run["t"]) == 1201 and run["t"][-1] == 6.0
    assert text(page, "preset-summary") == "from fast.toml"
    # a file kreisel run refuses is refused with kreisel run's message
    bad = tmp_path / "bad.toml"
    bad.write_text("[top]\nm = \n")
    page.find_element(By.ID, "load-toml").send_keys(str(bad))
    message = wait_for(page, "return document.getElementById('notice').textContent")
    assert message.startswith("bad.toml is not valid TOML: ") and "line 2" in message
    assert runs(page) == before + 1


def test_a_screenshot_of_the_view_is_saved_as_png(page):
    import io

    from PIL import Image

    _no_downloads(page)
    seek(page, 2.0)
    page.find_element(By.ID, "screenshot").click()
    wait_for(page, "return window.saved && window.saved.name.endsWith('.png')")
    name, data = _saved_bytes(page)
    assert name == "kreisel-tippe-ball-t2.000s.png"
    img = Image.open(io.BytesIO(data))
    size = page.execute_script(
        "const c = document.querySelector('#view3d canvas'); return [c.width, c.height];"
    )
    assert img.format == "PNG" and list(img.size) == size
    assert len(np.unique(np.asarray(img.convert("RGB")).reshape(-1, 3) // 8, axis=0)) > 50


def test_a_video_of_the_view_is_recorded_as_webm(page):
    _no_downloads(page)
    page.execute_script("window.saved = null;")
    if not page.execute_script("return window.explore.playing"):
        page.find_element(By.ID, "play").click()
    page.find_element(By.ID, "record").click()
    assert text(page, "record") == "Stop and save"
    time.sleep(1.5)
    page.find_element(By.ID, "record").click()
    wait_for(page, "return window.saved && window.saved.name.endsWith('.webm')")
    name, data = _saved_bytes(page)
    assert name.startswith("kreisel-tippe-ball-")
    assert data[:4] == bytes.fromhex("1a45dfa3")  # EBML, the container of WebM
    assert b"webm" in data[:64] and len(data) > 2000
    assert text(page, "record") == "Record video"


def test_a_shaken_top_shows_its_pivot_and_follows_it(browser, server):
    """The kapitza preset: the form shows the pivot's fields (and none for a play top), the
    run is kreisel.simulate's on the shaken pivot (the rod stays up, its balance chart is
    drawn), the body's origin moves with the pivot, and an edited omega reruns."""
    open_page(browser, server.url + "?preset=kapitza")
    t = preset("kapitza")
    assert field(browser, "pivot", "omega").get_attribute("value") == "200"
    assert not browser.find_element(By.ID, "fs-pivot").get_attribute("hidden")
    run = browser.execute_script("return window.explore.run")
    assert run["tables"]["pivot"] == t["pivot"]
    problem = from_tables(t)
    traj = kreisel.simulate(problem.model, problem.state, 3.0, rtol=1e-9,
                            t_eval=np.linspace(0.0, 3.0, 3001))  # fmt: skip
    np.testing.assert_array_equal(run["quaternion"], traj.quaternion)
    assert max(np.array(run["series"]["u"])) <= 1 and min(run["series"]["u"]) > 0.9
    z = []
    for tt in (0.0, np.pi / 200):  # the pivot up at 0, down half a period later
        seek(browser, tt)
        z.append(browser.execute_script("return window.explore.view.body.position.z"))
    # (the view interpolates between samples 1 ms apart)
    assert z[0] == pytest.approx(0.01) and z[1] == pytest.approx(-0.01, abs=1e-4)
    titles = browser.execute_script(
        "return [...document.querySelectorAll('#charts h3')].map((e) => e.textContent)"
    )
    assert any("balance" in x for x in titles), titles
    # a slower shaking: the rod falls (below the Kapitza threshold)
    before = runs(browser)
    box = field(browser, "pivot", "omega")
    box.clear()
    box.send_keys("100")
    browser.find_element(By.ID, "run").click()
    wait_for(browser, f"return window.explore.runs > {before}")
    assert min(browser.execute_script("return window.explore.run.series.u")) < 0.0
    open_page(browser, server.url + BALL)
    assert browser.find_element(By.ID, "fs-pivot").get_attribute("hidden")


def test_the_contact_arrows_and_each_parts_track_follow_the_tippe_top(browser, server):
    """The tippe top with its peg: in the 3D view, a contact point, a normal-force arrow and a
    friction arrow for each part touching, where the part's sphere reaches the floor (its
    lowest point, from the run's own orientation and centre of mass) and sized by
    kreisel.simulate's forces; the chart of each part's contact state; both change as the
    top turns over onto its peg; the forces checkbox hides the arrows."""
    open_page(browser, server.url + "?preset=tippe")
    problem = from_tables(preset("tippe"))
    traj = kreisel.simulate(problem.model, problem.state, 8.0, rtol=1e-9,
                            t_eval=np.linspace(0.0, 8.0, 2001))  # fmt: skip
    shape = problem.model.shape
    arrows = (
        "const v = window.explore.view; return [v.arrowSample, v.forceScale,"
        " v.arrows.map((a) => [a.part, a.point.visible, a.normal.visible,"
        " a.point.position.toArray(), a.normal.userData.force, a.friction.userData.force,"
        " a.friction.userData.direction, a.normal.scale.y])]"
    )
    seen = []
    for t, touching in ((1.0, "ball"), (2.0, "peg")):
        seek(browser, t)
        k, scale, shown = browser.execute_script(arrows)
        assert browser.execute_script("return window.explore.run.t")[k] == traj.t[k]
        assert [a[0] for a in shown] == ["ball", "peg"]
        # the arrows stand where the part's sphere touches the floor: its lowest point
        q = traj.quaternion[k]
        for part, (name, visible, normal_visible, at, n, f, direction, _) in zip(shape, shown):
            lowest = traj.com[k] + _rotate(q, [0.0, 0.0, part.z]) - [0, 0, part.radius]
            assert visible == normal_visible == (name == touching), (t, name)
            if name == touching:
                assert abs(lowest[2]) < 1e-9
                np.testing.assert_allclose(at[:2], lowest[:2], atol=1e-6)
                assert n == pytest.approx(traj.part_normal_force[k, shape.index(part)], rel=1e-6)
                ff = traj.part_friction_force[k, shape.index(part)]
                assert f == pytest.approx(np.hypot(*ff), rel=1e-6, abs=1e-12)
                if f > 0:
                    np.testing.assert_allclose(direction, ff / np.hypot(*ff), atol=1e-6)
            else:
                assert lowest[2] > 1e-6
        seen.append((k, shown))
        parts_now = text(browser, "parts-now")
        assert parts_now == ", ".join(f"{p} {traj.part_modes[p][k]}" for p in ("ball", "peg"))
    assert seen[0][1] != seen[1][1]
    # the chart of each part's contact state, one series per part, changing over the run
    track = browser.execute_script(
        "const c = window.explore.charts.plots.find((p) => p.plot.root.dataset.chart"
        " === 'part_state_0'); return c && [c.plot.series.map((s) => s.label), c.plot.data[1],"
        " c.plot.data[2]]"
    )
    assert track is not None and track[0][1:] == ["ball", "peg"]
    states = browser.execute_script("return window.explore.run.contacts.states")
    assert [states[round(v)] for v in track[1]] == list(traj.part_modes["ball"])
    assert len(set(track[1])) > 1 and len(set(track[2])) > 1
    assert browser.find_element(By.CSS_SELECTOR, '#legend [data-trace="normal"]').is_displayed()
    # the checkbox hides the arrows and their legend
    browser.find_element(By.ID, "forces").click()
    seek(browser, 1.0)
    k, _, shown = browser.execute_script(arrows)
    assert not any(a[1] or a[2] for a in shown)
    assert not browser.find_element(By.CSS_SELECTOR, '#legend [data-trace="normal"]').is_displayed()
    open_page(browser, server.url + BALL)  # as the other tests expect it


def _rotate(q, v):
    """v turned by the unit quaternion q (w, x, y, z), written out: v + 2 w (u x v) + 2 u x
    (u x v)."""
    w, u = q[0] / np.linalg.norm(q), np.asarray(q[1:]) / np.linalg.norm(q)
    uv = np.cross(u, v)
    return np.asarray(v) + 2 * w * uv + 2 * np.cross(u, uv)
