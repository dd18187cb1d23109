"""Every case of the experiment file's bad-input corpus through the real command line: exit
code 2, one line naming the file, the field and its line, nothing written (see
experiment_corpus.py)."""


import pytest
from experiment_corpus import CASES
from input_corpus import Case, check_refusal, write_case

from gbh_drake.cli import DEFAULT_SCENARIO, main


def _write_case(case: Case, folder):
    return write_case(case, folder, {"@BASE@": str(DEFAULT_SCENARIO)})


def test_case_ids_are_unique():
    ids = [c.id for c in CASES]
    assert len(ids) == len(set(ids))


@pytest.mark.parametrize("case", CASES, ids=[c.id for c in CASES])
def test_bad_experiment(case: Case, tmp_path, capsys):
    path = _write_case(case, tmp_path)
    origin = f"{path}{case.origin}"
    if case.field:
        prefix = f"gbh: invalid experiment: {origin}: {case.field}" + \
            (f" (line {case.line})" if case.line else "") + ": "
    else:
        prefix = f"gbh: invalid experiment: {origin}: " + (f"line {case.line}" if case.line else "")
    check_refusal(case, main, ["experiment", str(path), "--out", str(tmp_path / "out"),
                               "--no-progress"], capsys, prefix, tmp_path / "out")


def test_a_missing_experiment_file(tmp_path, capsys):
    assert main(["experiment", str(tmp_path / "nope.yaml")]) == 2
    assert capsys.readouterr().err == f"gbh: invalid experiment: {tmp_path / 'nope.yaml'}: " \
                                      "experiment file not found\n"


def test_an_empty_scenario_document_is_the_default_scenario(tmp_path):
    """``---`` alone (or ``~``) is no document: the defaults, as an empty file."""
    from gbh_drake.scenario import Scenario, load_scenario
    from gbh_drake.scenario.loader import dump_resolved

    for text in ("---\n", "--- # nothing\n", "~\n", ""):
        path = tmp_path / "s.yaml"
        path.write_text(text)
        default = Scenario()
        default.source_path = str(path.resolve())
        assert dump_resolved(load_scenario(path)) == dump_resolved(default), text


def test_the_public_api_refuses_what_the_yaml_refuses():
    from gbh_drake.core.params import GbhInputError, GbhParams

    for value in (float("nan"), float("inf"), 1.0):
        with pytest.raises(GbhInputError, match=r"^GbhParams\.d2: must be"):
            GbhParams(d2=value).check()
