"""The studio's page in a real browser: Debian's Chromium, headless, driven by Playwright
(tools/screenshot_studio.py: the system's browser, none downloaded; ``./dev.sh`` installs it
where missing): the controls are there, Detect pressed in the page detects, the picture is not
blank."""

from __future__ import annotations

import importlib.util
import shutil

import numpy as np
import pytest

from gbh_drake import REPO_ROOT

spec = importlib.util.spec_from_file_location("screenshot_studio",
                                              REPO_ROOT / "tools" / "screenshot_studio.py")
screenshot_studio = importlib.util.module_from_spec(spec)
spec.loader.exec_module(screenshot_studio)


@pytest.mark.sim
def test_detect_pressed_in_the_browser_detects_and_the_page_shows_it(tmp_path):
    if shutil.which("chromium") is None:
        pytest.skip("no chromium on PATH (./dev.sh setup installs Debian's)")
    pytest.importorskip("playwright.sync_api")
    from PIL import Image

    png = tmp_path / "studio.png"
    studio, connections = screenshot_studio.screenshot(png, views=4)
    assert connections == 1  # the browser's page was connected
    detection = studio.session.detection
    assert detection is not None and detection.result.structures and detection.offered
    assert any(line.startswith("detect:") for line in studio.text.lines)
    image = np.asarray(Image.open(png).convert("RGB"), dtype=float)
    assert image.shape == (*reversed(screenshot_studio.SIZE), 3)
    assert image[:, :900].std() > 10.0, "the 3-D view is blank"
