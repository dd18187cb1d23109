"""Fixtures: scenes with an object of the set on the table and the robot beside it (see
``gbh_drake.perception.scenes``), built once per session, and the truth in W."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pytest
import trimesh
from pydrake.math import RigidTransform

from gbh_drake.perception.config import ScanConfig
from gbh_drake.perception.scenes import ObjectScene, build_scene
from gbh_drake.systems.scanner import Scanner

#: The object scanned by the mug tests (handle along +x_O, a closed hole about 4 cm across).
MUG = "mug_classic"


@dataclass
class MugScene:
    """The mug scene in a default context, with a Scanner; the truth in W."""

    diagram: object
    context: object
    scene: ObjectScene
    query_object: object
    mesh_W: trimesh.Trimesh
    X_WO: RigidTransform
    handle_center_W: np.ndarray
    handle_axis_W: np.ndarray
    p_WT: np.ndarray
    """Scan target (m, W): the mug's centre."""
    scanner: Scanner
    """10 views (default config)."""


def build_mug_scene(model_dir) -> MugScene:
    """The mug at (0.55, 0) turned so that its handle points to +y_W (a camera on the robot's
    side sees it edge-on), with a Scanner connected to the scene graph."""
    scanners = []

    def add_scanner(builder, scene_graph):
        p_WT = np.array([0.55, 0.0, 0.002 + 0.5 * 0.095])
        scanner = builder.AddSystem(Scanner(ScanConfig(), p_WT))
        builder.Connect(scene_graph.get_query_output_port(), scanner.get_input_port())
        scanners.append((scanner, p_WT))

    scene = build_scene(MUG, model_dir, yaw_deg=90.0, systems=[add_scanner])
    (scanner, p_WT), = scanners
    center, axis, _ = scene.part_W(0)
    return MugScene(scene.diagram, scene.context, scene, scene.query_object, scene.mesh_W,
                    scene.X_WO, center, axis, p_WT, scanner)


@pytest.fixture(scope="session")
def mug_scene(tmp_path_factory) -> MugScene:
    return build_mug_scene(tmp_path_factory.mktemp("models"))


@pytest.fixture(scope="session")
def scene_cache(tmp_path_factory):
    """Builds scenes on demand, once per (object, placement): ``scene_cache(name, **kwargs)``
    with ``build_scene``'s keyword arguments."""
    cache: dict = {}

    def get(name: str, **kwargs) -> ObjectScene:
        key = (name, tuple(sorted((k, str(v)) for k, v in kwargs.items())))
        if key not in cache:
            cache[key] = build_scene(name, tmp_path_factory.mktemp(name), **kwargs)
        return cache[key]

    return get
