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
