"""tools/scan_vs_truth.py: a real scan compared with its true object."""

import importlib.util
import json
from pathlib import Path

import pytest

SCAN_TOOL = Path(__file__).parents[2] / "tools" / "scan_vs_truth.py"
spec = importlib.util.spec_from_file_location("scan_vs_truth", SCAN_TOOL)
scan_vs_truth = importlib.util.module_from_spec(spec)
spec.loader.exec_module(scan_vs_truth)


@pytest.mark.sim
def test_a_scan_compared_with_its_object(tmp_path, monkeypatch, capsys, mug_experiment):
    """tools/scan_vs_truth.py on the default mug (10 views): the scan's top is the mug's and
    nearly all of it lies on the mug; a row per trial."""
    monkeypatch.setattr("sys.argv", [
        "scan_vs_truth", "--experiment", str(mug_experiment), "--max-time", "0.8",
        "--out", str(tmp_path / "rows.jsonl")])
    scan_vs_truth.main()
    (row,) = [json.loads(line) for line in (tmp_path / "rows.jsonl").read_text().splitlines()]
    assert row["scanned"], row["message"]
    assert abs(row["scan_top"] - row["true_top"]) < 0.003
    assert row["off_share"] < 0.1  # (the cap over the cup's opening is off the true surface)
    assert "0 with the scan's top more than 5 mm above" in capsys.readouterr().out
