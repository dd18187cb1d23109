"""Opens the studio's page (``gbh studio``) in headless Chromium, presses Detect there and saves
a PNG screenshot: the picture of docs/studio.md, and what tests/studio/test_studio_browser.py
checks. Debian's ``chromium`` (``./dev.sh setup`` installs it), driven by Playwright (its own
browser is not downloaded).

Usage: python tools/screenshot_studio.py [docs/studio.png] [--views 4]
"""

from __future__ import annotations

import argparse
import shutil
import time
from pathlib import Path

#: Chromium's switches for a headless machine without a GPU (WebGL in software).
CHROMIUM_ARGS = ["--no-sandbox", "--disable-gpu", "--use-gl=swiftshader",
                 "--enable-unsafe-swiftshader", "--disable-background-networking",
                 "--disable-component-update", "--no-first-run"]
#: The page's size (px).
SIZE = (1280, 800)


def step_until(studio, what: str, seconds: float = 120.0) -> None:
    """Runs the studio's loop until it has done ``what`` (a button's or slider's name)."""
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        if what in studio.step():
            return
        time.sleep(0.05)
    raise TimeoutError(f"the studio did not see {what!r} within {seconds} s")


def screenshot(png: Path, views: int = 4, chromium: str | None = None):
    """Serves the studio of the default scenario (``views`` views) in a fresh Meshcat, opens
    it in Chromium, waits for its controls, clicks Detect, waits for the rank slider and the
    detection's text, saves ``png``; returns the :class:`~gbh_drake.studio.controls.Studio`
    and how many pages were connected to its Meshcat meanwhile."""
    from playwright.sync_api import sync_playwright

    from gbh_drake.scenario import Scenario
    from gbh_drake.scenario.loader import apply_overrides
    from gbh_drake.studio.choices import object_choices
    from gbh_drake.studio.controls import BUTTONS, RANK, Studio
    from gbh_drake.studio.session import Session
    from gbh_drake.viz.meshcat_server import local_meshcat

    chromium = chromium or shutil.which("chromium")
    if chromium is None:
        raise FileNotFoundError("no chromium on PATH (./dev.sh setup installs Debian's)")
    meshcat = local_meshcat()
    base = apply_overrides(Scenario(), f"{{scan: {{num_views: {int(views)}}}}}")
    studio = Studio(Session(base, object_choices(base), meshcat=meshcat), meshcat,
                    say=lambda _: None)
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=chromium, args=CHROMIUM_ARGS)
        try:
            page = browser.new_page(viewport={"width": SIZE[0], "height": SIZE[1]})
            page.goto(meshcat.web_url())
            opener = page.get_by_text("Open Controls", exact=True)  # a closed panel: open it
            opener.wait_for(timeout=30000)
            opener.click()
            for name in (*BUTTONS, "views"):  # the panel's controls, as the user sees them
                page.get_by_text(name, exact=True).wait_for(timeout=30000)
            detect = page.get_by_text("Detect", exact=True)
            # The panel scrolls (Meshcat's scene tree is above the controls): the button to
            # the middle, clear of the panel's "Close Controls" bar, then a mouse click.
            detect.evaluate("e => e.scrollIntoView({block: 'center'})")
            detect.click()
            step_until(studio, "Detect")
            page.get_by_text(RANK, exact=True).wait_for(timeout=30000)  # the rank slider came
            page.get_by_text("detect:").first.wait_for(timeout=30000)  # and the panel's text
            connections = meshcat.GetNumActiveConnections()
            page.wait_for_timeout(2000)  # WebGL draws what came
            page.screenshot(path=str(png))
        finally:
            browser.close()
    return studio, connections


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("png", nargs="?", default="docs/studio.png")
    parser.add_argument("--views", type=int, default=4)
    args = parser.parse_args()
    screenshot(Path(args.png), args.views)
    print(f"wrote {args.png}")
