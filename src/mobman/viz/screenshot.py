"""A PNG of a served scene, rendered headless by Debian's chromium driven by Playwright (software WebGL)."""

from __future__ import annotations

import io
import shutil
import time
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from PIL import Image

from mobman.errors import InputError

if TYPE_CHECKING:
    from playwright.sync_api import Page

CHROMIUM_ARGS = ("--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader")
"""Headless chromium flags: no sandbox (containers, root), software WebGL (no GPU needed)."""
HIDE_NOTICES = "[class*='Notification'] { display: none !important; }"
"""The client's notices (such as its software-rendering warning) are left out of the picture."""


def chromium() -> str:
    """The path of the system's chromium (Debian: ``apt-get install chromium``)."""
    for name in ("chromium", "chromium-browser"):
        path = shutil.which(name)
        if path:
            return path
    raise InputError("--screenshot needs chromium on the PATH (Debian: apt-get install chromium)")


def screenshot(
    url: str, path: Path | str, width: int = 1280, height: int = 800, timeout: float = 60.0
) -> Path:
    """Open ``url`` in headless chromium, wait until the picture stops changing, and write it to ``path``."""
    from playwright.sync_api import sync_playwright

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    with sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=chromium(), args=list(CHROMIUM_ARGS))
        try:
            page = browser.new_page(viewport={"width": width, "height": height})
            page.goto(url, timeout=timeout * 1000)
            page.add_style_tag(content=HIDE_NOTICES)
            page.wait_for_selector("canvas", timeout=timeout * 1000)
            shot = _settled(page, timeout)
        finally:
            browser.close()
    path.write_bytes(shot)
    return path


def _settled(page: Page, timeout: float) -> bytes:
    """A screenshot that differs from the one taken half a second before in under 0.1 % of its pixels (the
    scene has arrived and been drawn; the renderer's last refinements may still touch a few pixels)."""
    deadline = time.monotonic() + timeout
    time.sleep(1.0)
    previous = page.screenshot()
    while True:
        time.sleep(0.5)
        shot = page.screenshot()
        if _changed(previous, shot) < 1e-3 or time.monotonic() > deadline:
            return shot
        previous = shot


def _changed(a: bytes, b: bytes) -> float:
    """Fraction of pixels that differ between two PNG images of the same size."""
    first, second = (np.asarray(Image.open(io.BytesIO(x)).convert("RGB"), dtype=np.int16) for x in (a, b))
    return float(np.mean(np.any(np.abs(first - second) > 8, axis=-1)))
