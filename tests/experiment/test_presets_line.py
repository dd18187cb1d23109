"""The report says which GbH rules each method ran with (issue 17: the paper preset or ours)."""

from gbh_drake.experiment.report import presets_line


def row(method, grasp_method, preset=None):
    return {"method": method, "grasp_method": grasp_method,
            "record": {} if preset is None else {"gbh_preset": preset}}


def test_each_gbh_method_names_its_rules_and_the_baseline_is_left_out():
    line = presets_line([row("gbh-10", "gbh", ""), row("gbh-10", "gbh", ""),
                         row("gbh-paper", "gbh", "paper"), row("antipodal", "antipodal", ""),
                         row("old", "gbh")])
    assert "gbh-10: ours (2 trials)" in line and "gbh-paper: paper (1 trials)" in line
    assert "antipodal" not in line.split(":", 1)[1] and "old" not in line


def test_no_gbh_trials_no_line():
    assert presets_line([row("antipodal", "antipodal", "")]) == ""
