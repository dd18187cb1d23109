"""Fixtures: the station with a mug of the object set standing on the table, and the truth in W."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pytest
import trimesh
from pydrake.math import RigidTransform
from pydrake.systems.framework import DiagramBuilder

from gbh_drake.perception.config import ScanConfig
from gbh_drake.systems.scanner import Scanner

#: The object scanned by the tests (handle along +x_O, a closed hole about 4 cm across).
MUG = "mug_classic"


@dataclass
class MugScene:
    """The station with the mug in a default context; the truth in W."""

    diagram: object
    context: object
    station: object
    query_object: object
    mesh_W: trimesh.Trimesh
    X_WO: RigidTransform
    handle_center_W: np.ndarray
    handle_axis_W: np.ndarray
    p_WT: np.ndarray
    """Scan target (m, W): the mug's centre."""
    scanner: Scanner
    """10 views (default config), scanned once per context."""
    rescanner: Scanner
    """1 view, rescanned when the scene moves."""


def build_mug_scene(model_dir) -> MugScene:
    """The station with the mug at its default place, turned so that its handle points to +y_W
    (a camera on the robot's side sees it edge-on)."""
    from gbh_drake.objects import make_object
    from gbh_drake.scenario import Scenario
    from gbh_drake.station import ObjectAsset, add_station

    spec = make_object(MUG)
    scenario = Scenario()
    scenario.object.pose.set_rotation_rpy_deg([0.0, 0.0, 90.0])
    asset = ObjectAsset(spec.name, spec.mesh, spec.density, spec.rgba, f"object set: {MUG}")
    builder = DiagramBuilder()
    station = add_station(builder, scenario, model_dir=model_dir, object_asset=asset)
    X_WO = station.X_WO_initial
    p_WT = X_WO @ np.array([0.0, 0.0, 0.5 * spec.mesh.bounds[1, 2]])
    scanners = [builder.AddSystem(Scanner(config, p_WT, rescan_on_change=rescan))
                for config, rescan in [(ScanConfig(), False), (ScanConfig(num_views=1), True)]]
    for scanner in scanners:
        builder.Connect(station.scene_graph.get_query_output_port(), scanner.get_input_port())
    diagram = builder.Build()
    context = diagram.CreateDefaultContext()
    sg_context = station.scene_graph.GetMyContextFromRoot(context)
    query_object = station.scene_graph.get_query_output_port().Eval(sg_context)
    handle = spec.hangable_parts[0]
    return MugScene(
        diagram, context, station, query_object,
        mesh_W=spec.mesh.copy().apply_transform(X_WO.GetAsMatrix4()),
        X_WO=X_WO,
        handle_center_W=X_WO @ handle.center_O,
        handle_axis_W=X_WO.rotation() @ handle.axis_O,
        p_WT=p_WT,
        scanner=scanners[0],
        rescanner=scanners[1],
    )


@pytest.fixture(scope="session")
def mug_scene(tmp_path_factory) -> MugScene:
    return build_mug_scene(tmp_path_factory.mktemp("models"))
