"""The GbH LeafSystems on their own: fixed inputs, cached outputs, cloneable contexts."""

import pytest
from pydrake.systems.framework import DiagramBuilder

from gbh_drake.core.params import GbhParams
from gbh_drake.objects import make_object
from gbh_drake.systems.grasp_scorer import GraspScorer
from gbh_drake.systems.grasp_synthesizer import GraspSynthesizer
from gbh_drake.systems.hangability_detector import Hangability, HangabilityDetector


def _chain():
    builder = DiagramBuilder()
    params = GbhParams()
    detector = builder.AddSystem(HangabilityDetector(params))
    synthesizer = builder.AddSystem(GraspSynthesizer(params))
    scorer = builder.AddSystem(GraspScorer(params))
    builder.Connect(detector.get_output_port(), synthesizer.get_input_port())
    builder.Connect(synthesizer.get_output_port(), scorer.get_input_port())
    builder.ExportInput(detector.get_input_port(), "mesh_W")
    builder.ExportOutput(scorer.get_output_port(), "ranked_grasps")
    return builder.Build(), detector, synthesizer


def test_chain_on_a_mesh_from_the_user():
    diagram, detector, synthesizer = _chain()
    context = diagram.CreateDefaultContext()
    diagram.get_input_port().FixValue(context, make_object("mug_classic").mesh)
    ranked = diagram.get_output_port().Eval(context)
    assert ranked and all(g.n_collisions < 10 for g in ranked)
    # Contexts holding GbH values can be cloned (the Embree scene is shared, not copied).
    clone = context.Clone()
    assert len(diagram.get_output_port().Eval(clone)) == len(ranked)
    # A stage can be fed by hand.
    hangability = detector.get_output_port().Eval(detector.GetMyContextFromRoot(context))
    alone = synthesizer.CreateDefaultContext()
    synthesizer.get_input_port().FixValue(alone, hangability)
    assert len(synthesizer.get_output_port().Eval(alone)) >= len(ranked)


def test_nothing_hangable_is_a_result():
    diagram, detector, _ = _chain()
    context = diagram.CreateDefaultContext()
    diagram.get_input_port().FixValue(context, make_object("box").mesh)
    assert diagram.get_output_port().Eval(context) == []
    result = detector.get_output_port().Eval(detector.GetMyContextFromRoot(context))
    assert isinstance(result, Hangability) and result.message == "no hangable structure found"


def test_wrong_input_type_names_the_system_and_port():
    diagram, detector, _ = _chain()
    context = diagram.CreateDefaultContext()
    diagram.get_input_port().FixValue(context, "not a mesh")
    with pytest.raises(TypeError, match="mesh_W.*ScanResult or Trimesh.*str"):
        detector.get_output_port().Eval(detector.GetMyContextFromRoot(context))


def test_the_chain_runs_once_per_scan_however_often_drake_invalidates_it():
    """Drake marks the scan changed at every unrestricted update (here: re-fixing the input with
    the same scan); GbH runs again only for another scan, and on a copy of a scan (Drake's copy
    of the Scanner's state: mesh and free space shared) it hands on the same ranked list."""
    import copy

    from gbh_drake.perception.scan import ScanResult

    diagram, detector, synthesizer = _chain()
    runs = []
    compute = detector.compute
    detector.compute = lambda value: runs.append(value) or compute(value)
    context = diagram.CreateDefaultContext()
    mesh = make_object("mug_classic").mesh
    scan = ScanResult(mesh, mesh.vertices)
    diagram.get_input_port().FixValue(context, scan)
    first = diagram.get_output_port().Eval(context)
    diagram.get_input_port().FixValue(context, copy.deepcopy(scan))
    assert diagram.get_output_port().Eval(context) is first and len(runs) == 1
    other = ScanResult(mesh.copy(), mesh.vertices)  # another scan, even of the same shape
    diagram.get_input_port().FixValue(context, other)
    again = diagram.get_output_port().Eval(context)
    assert len(runs) == 2 and again is not first and len(again) == len(first)


def test_the_scoop_synthesizer_plans_once_per_hangability_object(monkeypatch):
    """As the stages: re-validating the same scan (a copy of it: Drake's copy of the Scanner's
    state) plans no scoop again, fed by the detector as in a trial; another scan does."""
    import copy

    import gbh_drake.systems.scoop_synthesizer as module
    from gbh_drake.perception.scan import ScanResult

    ring = make_object("key_ring").mesh.copy()
    ring.apply_translation([0.55, 0.0, -ring.bounds[0][2]])  # lying flat on the table
    builder = DiagramBuilder()
    detector = builder.AddSystem(HangabilityDetector(GbhParams()))
    scoops = builder.AddSystem(module.ScoopSynthesizer())
    builder.Connect(detector.get_output_port(), scoops.get_input_port())
    builder.ExportInput(detector.get_input_port(), "mesh_W")
    builder.ExportOutput(scoops.GetOutputPort("scoop_grasps"), "scoop_grasps")
    builder.ExportOutput(scoops.GetOutputPort("tall_scoop_grasps"), "tall_scoop_grasps")
    diagram = builder.Build()
    plan, runs = module.plan_scoops, []
    monkeypatch.setattr(module, "plan_scoops", lambda *a, **k: runs.append(1) or plan(*a, **k))
    context = diagram.CreateDefaultContext()
    scan = ScanResult(ring, ring.vertices)
    diagram.get_input_port().FixValue(context, scan)
    first = diagram.GetOutputPort("scoop_grasps").Eval(context)
    diagram.get_input_port().FixValue(context, copy.deepcopy(scan))
    assert diagram.GetOutputPort("scoop_grasps").Eval(context) is first and len(runs) == 1
    diagram.get_input_port().FixValue(context, ScanResult(ring.copy(), ring.vertices))
    again = diagram.GetOutputPort("scoop_grasps").Eval(context)
    assert len(runs) == 2 and len(again) == len(first) > 0
    # The ring's 2.5 mm wire is no taller than the wedge: no tall scoop, from the same plan;
    # the tape roll's 19 mm wall: tall scoops only, the plan's ranked_tall.
    assert diagram.GetOutputPort("tall_scoop_grasps").Eval(context) == [] and len(runs) == 2
    roll = make_object("tape_roll").mesh.copy()
    roll.apply_translation([0.55, 0.0, -roll.bounds[0][2]])
    diagram.get_input_port().FixValue(context, ScanResult(roll, roll.vertices))
    tall = diagram.GetOutputPort("tall_scoop_grasps").Eval(context)
    result = scoops.GetOutputPort("scoops").Eval(scoops.GetMyContextFromRoot(context))
    assert tall and tall == result.ranked_tall and len(runs) == 3
    assert diagram.GetOutputPort("scoop_grasps").Eval(context) == []
