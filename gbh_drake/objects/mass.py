"""Mass properties of a mesh of uniform density (kg, metres, frame of the mesh).

* A single watertight, consistently wound body: exact integrals over the closed surface
  (trimesh's mass properties).
* Anything else (open surfaces, several overlapping shells like pybullet's mug, whose handle is an
  open tube stuck into the cup): a voxel fill. The surface is voxelised at ``pitch`` (default: the
  largest extent / 100), gaps of up to ~2 voxels are closed (dilate, fill, erode), the enclosed
  voxels are filled, and each filled voxel is a solid cube. Overlapping shells are thus counted
  once and small holes in a surface are bridged. Error: about one voxel layer on the surface
  (walls read up to ~half a voxel thicker), so a 4 mm mug wall at 1 mm voxels is within ~25 %;
  a surface with a hole wider than ~2 voxels leaks and becomes a one-voxel-thick skin. The convex
  hull was rejected: it fills a mug's inside and its handle's hole.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import trimesh
from scipy import ndimage

from gbh_drake.core.arguments import argument_problem
from gbh_drake.core.ranges import is_number


@dataclass(frozen=True)
class MassProperties:
    """``mass`` (kg), ``com`` (3,) (m), ``inertia`` (3, 3) about the CoM (kg m^2), ``method``
    (``"exact"`` or ``"voxel"``) and ``density`` (kg/m^3; with a given total mass, the uniform
    density that gives it)."""

    mass: float
    com: np.ndarray
    inertia: np.ndarray
    method: str
    density: float | None = None


def is_exact_solid(mesh: trimesh.Trimesh) -> bool:
    """True if the mesh is one closed, consistently wound body of positive volume."""
    return bool(
        mesh.is_watertight
        and mesh.is_winding_consistent
        and mesh.body_count == 1
        and mesh.volume > 0
    )


def mass_properties_detailed(
    mesh: trimesh.Trimesh, density: float, pitch: float | None = None
) -> MassProperties:
    """Mass, centre of mass and inertia about the CoM of ``mesh`` at ``density`` (kg/m^3)."""
    if density <= 0:
        raise ValueError(f"density must be positive, got {density}")
    if is_exact_solid(mesh):
        props = trimesh.triangles.mass_properties(mesh.triangles, density=density)
        return MassProperties(
            float(props.mass), np.asarray(props.center_mass), np.asarray(props.inertia), "exact",
            float(density),
        )
    return _voxel_mass_properties(mesh, density, pitch)


def mass_properties_for(
    mesh: trimesh.Trimesh,
    *,
    density: float | None = None,
    mass: float | None = None,
    pitch: float | None = None,
) -> MassProperties:
    """Mass properties of ``mesh`` (uniform material) from either a ``density`` (kg/m^3) or a
    total ``mass`` (kg); give exactly one.

    With ``mass``, the body is the same uniform solid (same centre of mass, same method: exact or
    voxel fill) at the density that gives that mass: the inertia of the density-based solution is
    scaled by ``mass / (its mass)``. Use it when the mesh is filled but the real object is hollow
    (a scanned mug): the mass is then right, the inertia that of a uniform solid of that mass.
    """
    if (density is None) == (mass is None):
        raise ValueError("give exactly one of density (kg/m^3) or mass (kg)")
    for name, value in (("density", density), ("mass", mass)):
        if value is not None and not is_number(value):
            raise TypeError(argument_problem("mass_properties_for", name, "a number", value))
    if density is not None:
        if not (np.isfinite(density) and density > 0):
            raise ValueError(f"density must be positive and finite, got {density}")
        return mass_properties_detailed(mesh, float(density), pitch)
    if not (np.isfinite(mass) and mass > 0):
        raise ValueError(f"mass must be positive and finite, got {mass}")
    unit = mass_properties_detailed(mesh, 1.0, pitch)
    factor = float(mass) / unit.mass
    return MassProperties(float(mass), unit.com, unit.inertia * factor, unit.method, factor)


def mass_properties(
    mesh: trimesh.Trimesh, density: float, pitch: float | None = None
) -> tuple[float, np.ndarray, np.ndarray]:
    """``(mass kg, com (3,) m, inertia about the com (3, 3) kg m^2)``; see the module docstring
    for the fallback used when the mesh is not one watertight body."""
    p = mass_properties_detailed(mesh, density, pitch)
    return p.mass, p.com, p.inertia


def _voxel_mass_properties(
    mesh: trimesh.Trimesh, density: float, pitch: float | None
) -> MassProperties:
    if pitch is None:
        pitch = float(np.max(mesh.extents)) / 100.0
    centres = filled_voxel_centres(mesh, pitch)
    if len(centres) == 0:
        raise ValueError("voxel fill is empty: the mesh has no volume at this pitch")
    cell_mass = density * pitch**3
    mass = cell_mass * len(centres)
    com = centres.mean(axis=0)
    r = centres - com
    inertia = cell_mass * (np.eye(3) * np.einsum("ij,ij->", r, r) - r.T @ r)
    inertia += np.eye(3) * mass * pitch**2 / 6.0  # each cube's own inertia
    return MassProperties(float(mass), com, inertia, "voxel", float(density))


def filled_voxel_centres(mesh: trimesh.Trimesh, pitch: float, closing: int = 1) -> np.ndarray:
    """Centres ``(n, 3)`` (m) of the voxels of size ``pitch`` inside or on the surface.

    The surface is rasterised by a regular barycentric lattice on each triangle (spacing under
    half a voxel), gaps up to ``2 closing`` voxels are closed morphologically, and the enclosed
    space is filled. Deterministic.
    """
    tri = np.asarray(mesh.triangles, dtype=np.float64)
    edges = np.linalg.norm(tri - np.roll(tri, 1, axis=1), axis=2).max(axis=1)
    steps = np.maximum(1, np.ceil(edges / (0.45 * pitch))).astype(int)
    points = [tri.reshape(-1, 3)]
    for k in np.unique(steps[steps > 1]):
        i, j = np.meshgrid(np.arange(k + 1), np.arange(k + 1), indexing="ij")
        keep = i + j <= k
        bary = np.column_stack([i[keep], j[keep], k - i[keep] - j[keep]]) / k
        points.append(np.einsum("bk,tkd->tbd", bary, tri[steps == k]).reshape(-1, 3))
    points = np.vstack(points)
    pad = closing + 2
    origin = points.min(axis=0) - pad * pitch
    index = np.floor((points - origin) / pitch).astype(np.int64)
    grid = np.zeros(index.max(axis=0) + pad + 1, dtype=bool)
    grid[tuple(index.T)] = True
    solid = ndimage.binary_dilation(grid, iterations=closing) if closing else grid
    solid = ndimage.binary_fill_holes(solid)
    if closing:
        solid = ndimage.binary_erosion(solid, iterations=closing, border_value=0) | grid
    return origin + (np.argwhere(solid) + 0.5) * pitch
