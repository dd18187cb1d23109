"""The experiment's shared runs: ``gbh experiment`` in this process, and the short experiment on
2 local workers (the rows other engines must give again)."""

from pathlib import Path

import pytest

from gbh_drake.cli import main
from gbh_drake.experiment.rows import RowStore, row_key

SHORT = Path(__file__).parent / "short_experiment.yaml"


def _experiment_rows(experiment: Path, folder: Path, *options: str):
    """``gbh experiment <experiment> --out <folder> --no-progress <options>`` in this process:
    (folder, its rows by key, its rows in file order)."""
    assert main(["experiment", str(experiment), "--out", str(folder), "--no-progress",
                 *options]) == 0
    rows = RowStore(folder).load()
    return folder, {row_key(r): r for r in rows}, rows


@pytest.fixture(scope="session")
def experiment_rows():
    """``experiment_rows(experiment_file, folder, *options)``: runs ``gbh experiment`` here and
    gives (folder, its rows by key, its rows in file order)."""
    return _experiment_rows


@pytest.fixture(scope="module")
def first_run(tmp_path_factory):
    """The short experiment on 2 local workers: (folder, its rows by key, its rows)."""
    return _experiment_rows(SHORT, tmp_path_factory.mktemp("experiment") / "short",
                            "--workers", "2")


@pytest.fixture
def mug_experiment(tmp_path) -> Path:
    """An experiment file of one trial: the default scenario's mug, seed 0 (for the tools)."""
    path = tmp_path / "exp.yaml"
    path.write_text("name: t\nbase: %s\nobjects: [mug_classic]\ntrials: 1\nseed: 0\n"
                    % (Path(__file__).parents[2] / "scenarios" / "default.yaml"))
    return path
