"""mobman.viz.screenshot: a served page rendered by headless chromium to a PNG of the requested size, once the
picture has settled; a clear error without chromium."""

from __future__ import annotations

import functools
import http.server
import threading

import numpy as np
import pytest
from PIL import Image

from mobman.errors import InputError
from mobman.viz import screenshot as shot

PAGE = """<!doctype html><html><body style="margin:0;background:#ffffff">
<canvas id="c" width="200" height="100"></canvas>
<script>
const ctx = document.getElementById("c").getContext("2d");
ctx.fillStyle = "rgb(255, 0, 0)"; ctx.fillRect(0, 0, 200, 100);
</script></body></html>"""


@pytest.fixture
def served(tmp_path):
    (tmp_path / "index.html").write_text(PAGE)
    handler = functools.partial(http.server.SimpleHTTPRequestHandler, directory=str(tmp_path))
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    yield f"http://127.0.0.1:{server.server_address[1]}/index.html"
    server.shutdown()


def test_screenshot_renders_the_page_at_the_requested_size(served, tmp_path):
    path = shot.screenshot(served, tmp_path / "out" / "page.png", width=320, height=240, timeout=30.0)
    image = np.asarray(Image.open(path).convert("RGB"))
    assert image.shape == (240, 320, 3)
    np.testing.assert_array_equal(image[50, 100], [255, 0, 0])  # inside the canvas
    np.testing.assert_array_equal(image[200, 300], [255, 255, 255])  # the page's background


def test_changed_is_the_fraction_of_differing_pixels(tmp_path):
    def png(array):
        path = tmp_path / "x.png"
        Image.fromarray(array.astype(np.uint8)).save(path)
        return path.read_bytes()

    a = np.zeros((10, 10, 3))
    b = a.copy()
    b[:2, :5] = 255  # 10 of 100 pixels
    b[5, 5] = 4  # below the threshold of 8 levels: unchanged
    assert shot._changed(png(a), png(a)) == 0.0
    assert shot._changed(png(a), png(b)) == pytest.approx(0.1)


def test_without_chromium_the_error_names_the_option_and_the_install_line(monkeypatch):
    monkeypatch.setattr(shot.shutil, "which", lambda name: None)
    with pytest.raises(InputError, match=r"--screenshot needs chromium.*apt-get install chromium"):
        shot.chromium()
