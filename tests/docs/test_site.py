"""The documentation site builds in strict mode (MkDocs, the Material theme, mkdocstrings):
a broken link, a missing anchor, a page left out of the nav or an API reference that does not
resolve fails the build, and so this test (CI runs it with the suite)."""

import os
import subprocess
import sys
from pathlib import Path

from gbh_drake import REPO_ROOT

CONFIG = REPO_ROOT / "mkdocs.yml"


def mkdocs_build(config: Path, site: Path) -> subprocess.CompletedProcess:
    """``mkdocs build --strict`` of ``config`` into ``site``, with this interpreter's mkdocs."""
    return subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "--config-file", str(config),
         "--site-dir", str(site)],
        cwd=REPO_ROOT, capture_output=True, text=True, check=False,
        env={**os.environ, "NO_MKDOCS_2_WARNING": "1"})


def test_the_site_builds_strictly(tmp_path):
    done = mkdocs_build(CONFIG, tmp_path / "site")
    assert done.returncode == 0, done.stderr[-3000:]
    home = (tmp_path / "site" / "index.html").read_text()
    assert "Two commands" in home and 'href="getting_started/"' in home  # the README, links made relative
    reference = (tmp_path / "site" / "scenario_fields" / "index.html").read_text()
    assert "gbh_drake.scenario.schema.Scenario" in reference and "RandomRestingPose" in reference
    errors = (tmp_path / "site" / "errors" / "index.html").read_text()
    assert "plant_config.time_step" in errors  # the generated limits table
    speed = (tmp_path / "site" / "speed" / "index.html").read_text()
    assert 'href="../#figures"' in speed  # ../README.md#figures on GitHub, the home page here
    api = (tmp_path / "site" / "api" / "systems" / "index.html").read_text()
    assert "HangabilityDetector" in api and ":class:" not in api


def test_a_broken_link_fails_the_build(tmp_path):
    """The same configuration over a page with a link to nothing: strict mode refuses it."""
    docs = tmp_path / "docs"
    docs.mkdir()
    (docs / "page.md").write_text("# A page\n\n[nowhere](missing.md)\n")
    config = tmp_path / "mkdocs.yml"
    config.write_text(f"INHERIT: {CONFIG}\ndocs_dir: {docs}\n"
                      f"hooks: [{REPO_ROOT / 'tools' / 'mkdocs_hooks.py'}]\nwatch: []\n"
                      "nav:\n  - Home: index.md\n  - Page: page.md\n")
    (tmp_path / "README.md").write_text("# Home\n")
    done = mkdocs_build(config, tmp_path / "site")
    assert done.returncode != 0
    assert "missing.md" in done.stderr
