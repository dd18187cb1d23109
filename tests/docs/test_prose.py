"""The README and the docs pages describe the project as it is: no commit hashes, no words of
the issue tracker, no machine paths (history lives in docs/changelog.md, without hashes too);
the README stays an entry (at most 250 lines) whose two commands exist."""

import re

import pytest

from gbh_drake import REPO_ROOT

#: Pages kept as they were written: the experiment's archive (earlier runs, and the comparisons
#: of the rows before and after each change, which name the code versions they ran at) and the
#: summaries `gbh report` generates from rows.
ARCHIVE = ("docs/experiment/changes_*.md", "docs/experiment/exit_proof/*.md",
           "docs/experiment/unknown_occupied/*.md", "docs/experiment/reach_stable.md",
           "docs/experiment/**/summary.md", "docs/experiment/summary.md")

#: A commit hash: 7 to 40 hexadecimal digits with at least one letter and one digit.
HASH = re.compile(r"\b(?=[0-9a-f]*[a-f])(?=[0-9a-f]*[0-9])[0-9a-f]{7,40}\b")
#: The issue tracker's words.
ISSUE = re.compile(r"\bissues? \d+|\bfloors? (?:met|missed)|\btargets? (?:met|missed)|"
                   r"\b(?:floor|target) \d+|issue's", re.IGNORECASE)
#: A path of the machine the docs were written on.
MACHINE = re.compile(r"/work/|/home/\w+")


def _pages() -> list:
    archived = {p for pattern in ARCHIVE for p in REPO_ROOT.glob(pattern)}
    return [REPO_ROOT / "README.md",
            *sorted(p for p in (REPO_ROOT / "docs").rglob("*.md") if p not in archived)]


@pytest.mark.parametrize("page", _pages(), ids=lambda p: p.relative_to(REPO_ROOT).as_posix())
def test_pages_say_what_is(page):
    text = page.read_text()
    for pattern, what in ((HASH, "a commit hash"), (ISSUE, "issue talk"),
                          (MACHINE, "a path of the build machine")):
        found = [m.group(0) for m in pattern.finditer(text)]
        assert not found, f"{page.relative_to(REPO_ROOT)}: {what}: {found[:5]}"


def test_the_checks_find_what_they_look_for():
    assert HASH.search("fixed in `c03aa70`") and not HASH.search("a 1e-19 score, 2026-12-03")
    assert ISSUE.search("issue 23's target") and ISSUE.search("the floors met hold")
    assert not ISSUE.search("a bucket's floor a millimetre up")


def test_the_readme_is_an_entry():
    text = (REPO_ROOT / "README.md").read_text()
    assert len(text.splitlines()) <= 250
    dev = (REPO_ROOT / "dev.sh").read_text()
    for command in ("run", "test", "docs"):
        assert f"./dev.sh {command}" in text
        assert re.search(rf"^\s+{command}\)", dev, re.MULTILINE), f"dev.sh has no {command} case"
