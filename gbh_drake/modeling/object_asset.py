"""The object of a scenario: its mesh resting on the table, its mass properties, its start pose.

:func:`load_object_asset` reads a named object of the set or any mesh file, places it so that
it rests on the plane z = 0 of its frame O whatever the file's origin, computes its mass
properties (from a density or a given mass) and collects plausibility warnings (size, mass) that
name the source and hint at the fix. :func:`initial_object_pose` draws X_WO from the seed: a
fixed or distributed ``schema.Transform``, or a random stable resting pose; either way the object
never starts inside the table.
"""

from __future__ import annotations

import copy
import dataclasses
import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import trimesh
from pydrake.common import RandomGenerator
from pydrake.math import RigidTransform

from gbh_drake.modeling.object_config import ObjectConfig
from gbh_drake.modeling.object_sdf import model_name

#: A mesh file's colour in the scene (the built-in objects have their own).
MESH_RGBA = (0.85, 0.45, 0.2, 1.0)


@dataclass
class ObjectAsset:
    """An object ready for the plant: mesh in its frame O (metres, resting on z = 0), mass
    properties (kg, m, kg m^2 about the CoM in O), colour, where it came from."""

    name: str
    mesh: trimesh.Trimesh
    mass: float
    com_O: np.ndarray
    inertia_O: np.ndarray
    rgba: tuple[float, float, float, float] = MESH_RGBA
    source: str = ""
    """``object set: <name>`` or the mesh file's path."""
    warnings: list[str] = field(default_factory=list)
    """Plausibility warnings (size, mass), each naming the source and a hint."""
    hangable_parts: list = field(default_factory=list)
    """Ground truth of a named object or of an object set's (``HangablePart``: hole centre and
    axis in O, kind, clear diameter); empty for a mesh file (unknown). For judging what GbH
    found, never for planning."""
    natural_rest: object = None
    """The declared natural rest (``NaturalRest``), None for a mesh file."""

    @property
    def model_name(self) -> str:
        return model_name(self.name)


def make_asset(name: str, mesh: trimesh.Trimesh, *, density: float = 0.0, mass: float = 0.0,
               rgba=MESH_RGBA, source: str = "") -> ObjectAsset:
    """An asset from ``mesh`` in memory (any origin: it is placed to rest on z = 0, centred on
    its footprint) with its mass from ``mass`` (kg) when positive, else ``density`` (kg/m^3;
    600 when 0), and the plausibility warnings of an imported mesh."""
    from gbh_drake.objects import prepare_mesh_object

    prepared = prepare_mesh_object(mesh, source=source or name, density=density or None,
                                   mass=mass or None)
    return _asset(name, prepared, rgba, source)


def _asset(name: str, prepared, rgba, source: str) -> ObjectAsset:
    props = prepared.mass_properties
    return ObjectAsset(name, prepared.mesh, float(props.mass), np.asarray(props.com, float),
                       np.asarray(props.inertia, float), tuple(rgba), source,
                       list(prepared.warnings))


def load_object_asset(config: ObjectConfig, base_dir: Path) -> ObjectAsset:
    """The object of ``config``: a named object of the built-in set or of an object set
    (``config.set``, :mod:`gbh_drake.objects.sets`), or a mesh file (relative paths against
    ``base_dir``) placed resting on the table, with plausibility warnings (size, mass) that
    name the file and hint at ``scale``, ``mass`` or ``density``."""
    # Imported here: the object set pulls in manifold3d and is not needed for other uses.
    from gbh_drake.objects import load_mesh_object, make_object, mass_properties_for

    if config.set:  # (the manifest's path made plain: messages name it)
        return _set_asset(config, Path(os.path.normpath(_resolve(config.set, base_dir))))
    if config.mesh:
        path = _resolve(config.mesh, base_dir)
        prepared = load_mesh_object(path, scale=config.scale, density=config.density or None,
                                    mass=config.mass or None, orientation=config.orientation)
        return _without_warnings_as_given(_asset(path.stem, prepared, MESH_RGBA, str(path)),
                                          prepared, config)
    spec = make_object(config.name)
    mesh = spec.mesh
    if config.scale != 1.0:
        mesh = mesh.copy()
        mesh.apply_scale(config.scale)
    if config.mass > 0:
        props = mass_properties_for(mesh, mass=config.mass)
    else:
        props = mass_properties_for(mesh, density=config.density or spec.density)
    parts = list(spec.hangable_parts)
    if config.scale != 1.0:
        parts = [dataclasses.replace(p, center_O=p.center_O * config.scale,
                                     clear_diameter=p.clear_diameter * config.scale)
                 for p in parts]
    return ObjectAsset(spec.name, mesh, float(props.mass), np.asarray(props.com, float),
                       np.asarray(props.inertia, float), tuple(spec.rgba),
                       f"object set: {spec.name}", hangable_parts=parts,
                       natural_rest=spec.natural_rest)


def _resolve(path: str, base_dir: Path) -> Path:
    p = Path(path).expanduser()
    return p if p.is_absolute() else Path(base_dir) / p


def _without_warnings_as_given(asset: ObjectAsset, prepared, config: ObjectConfig) -> ObjectAsset:
    """A mesh started in one of its stable resting poses: whether it would stand as given in
    its file does not matter (those warnings are dropped)."""
    if config.random_pose is not None and config.random_pose.stable:
        as_given = {f"{prepared.source}: {w}" for w in prepared.placement.warnings}
        asset.warnings = [w for w in asset.warnings if w not in as_given]
    return asset


def _set_asset(config: ObjectConfig, manifest: Path) -> ObjectAsset:
    """The object ``config.name`` of the object set at ``manifest``: a built-in object, or its
    mesh with the set's scale and mass, turned into its natural rest (frame O is that rest, as
    the built-in objects are modelled in theirs), with its ground truth moved from the file's
    frame into O. A mesh that cannot be imported or simulated, or that makes an object heavier
    than the arm's payload, raises :class:`~gbh_drake.objects.sets.ObjectSetError` naming the
    manifest, the entry and the field. The last few are kept per process (a scenario's check
    and its station load the same object)."""
    from gbh_drake.objects.sets import load_object_set

    try:
        stamp = manifest.stat().st_mtime_ns
    except OSError:
        stamp = None
    key = (str(manifest.resolve()), stamp, config.name)
    if key not in _SET_ASSETS:
        object_set = load_object_set(manifest)
        obj = object_set.object(config.name)
        if obj.builtin:
            asset = load_object_asset(dataclasses.replace(config, set="", name=obj.builtin),
                                      manifest)
        else:
            asset = _mesh_entry_asset(obj, object_set.rest_mesh(config.name))
            object_set.check_payload(config.name, asset.mass)
        while len(_SET_ASSETS) >= 8:
            _SET_ASSETS.pop(next(iter(_SET_ASSETS)))
        _SET_ASSETS[key] = asset
    asset = copy.deepcopy(_SET_ASSETS[key])
    if config.random_pose is not None and config.random_pose.stable and \
            config.random_pose.rest != "natural":
        # A stable draw: how it rests as modelled does not matter.
        asset.warnings = [w for w in asset.warnings if not _as_given(w)]
    return asset


_SET_ASSETS: dict[tuple, ObjectAsset] = {}


def _as_given(warning: str) -> bool:
    """Whether ``warning`` is about how the mesh rests as given (its placement's)."""
    return any(words in warning for words in ("as given", "off its nearest stable face"))


def _mesh_entry_asset(obj, mesh: trimesh.Trimesh) -> ObjectAsset:
    """An object set's mesh entry (``SetObject``) as an asset, from its ``mesh`` in its natural
    rest (:meth:`~gbh_drake.objects.sets.ObjectSet.rest_mesh`)."""
    from gbh_drake.objects import prepare_mesh_object
    from gbh_drake.objects.sets import natural_rest_of, parts_in_file_frame, rest_transform
    from gbh_drake.objects.spec import NaturalRest

    entry = obj.entry
    rest = natural_rest_of(entry)
    X_RF = rest_transform(entry)
    prepared = prepare_mesh_object(mesh, source=str(obj.mesh_path), scale=entry.scale,
                                   density=entry.density or None, mass=entry.mass or None)
    asset = _asset(obj.name, prepared, MESH_RGBA, f"object set {obj.set_name}: {obj.name}")
    X_OF = prepared.X_OF @ X_RF
    R, p = X_OF[:3, :3], X_OF[:3, 3]
    asset.hangable_parts = [dataclasses.replace(part, center_O=R @ part.center_O + p,
                                                axis_O=R @ part.axis_O)
                            for part in parts_in_file_frame(entry)]
    asset.natural_rest = None if rest is None else NaturalRest((0.0, 0.0, 0.0), rest.reason)
    return asset


def initial_object_pose(config: ObjectConfig, asset: ObjectAsset, seed: int) -> RigidTransform:
    """X_WO at the start, from ``seed``: ``config.random_pose`` when given (a stable resting
    pose by its probability, the object's declared natural rest (``rest: natural``) or as
    modelled, a yaw and a position), else ``config.pose``; either
    way the lowest point is put on the table (never inside it), plus ``drop_height``."""
    from gbh_drake.objects import lift_to_table, sample_resting_pose

    if config.random_pose is not None:
        rp = config.random_pose
        R_rest = None
        if rp.rest == "natural":
            if asset.natural_rest is None:
                raise ValueError(f"object.random_pose.rest: natural: {asset.source} has no "
                                 "natural rest declared")
            R_rest = asset.natural_rest.R
        X, _ = sample_resting_pose(asset.mesh, np.random.default_rng(seed), rp.x, rp.y,
                                   np.radians(rp.yaw_deg), com=asset.com_O,
                                   orientation="stable" if rp.stable and R_rest is None
                                   else "natural", R_rest=R_rest)
    else:
        pose = config.pose
        X_WO = pose.GetDeterministicValue() if pose.IsDeterministic() else \
            pose.Sample(RandomGenerator(seed))
        X = lift_to_table(asset.mesh, X_WO.GetAsMatrix4(), z_table=X_WO.translation()[2]
                          if X_WO.translation()[2] > 0 else 0.0)
    X = np.array(X, dtype=float)
    X[2, 3] += config.drop_height
    return RigidTransform(X)
