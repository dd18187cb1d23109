"""An experiment on a user's object set resumes only the rows of the version of each entry they
ran (its mesh file's bytes, scale, mass, density, rest, control, hangable parts), refuses an
object it cannot simulate before any trial runs, and its report names the manifest. No trial
runs here: the rows are the worker's base rows of the tasks, as if every trial had finished."""

import hashlib
import json

import pytest
import trimesh

from gbh_drake import SCENARIOS_DIR
from gbh_drake.cli import main
from gbh_drake.experiment.config import ExperimentError, load_experiment, make_tasks
from gbh_drake.experiment.reuse import reuse_rows
from gbh_drake.experiment.rows import RowStore
from gbh_drake.experiment.worker import _base_row

SET = ("objects:\n"
       "  - name: block\n"
       "    mesh: block_cm.obj\n"
       "    scale: 0.01\n"
       "    mass: 0.25\n"
       "    rest: {as_given: true, reason: on its base}\n"
       "    tags: [box]\n"
       "  - {builtin: teapot}\n")


@pytest.fixture
def user_set(tmp_path):
    """A block (a file in centimetres) and the built-in teapot; an experiment of one trial
    each, natural protocol."""
    trimesh.creation.box((6.0, 8.0, 10.0)).export(tmp_path / "block_cm.obj")
    (tmp_path / "set.yaml").write_text(SET)
    (tmp_path / "exp.yaml").write_text(
        f"base: {SCENARIOS_DIR / 'default.yaml'}\nobject_set: set.yaml\ntrials: 1\n"
        "protocols: [natural]\nmethods: [{name: g, overrides: {grasp_method: gbh}}]\n"
        "replays: none\n")
    return tmp_path


def finish_every_trial(folder, *, legacy: bool = False) -> None:
    """The rows of every trial of the experiment in ``folder/out``, as the worker writes them
    (``legacy``: without ``object_digest``, as rows were written before they carried it)."""
    store = RowStore(folder / "out")
    for task in make_tasks(load_experiment(folder / "exp.yaml")):
        row = dict(_base_row(task), outcome="not_lifted", reason="made up",
                   protocol=task.protocol)  # (the runner sets it)
        if legacy:
            row.pop("object_digest", None)
        store.append(row)


def resume(folder, capsys) -> tuple[int, str]:
    """``gbh experiment`` on the folder: (exit code, what it said); it must run no trial."""
    code = main(["experiment", str(folder / "exp.yaml"), "--out", str(folder / "out"),
                 "--workers", "1", "--no-progress"])
    out, err = capsys.readouterr()
    assert "0 trials run" in out or code != 0, out
    return code, out + err


def test_rows_carry_the_version_of_a_set_entry_and_a_built_in_objects_are_as_before(user_set):
    tasks = {t.object: t for t in make_tasks(load_experiment(user_set / "exp.yaml"))}
    block, teapot = tasks["block"], tasks["teapot"]
    assert len(block.object_digest) == 64 and _base_row(block)["object_digest"] == \
        block.object_digest
    assert teapot.object_digest == "" and "object_digest" not in _base_row(teapot)
    for task in (block, teapot):  # the scenario's digest is its text's, as before
        assert task.digest == hashlib.sha256(task.scenario_yaml.encode()).hexdigest()


CHANGES = {
    "mass": ("mass: 0.25", "mass: 0.26"),
    "scale": ("scale: 0.01", "scale: 0.011"),
    "rest": ("rest: {as_given: true, reason: on its base}",
             "rest: {rpy_deg: [90, 0, 0], reason: on its side}"),
    "control": ("    tags: [box]\n", "    tags: [box]\n    control: true\n"),
    "density": ("mass: 0.25", "density: 500"),
    "parts": ("    tags: [box]\n", "    tags: [box]\n    hangable_parts: [{center: [0, 0, 0.05], "
                                    "axis: [1, 0, 0], clear_diameter: 0.02}]\n"),
}


@pytest.mark.parametrize("change", [*CHANGES, "mesh file"])
def test_a_changed_entry_refuses_its_rows(user_set, capsys, change):
    """It said ``2 done before, 0 to run`` after the mass changed from 0.25 to 0.26 kg."""
    finish_every_trial(user_set)
    code, said = resume(user_set, capsys)
    assert code == 0 and "2 done before, 0 to run" in said
    if change == "mesh file":
        trimesh.creation.box((6.0, 8.0, 11.0)).export(user_set / "block_cm.obj")
    else:
        old, new = CHANGES[change]
        (user_set / "set.yaml").write_text(SET.replace(old, new))
    code, said = resume(user_set, capsys)
    assert code == 2
    assert "1 rows were made with other objects than this experiment's (the object set's " \
           "entry of block changed since" in said and "('block', 'g', 0, 'natural')" in said


@pytest.mark.parametrize("old, new", [
    ("tags: [box]", "tags: [box, flat]"),
    ("reason: on its base", "reason: standing on its base"),
    ("    tags: [box]\n", "    tags: [box]\n    description: a block\n    mass_note: a guess\n"),
])
def test_a_changed_word_keeps_the_rows(user_set, capsys, old, new):
    finish_every_trial(user_set)
    (user_set / "set.yaml").write_text(SET.replace(old, new))
    code, said = resume(user_set, capsys)
    assert code == 0 and "2 done before, 0 to run" in said


def test_rows_written_before_rows_carried_the_entrys_version_resume(user_set, capsys):
    """Rows without ``object_digest`` (the shipped experiments' on the external set) are judged
    by their scenario alone."""
    finish_every_trial(user_set, legacy=True)
    (user_set / "set.yaml").write_text(SET.replace("mass: 0.25", "mass: 0.26"))
    code, said = resume(user_set, capsys)
    assert code == 0 and "2 done before, 0 to run" in said


def test_rows_of_another_version_are_not_reused(user_set):
    finish_every_trial(user_set)
    (user_set / "set.yaml").write_text(SET.replace("mass: 0.25", "mass: 0.26"))
    tasks = make_tasks(load_experiment(user_set / "exp.yaml"))
    done = {}
    assert reuse_rows(user_set / "new", RowStore(user_set / "new"), tasks, done,
                      [user_set / "out"], log=lambda _: None) == 1
    assert [key[0] for key in done] == ["teapot"]


def test_a_run_that_only_reuses_logs_its_run(user_set, capsys):
    """``--reuse`` into a new folder that took every trial ran none and wrote no runs.jsonl;
    its line is written as a run's, with the trials it reused, and the summary's head names
    ``gbh experiment``."""
    finish_every_trial(user_set)
    new = user_set / "new"
    assert main(["experiment", str(user_set / "exp.yaml"), "--out", str(new), "--reuse",
                 str(user_set / "out"), "--workers", "1", "--no-progress"]) == 0
    assert "0 trials run" in capsys.readouterr().out
    [run] = [json.loads(line) for line in (new / "runs.jsonl").read_text().splitlines()]
    assert run["trials"] == 0 and run["reused"] == 2 and not run["interrupted"]
    summary = (new / "summary.md").read_text()
    assert "Rebuilt from `trials.jsonl` by `gbh experiment`." in summary
    assert ": 0 trials on 1 local worker in 0.0 min (0.00 trials/min); 2 trials reused from " \
           "other folders" in summary


def _refused(experiment) -> str:
    """The text of the ExperimentError that loading the file ``experiment`` raises."""
    with pytest.raises(ExperimentError) as error:
        load_experiment(experiment)
    return str(error.value)


def test_an_entry_without_a_natural_rest_is_named_where_the_user_chose_it(user_set):
    """With ``objects`` left out (every object of the set) it said ``objects[0] 'block'``, an
    index of no list in the experiment file: now the set's entry; a listed object is named by
    its entry of the experiment's ``objects``."""
    (user_set / "set.yaml").write_text(SET.replace("    rest: {as_given: true, reason: on "
                                                   "its base}\n", ""))
    assert _refused(user_set / "exp.yaml").startswith(
        f"{user_set / 'exp.yaml'}: protocols[0] (line 4): natural: object_set "
        f"{user_set / 'set.yaml'}: objects[0] (block) (line 2) has no natural rest declared in "
        "the object set (1 object without: block)")
    (user_set / "exp.yaml").write_text((user_set / "exp.yaml").read_text()
                                       + "objects: [teapot, block]\n")
    with pytest.raises(ExperimentError, match=r"natural: objects\[1\] 'block' \(line 7\) has "):
        load_experiment(user_set / "exp.yaml")


def test_the_report_names_the_manifest_of_the_natural_rests(user_set, capsys):
    """summary.md said the rests were declared in gbh_drake/objects/catalog.py."""
    finish_every_trial(user_set)
    assert resume(user_set, capsys)[0] == 0
    summary = (user_set / "out" / "summary.md").read_text()
    assert "declared per object, with its reason, in its object set, [set.yaml](../set.yaml) " \
           "(a built-in object's in gbh_drake/objects/catalog.py)" in summary


@pytest.mark.parametrize("objects, field", [("", "object_set (line 2)"),
                                            ("objects: [teapot, big]\n", "objects[1] (line 7)")])
def test_an_object_that_cannot_be_simulated_is_refused_before_any_trial(user_set, capsys,
                                                                          objects, field):
    """A box in millimetres without ``scale``: 100 m, simulated (a mug's 122 m were, each trial
    a failure the experiment counted)."""
    trimesh.creation.box((60.0, 80.0, 100.0)).export(user_set / "big_mm.stl")
    (user_set / "set.yaml").write_text(SET + "  - {name: big, mesh: big_mm.stl, mass: 0.3}\n")
    (user_set / "exp.yaml").write_text((user_set / "exp.yaml").read_text() + objects)
    assert _refused(user_set / "exp.yaml").startswith(
        f"{user_set / 'exp.yaml'}: {field}: {user_set / 'set.yaml'}: objects[2] (big).scale "
        f"(line 9): {user_set / 'big_mm.stl'}: largest extent 100 m is larger than the "
        "workspace (> 1.2 m): looks like millimetres: give scale: 0.001 (then 10 cm)")
    code, said = resume(user_set, capsys)
    assert code == 2 and said.startswith("gbh: invalid experiment: ")
    assert not (user_set / "out").exists()
