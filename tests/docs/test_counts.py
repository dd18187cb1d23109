"""The counts the README and the docs pages state about the committed experiment, and their
Table 1, are what its rows give (tools/doc_counts.py recounts them): a rerun of the experiment
cannot leave the prose stale."""

import importlib.util

import pytest

from gbh_drake import REPO_ROOT

spec = importlib.util.spec_from_file_location("doc_counts", REPO_ROOT / "tools" / "doc_counts.py")
doc_counts = importlib.util.module_from_spec(spec)
spec.loader.exec_module(doc_counts)


@pytest.fixture(scope="module")
def rows():
    return doc_counts.read_rows()


def _marked_pages() -> list:
    return [p for p in doc_counts.pages()
            if doc_counts.stated(p.read_text()) or doc_counts.TABLE_START in p.read_text()]


def test_the_experiment_pages_mark_their_counts():
    marked = {p.relative_to(REPO_ROOT).as_posix(): p.read_text() for p in _marked_pages()}
    assert {"README.md", "docs/experiment/README.md"} <= set(marked)
    for name in ("README.md", "docs/experiment/README.md"):
        assert doc_counts.TABLE_START in marked[name] and doc_counts.TABLE_END in marked[name]
    assert len(doc_counts.stated(marked["docs/experiment/README.md"])) >= 40


@pytest.mark.parametrize("page", _marked_pages(), ids=lambda p: p.relative_to(REPO_ROOT).as_posix())
def test_stated_counts_are_the_rows(page, rows):
    text = page.read_text()
    for name, value in doc_counts.stated(text):
        assert name in doc_counts.COUNTS, f"{page.name}: unknown count {name!r}"
        assert value == doc_counts.COUNTS[name](rows), (
            f"{page}: {name} says {value!r}, the rows {doc_counts.COUNTS[name](rows)!r}; "
            "run tools/doc_counts.py --write and reread the sentence")
    assert doc_counts.recount(text, rows) == text, \
        f"{page}: Table 1 differs from the rows; run tools/doc_counts.py --write"


def test_counts_follow_the_rows(rows):
    """A changed row changes what the pages must say: the check can fail."""
    text = (REPO_ROOT / "docs" / "experiment" / "README.md").read_text()
    fewer = rows[~((rows["method"] == "gbh+") & (rows["object"] == "key_ring")
                   & (rows["protocol"] == "natural") & (rows["trial"] == 1))]
    assert int(doc_counts.COUNTS["retried_carried"](fewer)) == \
        int(doc_counts.COUNTS["retried_carried"](rows)) - 1  # a carried retry
    assert doc_counts.recount(text, fewer) != text
    plus = "| GbH, scoop, regrasp, fallback, one retry (`gbh+`) |"
    assert doc_counts.table1(fewer).split(plus)[-1] != doc_counts.table1(rows).split(plus)[-1]

