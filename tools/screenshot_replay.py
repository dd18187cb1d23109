"""Opens a Meshcat replay (replay.html) in headless Chromium and saves a PNG screenshot.

Usage: python tools/screenshot_replay.py output/default/replay.html docs/replay_default.png
Needs Debian's chromium (apt-get install chromium); used for the README picture, not by tests.
"""

import subprocess
import sys
import tempfile
from pathlib import Path


def screenshot(html: Path, png: Path, size=(1280, 800), wait_ms: int = 25000) -> None:
    with tempfile.TemporaryDirectory() as profile:
        subprocess.run(
            ["chromium", "--headless", "--no-sandbox", "--disable-gpu", "--use-gl=swiftshader",
             "--enable-unsafe-swiftshader", "--disable-quic", "--no-first-run",
             "--disable-background-networking", "--disable-component-update", "--disable-sync",
             f"--user-data-dir={profile}", f"--window-size={size[0]},{size[1]}",
             f"--timeout={wait_ms}", f"--screenshot={png.resolve()}",
             html.resolve().as_uri()],
            check=True, timeout=120, capture_output=True,
        )


if __name__ == "__main__":
    screenshot(Path(sys.argv[1]), Path(sys.argv[2]))
    print(f"wrote {sys.argv[2]}")
