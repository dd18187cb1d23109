"""A user's mesh file made into an object that behaves like a real one: one call.

:func:`load_mesh_object` = :func:`~gbh_drake.objects.mesh_io.load_mesh_file` (import, repair,
refuse with a clear message) + mass properties from a density or a given mass
(:func:`~gbh_drake.objects.mass.mass_properties_for`) + resting placement in frame O
(:func:`~gbh_drake.objects.placement.rest_on_table`) + plausibility warnings with hints
(:func:`~gbh_drake.objects.plausibility.plausibility_warnings`). :func:`prepare_mesh_object`
does the same for a mesh already in memory.
"""

from __future__ import annotations

import copy
import logging
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import trimesh

from gbh_drake.core.arguments import require
from gbh_drake.objects.mass import MassProperties, mass_properties_for
from gbh_drake.objects.mesh_io import load_mesh_file
from gbh_drake.objects.placement import Placement, rest_on_table
from gbh_drake.objects.plausibility import plausibility_warnings

log = logging.getLogger(__name__)

DEFAULT_MESH_DENSITY = 600.0
"""kg/m^3 used when neither a density nor a mass is given (a light wood or dense plastic)."""


@dataclass(frozen=True)
class MeshObject:
    """A mesh ready to simulate.

    ``mesh``: in frame O (m), resting on z = 0, x-y centred (see ``placement``). ``X_OF`` (4, 4):
    p_O = X_OF p_F from the file's frame F (move ground truth given in F with it).
    ``mass_properties``: mass (kg), com (3,) and inertia about the com (3, 3) in O, ``method``,
    ``density`` (the given one, or the one that gives the given mass). ``warnings``: every
    warning of the import, the placement and the plausibility checks, each
    ``"<source>: ..."``, without repeats. ``source``: the file (or name) in the messages.
    """

    mesh: trimesh.Trimesh
    X_OF: np.ndarray
    mass_properties: MassProperties
    placement: Placement
    warnings: list[str]
    source: str


def load_mesh_object(
    path,
    *,
    scale: float = 1.0,
    density: float | None = None,
    mass: float | None = None,
    orientation: str = "keep",
    center: str = "footprint",
) -> MeshObject:
    """Load ``path`` (any supported mesh file; ``scale`` to metres) and prepare it; see
    :func:`prepare_mesh_object`. Raises :class:`~gbh_drake.objects.mesh_io.MeshImportError`
    for a file that cannot be used.

    The last few results are kept per process (keyed by the file's path, size and modification
    time and the arguments), so that checking a scenario and building its station import a
    user's mesh once; each call gets its own copy."""
    require("load_mesh_object", "path", path, (str, os.PathLike), "a mesh file's path (a str or Path)")
    try:
        stat = Path(path).stat()
        key = (str(Path(path).resolve()), stat.st_size, stat.st_mtime_ns, scale, density, mass,
               orientation, center, str(path))
    except (OSError, TypeError, ValueError):  # the import says what is wrong with the path
        key = None
    if key in _LOADED:
        return copy.deepcopy(_LOADED[key])
    loaded = prepare_mesh_object(load_mesh_file(path, scale=scale), source=str(path),
                                 scale=scale, density=density, mass=mass,
                                 orientation=orientation, center=center)
    if key is not None:
        while len(_LOADED) >= _LOADED_SIZE:
            _LOADED.pop(next(iter(_LOADED)))
        _LOADED[key] = copy.deepcopy(loaded)
    return loaded


#: Mesh objects already loaded in this process (see :func:`load_mesh_object`).
_LOADED: dict[tuple, MeshObject] = {}
_LOADED_SIZE = 4


def prepare_mesh_object(
    mesh_F: trimesh.Trimesh,
    *,
    source: str,
    scale: float = 1.0,
    density: float | None = None,
    mass: float | None = None,
    orientation: str = "keep",
    center: str = "footprint",
) -> MeshObject:
    """Mass properties, resting frame O and warnings of ``mesh_F`` (frame F, m).

    Give ``mass`` (kg) or ``density`` (kg/m^3), not both; with neither, DEFAULT_MESH_DENSITY.
    With ``mass`` the density is the one giving it and no solid-filled warning is made.
    ``orientation`` and ``center``: see :func:`~gbh_drake.objects.placement.rest_on_table`.
    ``scale``: the scale already applied (for the warnings' hints). ``mesh_F`` is not modified.
    """
    if density is not None and mass is not None:
        raise ValueError(f"{source}: give either mass or density, not both")
    if density is None and mass is None:
        density = DEFAULT_MESH_DENSITY
    props_F = mass_properties_for(mesh_F, density=density, mass=mass)
    placed = rest_on_table(mesh_F, com=props_F.com, center=center, orientation=orientation)
    R = placed.X_OF[:3, :3]
    props = MassProperties(props_F.mass, placed.com_O.copy(), R @ props_F.inertia @ R.T,
                           props_F.method, props_F.density)
    loaded = [f"{source}: {w}" for w in mesh_F.metadata.get("gbh_warnings", [])]
    new = [f"{source}: {w}" for w in placed.warnings]
    new += plausibility_warnings(placed.mesh, props.mass, source, density=density, scale=scale)
    new = [w for w in dict.fromkeys(new) if w not in loaded]
    for w in new:
        log.warning("%s", w)
    placed.mesh.metadata["gbh_warnings"] = list(mesh_F.metadata.get("gbh_warnings", []))
    placed.mesh.metadata["source_path"] = source
    return MeshObject(placed.mesh, placed.X_OF, props, placed, loaded + new, source)
