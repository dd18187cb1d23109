"""A wrong wire between Python-valued ports fails when the diagram is built, naming both ends."""

import pytest
import trimesh
from pydrake.common.value import AbstractValue
from pydrake.systems.framework import DiagramBuilder
from pydrake.systems.primitives import ConstantValueSource

from gbh_drake.perception.config import ScanConfig
from gbh_drake.systems import (
    GraspScorer,
    GraspSynthesizer,
    HangabilityDetector,
    Scanner,
    build_checked,
)
from gbh_drake.systems.ports import accepted_types


def test_matching_models_build():
    builder = DiagramBuilder()
    detector = builder.AddNamedSystem("detector", HangabilityDetector())
    synthesizer = builder.AddNamedSystem("synthesizer", GraspSynthesizer())
    builder.Connect(detector.get_output_port(), synthesizer.get_input_port())
    build_checked(builder)


def test_a_stage_takes_the_types_it_lists():
    """The GbH stages take a scan or any mesh: both build."""
    builder = DiagramBuilder()
    mesh = builder.AddSystem(ConstantValueSource(AbstractValue.Make(trimesh.creation.box())))
    detector = builder.AddSystem(HangabilityDetector())
    builder.Connect(mesh.get_output_port(), detector.get_input_port())
    build_checked(builder)
    assert trimesh.Trimesh in accepted_types(detector.get_input_port())


def test_a_wrong_wire_fails_at_build_naming_both_ports():
    builder = DiagramBuilder()
    detector = builder.AddNamedSystem("detector", HangabilityDetector())
    scorer = builder.AddNamedSystem("scorer", GraspScorer())
    builder.Connect(detector.get_output_port(), scorer.get_input_port())  # Drake accepts it
    with pytest.raises(TypeError, match=r"output detector\.hanging_structures \(Hangability\) "
                                        r"is connected to input scorer\.grasp_candidates, which "
                                        r"takes list"):
        build_checked(builder)


def test_a_scanner_feeding_a_list_input_fails():
    builder = DiagramBuilder()
    scanner = builder.AddNamedSystem("scanner", Scanner(ScanConfig(), [0.55, 0.0, 0.06]))
    synthesizer = builder.AddNamedSystem("synthesizer", GraspSynthesizer())
    builder.Connect(scanner.GetOutputPort("mesh_W"), synthesizer.get_input_port())
    with pytest.raises(TypeError, match="scanner.mesh_W"):
        build_checked(builder)
