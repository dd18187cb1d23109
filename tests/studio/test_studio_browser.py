"""The studio's page in a real browser: Debian's Chromium, headless, driven by Playwright
(tools/screenshot_studio.py: the system's browser, none downloaded; ``./dev.sh`` installs it
where missing): the controls are there, Detect pressed in the page detects, the picture is not
blank; ``gbh studio`` itself, run as a user runs it, through its page."""

from __future__ import annotations

import importlib.util
import queue
import shutil
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

from gbh_drake import REPO_ROOT
from gbh_drake.studio.controls import RANK

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


def _panel(page) -> list[str]:
    """The studio's lines of text in the page's control panel, and its controls' names."""
    return page.evaluate("""() => Array.from(document.querySelectorAll('.dg.main > ul > li'))
        .map(li => li.innerText.split('\\n')[0].trim())""")


def _wait(page, what, seconds: float = 120.0) -> list[str]:
    """Polls the page's panel until ``what(lines)``; returns the lines."""
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        lines = _panel(page)
        if what(lines):
            return lines
        page.wait_for_timeout(200)
    raise AssertionError(f"the page never showed what was awaited: {_panel(page)}")


def _click(page, name: str) -> None:
    button = page.get_by_text(name, exact=True)
    button.evaluate("e => e.scrollIntoView({block: 'center'})")
    button.click()


@pytest.mark.sim
@pytest.mark.trial
def test_gbh_studio_in_the_browser_scan_keeps_detect_and_reset_stops_execute():
    """``gbh studio`` as a user runs it, its page in Chromium: the scenario's seed and pose
    are placed as given (the sliders neither clamp nor round them); Scan after Detect keeps the
    detection and the rank slider; Reset pressed during Execute stops the pick, said as
    stopped on the terminal, not as a verdict."""
    if shutil.which("chromium") is None:
        pytest.skip("no chromium on PATH (./dev.sh setup installs Debian's)")
    pytest.importorskip("playwright.sync_api")
    from playwright.sync_api import sync_playwright

    from tests.studio.test_studio import OFF_GRID

    process = subprocess.Popen(
        [sys.executable, "-m", "gbh_drake.cli", "studio",
         str(REPO_ROOT / "scenarios" / "default.yaml"), "--set", OFF_GRID,
         # A quarter of real time: the pick (about 14 s simulated) lasts a minute, so that Reset
         # lands during it although the software-rendered page answers seconds late.
         "--set", "{simulator_config: {target_realtime_rate: 0.25}}"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    said: queue.Queue[str] = queue.Queue()
    threading.Thread(target=lambda: [said.put(line) for line in process.stdout],
                     daemon=True).start()

    def next_line(seconds: float = 120.0) -> str:
        return said.get(timeout=seconds)

    try:
        url = next_line().split()[2]
        placed = next_line()
        assert "seed: 1234" in placed and "num_views: 2" in placed, placed
        assert "translation: [0.5523, 0.0117, 0.0], rotation: !Rpy {deg: [0.0, 0.0, 32.5]}" \
            in placed, placed
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=shutil.which("chromium"),
                                        args=screenshot_studio.CHROMIUM_ARGS)
            try:
                page = browser.new_page(viewport={"width": 1280, "height": 800})
                page.goto(url)
                page.get_by_text("Open Controls", exact=True).click()
                _click(page, "Detect")
                _wait(page, lambda lines: RANK in lines and
                      any(line.startswith("· planner") for line in lines))
                _click(page, "Scan")
                _click(page, "Free space")  # said once Scan is done
                lines = _wait(page, lambda lines: any(line.startswith("· free space:")
                                                      for line in lines))
                assert RANK in lines and any(line.startswith("· detect:") for line in lines)
                assert said.empty(), "nothing placed anew: the page moved no slider"

                # Reset clicked once the pick runs: while it is drawn live, the page (software
                # WebGL) answers Playwright's queries seconds late; the pick, at a quarter of real
                # time, lasts a minute.
                _click(page, "Execute")
                _wait(page, lambda lines: "· executing grasp 1..." in lines, 30)
                page.get_by_text("Reset", exact=True).click(timeout=45_000)
                stopped = next_line(60)
                assert stopped.startswith("stopped by Reset after ") and \
                    "s simulated: " in stopped, stopped
                # The controls are rebuilt after Reset: wait for the page's last state (a
                # query between the rebuild's steps saw neither the pick nor the rank slider).
                lines = _wait(page, lambda lines: not any(
                    line.startswith(("· executing", "· stopped")) for line in lines)
                    and RANK in lines and any(line.startswith("· detect:") for line in lines))
                assert RANK in lines and any(line.startswith("· detect:") for line in lines)
            finally:
                browser.close()
        process.send_signal(signal.SIGTERM)
        assert process.wait(timeout=60) == 0
    finally:
        process.kill()
