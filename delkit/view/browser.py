"""A headless Chromium for the viewer's tests, benchmark and screenshots: Debian's ``chromium`` and
``chromium-driver`` driven by selenium, with a fresh profile and nothing fetched (no selenium-manager
download: the driver's path is given)."""

from __future__ import annotations

import os
import shutil
import tempfile
import time
from contextlib import contextmanager
from typing import Any

__all__ = ["CHROMIUM", "DRIVER", "FLAGS", "why_unavailable", "chromium", "open_page"]

CHROMIUM = shutil.which("chromium") or "/usr/bin/chromium"
DRIVER = shutil.which("chromedriver") or "/usr/bin/chromedriver"
FLAGS = ("--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--disable-dev-shm-usage", "--window-size=1400,1000")


def why_unavailable() -> str | None:
    """Why no browser can be driven here (None: it can)."""
    if not (os.path.exists(CHROMIUM) and os.path.exists(DRIVER)):
        return ("Debian's chromium and chromium-driver are not installed (`make test` installs them with apt-get "
                "where it can: apt-get install chromium chromium-driver)")
    from importlib.util import find_spec

    for mod, extra in (("selenium", "view-test"), ("starlette", "view"), ("uvicorn", "view")):
        if find_spec(mod) is None:
            return f"{mod} is not installed (pip install 'delkit[{extra}]')"
    return None


@contextmanager
def chromium(width: int = 1400, height: int = 1000) -> Any:
    """A selenium driver of headless Chromium (quit and its profile removed on exit)."""
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    profile = tempfile.mkdtemp(prefix="delkit-view-chromium-")
    opts = webdriver.ChromeOptions()
    opts.binary_location = CHROMIUM
    for f in FLAGS:
        opts.add_argument(f)
    opts.add_argument(f"--window-size={width},{height}")
    opts.add_argument(f"--user-data-dir={profile}")
    drv = webdriver.Chrome(service=Service(DRIVER), options=opts)
    drv.set_script_timeout(30)
    try:
        yield drv
    finally:
        drv.quit()
        shutil.rmtree(profile, ignore_errors=True)


def open_page(drv: Any, url: str, timeout: float = 20.0) -> float:
    """Load the viewer's page, wait until it has drawn its first frame; returns the page's own ready time (ms
    since navigation start, ``performance.now()``)."""
    drv.get(url)
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        t = drv.execute_script("return (window.delkitView && window.delkitView.ready) ? "
                               "window.delkitView.timings.ready : null")
        if t is not None:
            return float(t)
        time.sleep(0.01)
    raise AssertionError(f"the page did not become ready: {drv.find_element('tag name', 'body').text[:400]}")
