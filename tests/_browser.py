"""Helpers of the browser tests of ``kreisel explore`` (and of tools/explore_screenshots.py):
the server in a subprocess on a free port, and Debian's Chromium driven headless by Selenium
through Debian's chromedriver (nothing is downloaded)."""

from __future__ import annotations

import os
import socket
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

import pytest

CHROMIUM = "/usr/bin/chromium"
CHROMEDRIVER = "/usr/bin/chromedriver"


def have_browser() -> bool:
    return os.access(CHROMIUM, os.X_OK) and os.access(CHROMEDRIVER, os.X_OK)


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def tippe_sweep(path: Path) -> Path:
    """A small sweep store at ``path``: the tippe preset over 2 values of s and 2 of A."""
    import kreisel

    spec = {"top": {"preset": "tippe-ball"}, "grid": {"s": [0.004, 0.006], "A": [2.4e-6, 2.56e-6]}}
    kreisel.sweep(spec, str(path), progress=False)
    return path


@pytest.fixture(scope="module", name="store")
def store_fixture(tmp_path_factory):
    """A folder of sweep stores for ``--store``: tippe.zarr, and link.zarr, a symbolic link to
    a store outside it."""
    root = tmp_path_factory.mktemp("stores")
    tippe_sweep(root / "tippe.zarr")
    outside = tmp_path_factory.mktemp("outside")
    tippe_sweep(outside / "secret.zarr")
    os.symlink(outside / "secret.zarr", root / "link.zarr")
    return root


@pytest.fixture(scope="module", name="server")
def server_fixture(store):
    """``kreisel explore --store`` the folder of :func:`store_fixture`, for a test module."""
    s = Server(store=store)
    yield s
    s.stop()


class Server:
    """``kreisel explore --no-browser --port PORT [--store DIR]`` in a subprocess."""

    def __init__(self, store: Path | None = None, port: int | None = None) -> None:
        self.port = port or free_port()
        self.url = f"http://127.0.0.1:{self.port}/"
        args = [
            sys.executable,
            "-m",
            "kreisel",
            "explore",
            "--no-browser",
            "--port",
            str(self.port),
        ]
        if store is not None:
            args += ["--store", str(store)]
        self.proc = subprocess.Popen(
            args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
        )
        deadline = time.monotonic() + 30
        while True:
            if self.proc.poll() is not None:
                raise RuntimeError(f"kreisel explore ended: {self.proc.stderr.read()}")
            try:
                with urllib.request.urlopen(self.url + "api/schema", timeout=2) as r:
                    if r.status == 200:
                        break
            except OSError:
                if time.monotonic() > deadline:
                    self.stop()
                    raise
                time.sleep(0.1)

    def stop(self) -> None:
        if self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(10)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        for f in (self.proc.stdout, self.proc.stderr):
            if f is not None:
                f.close()


def chromium(width: int = 1400, height: int = 1200):
    """A headless Chromium (software WebGL) that keeps the console's messages."""
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    for arg in (
        "--headless=new",
        "--no-sandbox",
        "--disable-dev-shm-usage",
        "--use-gl=angle",
        "--use-angle=swiftshader",
        "--enable-unsafe-swiftshader",
        "--disable-gpu-sandbox",
        f"--window-size={width},{height}",
        "--hide-scrollbars",
    ):
        options.add_argument(arg)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    return webdriver.Chrome(service=Service(executable_path=CHROMEDRIVER), options=options)


def wait_for(driver, script: str, timeout: float = 20.0):
    """Runs ``script`` (returning a value) until it returns a truthy value."""
    deadline = time.monotonic() + timeout
    while True:
        value = driver.execute_script(script)
        if value:
            return value
        if time.monotonic() > deadline:
            raise TimeoutError(f"the page never made this true: {script}")
        time.sleep(0.05)


def open_page(driver, url: str, timeout: float = 30.0) -> None:
    """Loads the page and waits for its first run."""
    driver.get(url)
    wait_for(driver, "return document.body.dataset.ready === 'true'", timeout)
