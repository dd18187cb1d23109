"""Fixtures: a small test mug (cup + torus handle) standing in the station, and its true mesh."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pytest
import trimesh
from pydrake.math import RigidTransform
from pydrake.systems.framework import DiagramBuilder

#: The mug's handle hole in its frame O (m): centre and axis (the handle points along +x_O).
HANDLE_CENTER_O = np.array([0.057, 0.0, 0.045])
HANDLE_AXIS_O = np.array([0.0, 1.0, 0.0])


def make_test_mug() -> trimesh.Trimesh:
    """A watertight mug in frame O (m): cup of radius 4 cm, height 9 cm, wall 5 mm, bottom
    5 mm, with a torus handle along +x_O whose hole is about 3 cm across."""
    outer = trimesh.creation.cylinder(radius=0.04, height=0.09, sections=64)
    outer.apply_translation([0, 0, 0.045])
    inner = trimesh.creation.cylinder(radius=0.035, height=0.09, sections=64)
    inner.apply_translation([0, 0, 0.05 + 0.045])
    cup = trimesh.boolean.difference([outer, inner], engine="manifold")
    handle = trimesh.creation.torus(major_radius=0.022, minor_radius=0.006,
                                    major_sections=48, minor_sections=16)
    handle.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, [1, 0, 0]))
    handle.apply_translation([0.058, 0.0, 0.045])
    mug = trimesh.boolean.union([cup, handle], engine="manifold")
    assert mug.is_watertight
    return mug


@dataclass
class MugScene:
    """The station with the test mug, a context, and the truth in W."""

    diagram: object
    context: object
    scene_graph: object
    query_object: object
    mesh_W: trimesh.Trimesh
    X_WO: RigidTransform
    p_WT: np.ndarray
    """Scan target (m, W): the mug's centre."""

    @property
    def handle_center_W(self) -> np.ndarray:
        return self.X_WO @ HANDLE_CENTER_O

    @property
    def handle_axis_W(self) -> np.ndarray:
        return self.X_WO.rotation() @ HANDLE_AXIS_O


def build_mug_scene(model_dir) -> MugScene:
    """The station with the test mug at its default place, handle along +y_W."""
    from gbh_drake.scenario import Scenario
    from gbh_drake.station import ObjectAsset, add_station

    mug = make_test_mug()
    scenario = Scenario()
    # The handle sideways (+y_W), so that a camera on the robot's side sees it edge-on.
    scenario.object.pose.set_rotation_rpy_deg([0.0, 0.0, 90.0])
    builder = DiagramBuilder()
    station = add_station(builder, scenario, model_dir=model_dir,
                          object_asset=ObjectAsset("mug", mug, 900.0, (0.9, 0.9, 0.85, 1.0),
                                                   "test mug"))
    diagram = builder.Build()
    context = diagram.CreateDefaultContext()
    sg_context = station.scene_graph.GetMyContextFromRoot(context)
    query_object = station.scene_graph.get_query_output_port().Eval(sg_context)
    X_WO = station.X_WO_initial
    mesh_W = mug.copy().apply_transform(X_WO.GetAsMatrix4())
    p_WT = X_WO.translation() + [0.0, 0.0, 0.045]
    return MugScene(diagram, context, station.scene_graph, query_object, mesh_W, X_WO, p_WT)


@pytest.fixture(scope="session")
def mug_scene(tmp_path_factory) -> MugScene:
    return build_mug_scene(tmp_path_factory.mktemp("models"))
