"""The studio (``gbh studio``) driven in-process through Drake's Meshcat API, as the page drives
it: sliders set with ``SetSliderValue`` (as Drake's JointSliders tests do), buttons pressed with
the message the page sends when one is clicked (``_InjectWebsocketMessage``, as Drake's own
tests press them); assertions on the scene tree, the panel's text and the trial's record."""

from __future__ import annotations

import signal
import subprocess
import sys

import msgpack
import numpy as np
import pytest

from gbh_drake.cli import main
from gbh_drake.scenario import Scenario
from gbh_drake.scenario.loader import apply_overrides
from gbh_drake.studio.choices import DROP, Choices, object_choices, overrides
from gbh_drake.studio.controls import RANK, Studio
from gbh_drake.studio.session import Session
from gbh_drake.viz.meshcat_server import local_meshcat


def press(meshcat, name: str) -> None:
    """Clicks the button ``name`` as the page does (its message over the websocket)."""
    meshcat._InjectWebsocketMessage(msgpack.packb({"type": "button", "name": name}))


def test_the_choices_are_gbh_run_set_text_that_places_the_object_where_chosen():
    """What the studio builds is what ``gbh run --set '<its text>'`` runs: the object, where
    the controls put it (a chosen rest turned by the yaw), the views, method, preset, seed."""
    base = Scenario()
    mug = next(o for o in object_choices(base) if o.label == "mug_classic")
    R_rest = np.array([[1.0, 0, 0], [0, 0, -1.0], [0, 1.0, 0]])  # x by +90 deg
    choices = Choices(x=0.5, y=-0.1, yaw_deg=90.0, rest=0, views=3, method="gbh_fallback",
                      preset="paper", seed=7)
    s = apply_overrides(base, overrides(mug, choices, R_rest))
    assert (s.object.name, s.scan.num_views, s.grasp_method, s.gbh.preset, s.seed) == \
        ("mug_classic", 3, "gbh_fallback", "paper", 7)
    X = s.object.pose.GetDeterministicValue()
    np.testing.assert_allclose(X.translation(), [0.5, -0.1, 0.0])
    Rz = np.array([[0.0, -1, 0], [1, 0, 0], [0, 0, 1]])
    np.testing.assert_allclose(X.rotation().matrix(), Rz @ R_rest, atol=1e-9)
    drop = apply_overrides(base, overrides(mug, Choices(x=0.6, y=0.05, rest=DROP)))
    assert drop.object.random_pose.x == [0.6, 0.6] and drop.object.random_pose.rest == "stable"


@pytest.mark.sim
@pytest.mark.trial
def test_scan_detect_slide_to_rank_2_execute_and_reset_from_the_page():
    meshcat = local_meshcat()
    base = Scenario()  # the mug
    said = []
    studio = Studio(Session(base, object_choices(base), meshcat=meshcat), meshcat,
                    say=said.append)
    session = studio.session
    assert session.objects[session.choices.object].label == "mug_classic"
    assert set(meshcat.GetSliderNames()) >= {"object", "x (m)", "views", "method", "seed"}
    assert RANK not in meshcat.GetSliderNames()  # nothing to rank before Detect

    meshcat.SetSliderValue("views", 4)
    assert studio.step() == ["views"] and session.choices.views == 4
    press(meshcat, "Scan")
    assert studio.step() == ["Scan"]
    assert said[-1].startswith("placed: gbh run --set '") and "num_views: 4" in said[-1]
    assert session.scenario.scan.num_views == 4 and len(session.scan.X_WCs) == 4
    assert meshcat.HasPath("studio/cameras/views/3") and meshcat.HasPath("studio/object")
    assert any(line.startswith("scan: 4 views") for line in studio.text.lines)
    press(meshcat, "Free space")
    assert studio.step() == ["Free space"] and meshcat.HasPath("studio/free_space")

    press(meshcat, "Detect")
    assert studio.step() == ["Detect"]
    detection = session.detection
    assert detection.result.structures and meshcat.HasPath("studio/structures")
    offered = [o for o in detection.offered if not o.rule]
    assert len(offered) >= 2, "the mug's scan offers at least two grasps to step through"
    assert RANK in meshcat.GetSliderNames()
    assert any("candidates; removed: collision N_c" in line for line in studio.text.lines)
    assert studio.rank == 0 and meshcat.HasPath("studio/grasp/open/fingers")
    assert meshcat.HasPath("studio/near/0")  # the refused candidates nearest to it
    assert any(line.startswith("near (") and "refused by " in line for line in studio.text.lines)

    meshcat.SetSliderValue(RANK, 1)
    assert studio.step() == [RANK] and studio.rank == 1
    shown = offered[1].shown
    assert meshcat.HasPath("studio/grasp/closed")
    assert any(line.startswith(f"grasp 2/{len(detection.offered)}") for line in studio.text.lines)
    assert any(line.startswith(f"= m {shown.terms['m']:.2f}") for line in studio.text.lines)
    assert any(line.startswith(("planner:", "planner would refuse it:"))
               for line in studio.text.lines)

    scanned = session.simulator.get_context().get_time()
    press(meshcat, "Execute")
    assert studio.step() == ["Execute"]
    record = session.record
    # The grasp on the slider is the one executed, through the trial's machine and judge.
    assert record.grasp_source == "grasps" and record.grasp_kind == offered[1].grasp.kind
    assert record.grasp_score == pytest.approx(offered[1].grasp.score)
    assert session.execute_from == pytest.approx(scanned)
    verdict = "SUCCESS" if record.success else "FAILURE"
    assert f"verdict: {verdict}" in " ".join(studio.text.lines)
    if record.success:
        assert record.held_by in ("cage", "pinch") and f"({record.held_by})" in said[-1]

    press(meshcat, "Reset")  # back to the scan, the detection kept
    assert studio.step() == ["Reset"]
    assert session.simulator.get_context().get_time() == pytest.approx(scanned)
    assert session.stage == "detected" and session.record is None
    assert not any(line.startswith("verdict:") for line in studio.text.lines)


def test_gbh_studio_help_says_what_it_does_and_how_to_leave(capsys):
    with pytest.raises(SystemExit) as exit_:
        main(["studio", "--help"])
    assert exit_.value.code == 0
    out = " ".join(capsys.readouterr().out.split())
    for words in ("Detect", "Execute", "rank slider", "--objects", "--mesh", "--port",
                  "until Ctrl-C (SIGINT) or SIGTERM (exit 0)", "docs/studio.md"):
        assert words in out, words


@pytest.mark.sim
def test_a_mesh_file_that_cannot_be_used_exits_2_naming_it(tmp_path, capsys):
    bad = tmp_path / "cup.obj"
    bad.write_text("v 0 0 0\n")
    assert main(["studio", "--mesh", str(bad)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("gbh: invalid mesh: ") and "cup.obj" in err and "\n" not in err


@pytest.mark.sim
def test_gbh_studio_serves_the_placed_object_until_sigterm_then_exits_0():
    process = subprocess.Popen([sys.executable, "-m", "gbh_drake.cli", "studio", "--set",
                                "scan: {num_views: 1}"], stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True)
    try:
        url = process.stdout.readline()
        assert url.startswith("gbh studio: http://localhost:") and "Ctrl-C ends it" in url
        placed = process.stdout.readline()
        assert placed.startswith("placed: gbh run --set '{seed: 0, grasp_method: gbh, ")
        process.send_signal(signal.SIGTERM)
        assert process.wait(timeout=60) == 0
    finally:
        process.kill()
    assert process.stderr.read() == ""


def test_the_objects_offered_are_the_scenarios_the_built_in_set_a_manifests_and_mesh_files(
        tmp_path):
    import trimesh

    from gbh_drake import REPO_ROOT
    from gbh_drake.objects.catalog import list_objects
    from gbh_drake.objects.sets import load_object_set

    mesh = tmp_path / "cup.obj"
    trimesh.creation.box([0.05, 0.05, 0.08]).export(mesh)
    manifest = REPO_ROOT / "scenarios" / "object_sets" / "own.yaml"
    objects = object_choices(Scenario(), [manifest], [mesh])
    labels = [o.label for o in objects]
    own = load_object_set(manifest)
    assert labels[0] == "mug_classic" and labels.count("mug_classic") == 1
    assert set(list_objects()) <= set(labels)
    assert [f"{own.name}/{n}" for n in own.names] == labels[-1 - len(own.names):-1]
    assert objects[-2].config.set == str(manifest.resolve())
    assert labels[-1] == "cup.obj" and objects[-1].config.mesh == str(mesh.resolve())


@pytest.mark.sim
def test_a_mesh_file_chosen_with_the_object_slider_without_structure_has_nothing_to_execute(
        tmp_path):
    import trimesh

    mesh = tmp_path / "block.obj"
    trimesh.creation.box([0.05, 0.05, 0.08]).export(mesh)
    meshcat = local_meshcat()
    base = apply_overrides(Scenario(), "{scan: {num_views: 1}}")
    objects = object_choices(base, meshes=[mesh])
    studio = Studio(Session(base, objects, meshcat=meshcat), meshcat, say=lambda _: None)
    meshcat.SetSliderValue("object", len(objects) - 1)
    assert studio.step() == ["object"]
    assert any("changed: Reset or Scan places it" in line for line in studio.text.lines)
    press(meshcat, "Execute")  # places, scans and detects first
    assert studio.step() == ["Execute"]
    session = studio.session
    assert session.scenario.object.mesh == str(mesh.resolve()) and session.record is None
    assert session.detection.result.none.outcome == "no_hangable_structure"
    assert RANK not in meshcat.GetSliderNames()
    lines = studio.text.lines
    assert lines[0].startswith("block.obj: ") and "no grasp offered (" in " ".join(lines)
    assert any(line.startswith("nothing to execute: the method offered") for line in lines)


#: The default scenario's mug with what no slider's range or step holds: a seed above 99, more
#: than 20 views, a pose off the 5 mm and 1 deg grid (two views: its handle's structures found).
OFF_GRID = ("{seed: 1234, scan: {num_views: 2}, object: {pose: {translation: [0.5523, 0.0117, "
            "0.0], rotation: !Rpy {deg: [0.0, 0.0, 32.5]}}}}")


def off_grid_scenario():
    from gbh_drake import REPO_ROOT
    from gbh_drake.scenario import load_scenario

    return load_scenario(REPO_ROOT / "scenarios" / "default.yaml", overrides=OFF_GRID)


def test_the_sliders_keep_the_scenarios_values_that_their_range_and_step_do_not_hold():
    """Drake's AddSlider clamps to the range and rounds to the step: the studio's trial was
    seed 99, 20 views, yaw 30 deg for a scenario of seed 1234, 24 views, yaw 32.5 deg."""
    base = apply_overrides(off_grid_scenario(), "{scan: {num_views: 24}}")
    meshcat = local_meshcat()
    session = Session(base, object_choices(base), meshcat=meshcat)
    studio = Studio(session, meshcat, say=lambda _: None)
    c = session.choices
    assert (c.seed, c.views, c.x, c.y) == (1234, 24, 0.5523, 0.0117)
    assert c.yaw_deg == pytest.approx(32.5)  # from the pose's rotation matrix
    assert studio.step() == []  # the page's sliders show them: nothing moved
    text = session._overrides_now()
    assert "seed: 1234" in text and "num_views: 24" in text
    assert "translation: [0.5523, 0.0117, 0.0], rotation: !Rpy {deg: [0.0, 0.0, 32.5]}" in text
    assert meshcat.GetSliderValue("seed") == 1234 and meshcat.GetSliderValue("views") == 24
    meshcat.SetSliderValue("yaw (deg)", 40)  # moved: the slider's value from then on
    assert studio.step() == ["yaw (deg)"] and c.yaw_deg == 40.0 and c.x == 0.5523


def test_the_rank_slider_of_a_single_grasp_stays_on_it():
    """One grasp offered: the slider ran 0..1 and stood at 1 with grasp 1 of 1 shown."""
    from gbh_drake.method_spec import Tier
    from gbh_drake.studio.session import Detection, Offered

    meshcat = local_meshcat()
    base = Scenario()
    session = Session(base, object_choices(base), meshcat=meshcat)
    studio = Studio(session, meshcat, say=lambda _: None)
    session.detection = Detection(None, [], None, [Offered(Tier.GRASPS, 0, object())])
    studio.layout()
    meshcat.SetSliderValue(RANK, 1)
    assert meshcat.GetSliderValue(RANK) == 0 and studio.step() == []


@pytest.mark.sim
def test_scan_pressed_again_after_detect_keeps_the_detection_with_its_rank_slider():
    """Scan pressed again after Detect showed the scan but dropped the structures, the grasp
    and their text while the rank slider stayed (moving it then drew a grasp with no
    detection). A button clicked while a step rebuilt the panel was lost."""
    meshcat = local_meshcat()
    base = off_grid_scenario()
    studio = Studio(Session(base, object_choices(base), meshcat=meshcat), meshcat,
                    say=lambda _: None)
    session = studio.session
    press(meshcat, "Detect")
    assert studio.step() == ["Detect"] and session.detection.offered
    meshcat.SetSliderValue(RANK, 1)
    assert studio.step() == [RANK]
    press(meshcat, "Scan")
    assert studio.step() == ["Scan"]
    assert studio.rank == 1 and meshcat.GetSliderValue(RANK) == 1
    assert meshcat.HasPath("studio/structures") and meshcat.HasPath("studio/grasp/open")
    assert meshcat.HasPath("studio/cameras/views/0")
    lines = studio.text.lines
    assert any(line.startswith("detect:") for line in lines)
    assert any(line.startswith("grasp 2/") for line in lines)

    press(meshcat, "Free space")  # clicked while a step rebuilds the panel: not lost
    studio.scan()
    assert studio.step() == ["Free space"] and meshcat.HasPath("studio/free_space")
