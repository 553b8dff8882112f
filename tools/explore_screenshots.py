"""Screenshots of ``kreisel explore`` for the README and the guide, and the frame rate of
its playback, in Debian's headless Chromium (the harness of tests/test_explore_browser.py).

    .venv/bin/python tools/explore_screenshots.py [--out docs/_static/explore]

Writes main.png (the 3D view and the charts), atlas.png, sweeps.png, export.png and
kovalevskaya.png, and prints the frames per second reached while playing a long run (a
tippe top over 120 s, 20001 samples) at real time, in three rounds of 4 s. Headless Chromium
draws WebGL in software (SwiftShader), so the rate is a lower bound of what a browser on a GPU
reaches.
"""

from __future__ import annotations

import argparse
import io
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))

from _browser import Server, chromium, open_page, wait_for  # noqa: E402

WIDTH = 1100  # px of the saved images


def save(driver, path: Path) -> None:
    from PIL import Image

    img = Image.open(io.BytesIO(driver.get_screenshot_as_png())).convert("RGB")
    img = img.resize((WIDTH, round(img.height * WIDTH / img.width)), Image.LANCZOS)
    # 256 colours are plenty for a page: a third of the bytes in git
    img.quantize(colors=256, method=Image.Quantize.MEDIANCUT).save(path, optimize=True)
    print(f"wrote {path}")


def click(driver, selector: str) -> None:
    from selenium.webdriver.common.by import By

    driver.find_element(By.CSS_SELECTOR, selector).click()


def seek(driver, t: float) -> None:
    driver.execute_script(
        "if (window.explore.playing) document.getElementById('play').click();"
        "const s = document.getElementById('slider'); s.value = arguments[0];"
        "s.dispatchEvent(new Event('input'));",
        t,
    )


def frame_rate(driver, seconds: float = 5.0) -> float:
    """Frames drawn per second while playing the run on the page (requestAnimationFrame)."""
    driver.execute_script("if (!window.explore.playing) document.getElementById('play').click();")
    start = driver.execute_script("return [window.explore.frames, performance.now()]")
    time.sleep(seconds)
    end = driver.execute_script("return [window.explore.frames, performance.now()]")
    return (end[0] - start[0]) / ((end[1] - start[1]) / 1000.0)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=ROOT / "docs" / "_static" / "explore")
    args = ap.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)

    from selenium.webdriver.common.action_chains import ActionChains
    from selenium.webdriver.common.by import By
    from selenium.webdriver.support.ui import Select

    import kreisel

    with tempfile.TemporaryDirectory() as tmp:
        spec = {
            "top": {"preset": "tippe-ball"},  # a top on one tip sphere: s is a field
            "grid": {
                "s": {"start": 0.002, "stop": 0.012, "num": 11},
                "A": {"start": 2.0e-6, "stop": 3.6e-6, "num": 11},
            },
        }
        kreisel.sweep(spec, str(Path(tmp) / "tippe-ball-s-A.zarr"), progress=False)
        server = Server(store=Path(tmp))
        driver = chromium(1400, 1450)
        try:
            open_page(driver, server.url)
            seek(driver, 2.45)
            save(driver, args.out / "main.png")
            click(driver, "#tabs [data-tab=atlas]")
            save(driver, args.out / "atlas.png")
            click(driver, "#tabs [data-tab=sweeps]")
            Select(driver.find_element(By.ID, "store")).select_by_value("tippe-ball-s-A.zarr")
            wait_for(driver, "return document.getElementById('sweep-var').value !== ''")
            runs = int(driver.find_element(By.ID, "run-count").text)
            canvas = driver.find_element(By.ID, "sweep-map")
            ActionChains(driver).move_to_element_with_offset(canvas, -60, -40).click().perform()
            wait_for(
                driver, f"return Number(document.getElementById('run-count').textContent) > {runs}"
            )
            seek(driver, 3.0)
            save(driver, args.out / "sweeps.png")
            click(driver, "#tabs [data-tab=export]")
            save(driver, args.out / "export.png")
            open_page(driver, server.url + "?preset=kovalevskaya")
            seek(driver, 6.0)
            save(driver, args.out / "kovalevskaya.png")
            # a long run: the tippe top over 120 s, 20001 samples, played at real time
            open_page(driver, server.url)
            driver.execute_script(
                "document.getElementById('f-simulation-t_end').value = '120';"
                "document.getElementById('f-simulation-samples').value = '20001';"
                "document.getElementById('run').click();"
            )
            wait_for(driver, "return window.explore.run.t.length === 20001", 60)
            # three rounds: the machine may be shared, and the rate follows its load
            rates = sorted(frame_rate(driver, 4.0) for _ in range(3))
            print(
                "frame rate playing a 120 s run of 20001 samples at real time: "
                + ", ".join(f"{r:.1f}" for r in rates)
                + f" frames/s (median {rates[1]:.1f}; headless Chromium, software WebGL)"
            )
        finally:
            driver.quit()
            server.stop()


if __name__ == "__main__":
    main()
