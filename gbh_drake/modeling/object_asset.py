"""The object of a scenario: its mesh resting on the table, its mass properties, its start pose.

:func:`load_object_asset` reads a named object of the set or any mesh file, places it so that
it rests on the plane z = 0 of its frame O whatever the file's origin, computes its mass
properties (from a density or a given mass) and collects plausibility warnings (size, mass) that
name the source and hint at the fix. :func:`initial_object_pose` draws X_WO from the seed: a
fixed or distributed ``schema.Transform``, or a random stable resting pose; either way the object
never starts inside the table.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import trimesh
from pydrake.common import RandomGenerator
from pydrake.math import RigidTransform, RotationMatrix

from gbh_drake.config import ObjectConfig
from gbh_drake.modeling.object_sdf import model_name

#: Density (kg/m^3) of a mesh object when the scenario gives neither density nor mass.
DEFAULT_MESH_DENSITY = 600.0


@dataclass
class ObjectAsset:
    """An object ready for the plant: mesh in its frame O (metres, resting on z = 0), mass
    properties (kg, m, kg m^2 about the CoM in O), colour, where it came from."""

    name: str
    mesh: trimesh.Trimesh
    mass: float
    com_O: np.ndarray
    inertia_O: np.ndarray
    rgba: tuple[float, float, float, float] = (0.85, 0.45, 0.2, 1.0)
    source: str = ""
    """``object set: <name>`` or the mesh file's path."""
    warnings: list[str] = field(default_factory=list)
    """Plausibility warnings (size, mass), each naming the source and a hint."""

    @property
    def model_name(self) -> str:
        return model_name(self.name)


def make_asset(name: str, mesh: trimesh.Trimesh, *, density: float = 0.0, mass: float = 0.0,
               rgba=(0.85, 0.45, 0.2, 1.0), source: str = "") -> ObjectAsset:
    """An asset from ``mesh`` (any origin: it is moved to rest on z = 0) with its mass from
    ``mass`` (kg) when positive, else ``density`` (kg/m^3; default for meshes when 0)."""
    from gbh_drake.objects.mass import mass_properties_detailed

    mesh = rest_on_ground(mesh)
    props = mass_properties_detailed(mesh, density or DEFAULT_MESH_DENSITY)
    inertia = np.asarray(props.inertia, dtype=float)
    total = float(props.mass)
    if mass > 0:
        inertia = inertia * (mass / total)
        total = float(mass)
    return ObjectAsset(name, mesh, total, np.asarray(props.com, dtype=float), inertia,
                       tuple(rgba), source)


def rest_on_ground(mesh: trimesh.Trimesh) -> trimesh.Trimesh:
    """``mesh`` translated so that its lowest point is at z = 0 and its footprint's bounding box
    is centred on x = y = 0 (a copy; the input is unchanged)."""
    lo, hi = mesh.bounds
    shift = np.array([-0.5 * (lo[0] + hi[0]), -0.5 * (lo[1] + hi[1]), -lo[2]])
    if np.allclose(shift, 0.0):
        return mesh
    moved = mesh.copy()
    moved.apply_translation(shift)
    return moved


def load_object_asset(config: ObjectConfig, base_dir: Path) -> ObjectAsset:
    """The object of ``config``: a named object of the set, or a mesh file (relative paths
    against ``base_dir``) through the same import."""
    # Imported here: the object set pulls in manifold3d and is not needed for other uses.
    from gbh_drake.objects import load_mesh_file, make_object

    if config.mesh:
        path = Path(config.mesh).expanduser()
        path = path if path.is_absolute() else Path(base_dir) / path
        mesh = load_mesh_file(path, scale=config.scale)
        asset = make_asset(path.stem, mesh, density=config.density, mass=config.mass,
                           source=str(path))
        asset.warnings = list(mesh.metadata.get("gbh_warnings", []))
        return asset
    spec = make_object(config.name)
    mesh = spec.mesh
    if config.scale != 1.0:
        mesh = mesh.copy()
        mesh.apply_scale(config.scale)
    return make_asset(spec.name, mesh, density=config.density or spec.density, mass=config.mass,
                      rgba=spec.rgba, source=f"object set: {spec.name}")


def initial_object_pose(config: ObjectConfig, asset: ObjectAsset, seed: int) -> RigidTransform:
    """X_WO at the start, from ``seed``: ``config.random_pose`` when given, else
    ``config.pose``; raised so that no part starts below the table, plus ``drop_height``."""
    if config.random_pose is not None:
        from gbh_drake.objects.placement import sample_resting_pose

        rp = config.random_pose
        X, _ = sample_resting_pose(asset.mesh, np.random.default_rng(seed), rp.x, rp.y,
                                   np.radians(rp.yaw_deg), stable=rp.stable)
        X_WO = RigidTransform(np.asarray(X))
    elif config.pose.IsDeterministic():
        X_WO = config.pose.GetDeterministicValue()
    else:
        X_WO = config.pose.Sample(RandomGenerator(seed))
    R = X_WO.rotation().matrix()
    low = float((np.asarray(asset.mesh.vertices) @ R[2]).min() + X_WO.translation()[2])
    lift = max(0.0, -low) + config.drop_height
    return RigidTransform(RotationMatrix(R), X_WO.translation() + [0.0, 0.0, lift])
