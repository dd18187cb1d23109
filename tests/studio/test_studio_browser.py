"""The studio's page in a real browser: Debian's Chromium, headless, driven by Playwright (its
own browser is not downloaded: the system's is used; ``./dev.sh`` installs it where missing)."""

from __future__ import annotations

import shutil
import time

import numpy as np
import pytest

from gbh_drake.scenario import Scenario
from gbh_drake.scenario.loader import apply_overrides
from gbh_drake.studio.choices import object_choices
from gbh_drake.studio.controls import BUTTONS, RANK, Studio
from gbh_drake.studio.session import Session
from gbh_drake.viz.meshcat_server import local_meshcat

#: Chromium's switches for a headless machine without a GPU (WebGL in software).
CHROMIUM_ARGS = ["--no-sandbox", "--disable-gpu", "--use-gl=swiftshader",
                 "--enable-unsafe-swiftshader", "--disable-background-networking",
                 "--disable-component-update", "--no-first-run"]


def step_until(studio: Studio, what: str, seconds: float = 60.0) -> None:
    """Runs the studio's loop until it has done ``what`` (a button's or slider's name)."""
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        if what in studio.step():
            return
        time.sleep(0.05)
    raise AssertionError(f"the studio did not see {what!r} within {seconds} s")


@pytest.mark.sim
def test_the_page_shows_the_controls_and_detect_pressed_in_the_browser_draws_the_grasps(
        tmp_path):
    chromium = shutil.which("chromium")
    if chromium is None:
        pytest.skip("no chromium on PATH (./dev.sh setup installs Debian's)")
    sync_playwright = pytest.importorskip("playwright.sync_api").sync_playwright
    from PIL import Image

    meshcat = local_meshcat()
    base = apply_overrides(Scenario(), "{scan: {num_views: 4}}")
    studio = Studio(Session(base, object_choices(base), meshcat=meshcat), meshcat)
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=chromium, args=CHROMIUM_ARGS)
        try:
            page = browser.new_page(viewport={"width": 1280, "height": 800})
            page.goto(meshcat.web_url())
            for name in BUTTONS:  # the panel's controls, as the user sees them
                page.get_by_text(name, exact=True).wait_for(timeout=30000)
            page.get_by_text("views", exact=True).wait_for()
            page.get_by_text("Detect", exact=True).click()
            step_until(studio, "Detect")
            page.get_by_text(RANK, exact=True).wait_for(timeout=30000)  # the rank slider came
            page.get_by_text("detect:", exact=False).first.wait_for()  # and the panel's text
            assert meshcat.GetNumActiveConnections() == 1
            page.wait_for_timeout(1500)  # let WebGL draw the new objects
            png = tmp_path / "studio.png"
            page.screenshot(path=str(png))
        finally:
            browser.close()
    assert studio.session.detection is not None and studio.session.detection.offered
    image = np.asarray(Image.open(png).convert("RGB"), dtype=float)
    assert image.shape == (800, 1280, 3)
    assert image[:, :900].std() > 10.0, "the 3-D view is blank"
