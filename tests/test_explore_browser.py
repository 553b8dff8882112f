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
    shown = text(page, "inversion-time")
    assert shown == f"{expected!r} s"
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
    values = {
        k: float(field(page, "top", k).get_attribute("value")) for k in ("s", "rho", "A", "C")
    }
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
    shown = text(page, "inversion-time")
    assert shown == f"{float(ds['inversion_time'].values[-1, -1])!r} s"


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
    assert text(browser, "inversion-time") == f"{inversion!r} s"
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
