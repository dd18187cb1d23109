"""Ray is an optional extra (``pip install 'gbh_drake[ray]'``): only ``gbh experiment --ray``
imports it, and without it that asks for the extra in one line (exit 2) before anything runs."""

import subprocess
import sys

import pytest

from gbh_drake import SCENARIOS_DIR
from gbh_drake.cli import main
from gbh_drake.experiment import engines


@pytest.fixture
def no_ray(monkeypatch):
    """``import ray`` fails as if Ray were not installed."""
    monkeypatch.setitem(sys.modules, "ray", None)


@pytest.mark.parametrize("address", ["local", "auto"])
def test_ray_engine_without_ray_is_one_line_naming_the_setting(no_ray, address, tmp_path, capsys):
    code = main(["experiment", str(SCENARIOS_DIR / "experiment_small.yaml"), "--ray", address,
                 "--out", str(tmp_path / "out"), "--no-progress"])
    err = capsys.readouterr().err
    assert code == 2
    assert err.count("\n") == 1 and err.startswith("gbh: --ray needs Ray"), err
    assert "pip install 'gbh_drake[ray]'" in err and "Traceback" not in err
    assert not (tmp_path / "out").exists()  # nothing ran


def test_init_ray_without_ray_raises_ray_missing(no_ray):
    assert not engines.ray_installed()
    with pytest.raises(engines.RayMissing, match=r"--ray needs Ray"):
        engines.init_ray("local")


def test_ray_is_found_when_installed():
    assert engines.ray_installed()  # the dev environment installs the extra


def test_a_trial_and_the_local_engine_do_not_import_ray():
    code = ("import sys\n"
            "import gbh_drake.cli, gbh_drake.run, gbh_drake.trial\n"
            "import gbh_drake.experiment.runner, gbh_drake.experiment.worker\n"
            "print(sorted(m for m in sys.modules if m == 'ray' or m.startswith('ray.')))\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120,
                         check=True).stdout
    assert out.strip() == "[]"
