"""The wheel works on its own: built from this tree, installed into a fresh venv (no checkout on
``sys.path``, no ``PYTHONPATH``, run from a folder of its own), ``gbh run`` without a file runs
the packaged default scenario, a packaged scenario's relative mesh path resolves, and a diagram of
one's own builds with ``gbh_drake.systems``.

Offline: the wheel is built with ``--no-build-isolation`` (the dev venv's setuptools) from a copy
of the tree (an in-place build would write ``build/`` into a checkout others share), and the fresh
venv reaches the dev venv's already-installed dependencies through a ``.pth`` line (which does not
run the dev venv's own ``.pth`` files, so its editable gbh_drake stays out). The same ``.pth`` makes
``import ray`` fail: a trial must not need the optional ``[ray]`` extra. About 20 s on 2 cores.
"""

import os
import shutil
import subprocess
import sys
import sysconfig
import textwrap
import zipfile
from pathlib import Path
from types import SimpleNamespace

import pytest

from gbh_drake import MODELS_DIR, REPO_ROOT, SCENARIOS_DIR

pytestmark = pytest.mark.sim

#: What the build reads (besides these, only tests, docs and tools are in the repository).
SOURCES = ("pyproject.toml", "setup.py", "README.md", "LICENSE", "gbh_drake", "models", "scenarios")
IGNORED = shutil.ignore_patterns("__pycache__", "*.pyc", "*.egg-info", "build", "objects")


def _run(command, *, cwd, timeout=300, check=True):
    """``command`` in ``cwd`` with this environment minus PYTHONPATH and the active venv."""
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV")}
    env["PIP_NO_INDEX"] = "1"  # never download: everything is local
    result = subprocess.run([str(c) for c in command], cwd=cwd, env=env, capture_output=True,
                            text=True, timeout=timeout)
    if check:
        assert result.returncode == 0, f"{command}:\n{result.stdout}\n{result.stderr}"
    return result


@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    """The wheel built from this tree, installed with ``--no-deps`` into a fresh venv; ``cwd``
    is an empty folder outside the repository."""
    root = tmp_path_factory.mktemp("wheel")
    src = root / "src"
    src.mkdir()
    for name in SOURCES:
        source = REPO_ROOT / name
        if source.is_dir():
            # models/objects/ (generated, gitignored) is not shipped; gbh_drake/objects/ is code
            ignore = IGNORED if name == "models" else shutil.ignore_patterns(
                "__pycache__", "*.pyc", "*.egg-info")
            shutil.copytree(source, src / name, ignore=ignore)
        else:
            shutil.copy2(source, src / name)
    _run([sys.executable, "-m", "pip", "wheel", "-q", "--no-deps", "--no-build-isolation",
          "-w", root / "dist", "."], cwd=src)
    (wheel,) = (root / "dist").glob("gbh_drake-*.whl")

    venv = root / "venv"
    _run([sys.executable, "-m", "venv", "--without-pip", venv], cwd=root)
    python = venv / "bin" / "python"
    site = Path(_run([python, "-c", "import sysconfig; print(sysconfig.get_path('purelib'))"],
                     cwd=root).stdout.strip())
    dev_site = {sysconfig.get_path("purelib"), sysconfig.get_path("platlib")}
    (site / "_gbh_dev_dependencies.pth").write_text(
        "\n".join(sorted(dev_site)) + "\nimport sys; sys.modules['ray'] = None\n")
    _run([sys.executable, "-m", "pip", "--python", python, "install", "-q", "--no-deps",
          "--no-index", wheel], cwd=root)
    cwd = root / "elsewhere"
    cwd.mkdir()
    return SimpleNamespace(wheel=wheel, venv=venv, python=python, gbh=venv / "bin" / "gbh",
                           package=site / "gbh_drake", cwd=cwd)


def test_the_wheel_ships_the_models_and_scenarios(installed):
    names = set(zipfile.ZipFile(installed.wheel).namelist())
    for folder, shipped in ((MODELS_DIR, "gbh_drake/models"), (SCENARIOS_DIR, "gbh_drake/scenarios")):
        files = [p for p in folder.rglob("*") if p.is_file() and "objects" not in p.parts
                 and "__pycache__" not in p.parts]
        assert files
        for path in files:
            assert f"{shipped}/{path.relative_to(folder).as_posix()}" in names
    assert not any(n.startswith("gbh_drake/models/objects/") for n in names)
    packages = {p.parent.relative_to(REPO_ROOT).as_posix()
                for p in (REPO_ROOT / "gbh_drake").rglob("__init__.py")}
    assert packages <= {Path(n).parent.as_posix() for n in names}


def test_the_fresh_venv_imports_the_installed_wheel(installed):
    out = _run([installed.python, "-c", textwrap.dedent("""\
        import gbh_drake
        from gbh_drake.experiment.config import load_experiment
        print(gbh_drake.__file__)
        print(gbh_drake.MODELS_DIR)
        print(gbh_drake.SCENARIOS_DIR)
        print(gbh_drake.IN_CHECKOUT)
        print(load_experiment(gbh_drake.SCENARIOS_DIR / "experiment_small.yaml").base_path)
        try:
            import ray
        except ImportError:
            print("no ray")
        """)], cwd=installed.cwd).stdout.splitlines()
    assert out == [str(installed.package / "__init__.py"), str(installed.package / "models"),
                   str(installed.package / "scenarios"), "False",
                   str(installed.package / "scenarios" / "default.yaml"), "no ray"]


def test_gbh_run_without_a_file_runs_the_packaged_default(installed):
    result = _run([installed.gbh, "run", "--set", "max_time: 1.0"], cwd=installed.cwd)
    out = result.stdout
    assert f"scenario {installed.package / 'scenarios' / 'default.yaml'}\n" in out, out
    assert "object mug_classic" in out and "simulated 1.00 s" in out and "scan: " in out, out
    folder = installed.cwd / "output" / "default"
    assert f"replay: {folder / 'replay.html'}" in out, out
    for name in ("replay.html", "summary.yaml", "scenario.yaml"):
        assert (folder / name).is_file()


def test_a_relative_output_dir_given_by_set_is_under_the_current_folder(installed):
    """Not in the packaged scenarios folder (site-packages), where the file is."""
    out = _run([installed.gbh, "run", "--set", "output_dir: out/settle",
                "--set", "task: settle\nsettle_time: 0.05"], cwd=installed.cwd).stdout
    assert f"replay: {installed.cwd / 'out' / 'settle' / 'replay.html'}" in out, out
    assert (installed.cwd / "out" / "settle" / "summary.yaml").is_file()
    assert not (installed.package / "scenarios" / "out").exists()


def test_a_packaged_scenario_finds_its_mesh_beside_it(installed):
    scenario = installed.package / "scenarios" / "mesh_file.yaml"  # mesh: meshes/staple.obj
    out = _run([installed.gbh, "run", scenario, "--set", "task: settle\nsettle_time: 0.05"],
               cwd=installed.cwd).stdout
    assert "staple" in out and (installed.cwd / "output" / "mesh_file" / "summary.yaml").is_file()


def test_ray_engine_without_ray_is_one_line(installed):
    result = _run([installed.gbh, "experiment", installed.package / "scenarios" / "experiment_small.yaml",
                   "--ray", "local"], cwd=installed.cwd, check=False)
    assert result.returncode == 2, result.stderr
    assert result.stderr.count("\n") == 1 and "--ray needs Ray" in result.stderr, result.stderr


def test_a_diagram_of_ones_own_builds(installed):
    script = installed.cwd / "own_diagram.py"
    script.write_text(textwrap.dedent("""\
        from pydrake.systems.framework import DiagramBuilder

        import gbh_drake
        from gbh_drake.scenario import Scenario
        from gbh_drake.station import make_station
        from gbh_drake.systems import Scanner, build_checked

        scenario = Scenario()
        builder = DiagramBuilder()
        station = builder.AddSystem(make_station(scenario))
        scanner = builder.AddSystem(Scanner(scenario.scan, scenario.scan_target, scan_time=0.3))
        builder.Connect(station.GetOutputPort("camera_query_object"),
                        scanner.GetInputPort("query_object"))
        diagram = build_checked(builder)
        print(gbh_drake.__file__)
        print(sorted(s.get_name() for s in diagram.GetSystems()))
        """))
    out = _run([installed.python, script], cwd=installed.cwd).stdout.splitlines()
    assert out[0] == str(installed.package / "__init__.py")
    assert "station" in out[1] and "scanner" in out[1], out
