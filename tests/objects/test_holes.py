"""Ground-truth hangable parts admit the hook gripper's rods and cage thin material."""

import numpy as np
import open3d as o3d
import pytest

from gbh_drake.core.gripper import HookGripperGeometry
from gbh_drake.objects import list_objects
from gbh_drake.objects.holes import plane_basis

GRIPPER = HookGripperGeometry()
ROD_RADIUS = GRIPPER.rod_width / np.sqrt(2.0)  # half diagonal of the square rod
CLEARANCE = 0.003
MIN_CLEAR_DIAMETER = 0.025
CAGE_GAP = 0.025  # what fits between the closed rods (~2.6 cm clear)


def _scene(mesh):
    scene = o3d.t.geometry.RaycastingScene()
    scene.add_triangles(
        o3d.core.Tensor(np.asarray(mesh.vertices, dtype=np.float32)),
        o3d.core.Tensor(np.asarray(mesh.faces, dtype=np.uint32)),
    )
    return scene


def _cast(scene, origins, directions):
    rays = np.hstack([origins, directions]).astype(np.float32)
    return scene.cast_rays(o3d.core.Tensor(rays))["t_hit"].numpy()


def _disc(center, axis, radius, n_rings=4, n_around=24):
    e1, e2 = plane_basis(axis)
    pts = [center]
    for r in np.linspace(radius / n_rings, radius, n_rings):
        t = 2 * np.pi * np.arange(n_around) / n_around
        pts.append(center + r * (np.outer(np.cos(t), e1) + np.outer(np.sin(t), e2)))
    return np.vstack(pts)


def _parts(specs):
    return [(n, p) for n in list_objects() for p in specs[n].hangable_parts]


@pytest.fixture(scope="module")
def scenes(specs):
    return {n: _scene(s.mesh) for n, s in specs.items()}


def test_every_part_is_well_formed(specs):
    for name, part in _parts(specs):
        assert part.kind in ("closed", "open"), name
        assert np.linalg.norm(part.axis_O) == pytest.approx(1.0)
        assert part.clear_diameter >= MIN_CLEAR_DIAMETER, (name, part.name, part.clear_diameter)


@pytest.mark.parametrize("name", [n for n in list_objects() if n not in ("ball", "box", "bottle",
                                                                          "can")])
def test_rods_pass_along_the_axis(specs, scenes, name):
    for part in specs[name].hangable_parts:
        for radius in (ROD_RADIUS + CLEARANCE, 0.95 * 0.5 * part.clear_diameter):
            pts = _disc(part.center_O, part.axis_O, radius)
            for sign in (1.0, -1.0):
                d = sign * part.axis_O
                t = _cast(scenes[name], pts - 2.0 * d, np.tile(d, (len(pts), 1)))
                assert np.all(np.isinf(t)), (name, part.name, radius, sign)


def test_centres_are_in_free_space(specs, scenes):
    for name, part in _parts(specs):
        c = o3d.core.Tensor(part.center_O[None].astype(np.float32))
        distance = float(scenes[name].compute_distance(c).numpy()[0])
        assert distance >= 0.45 * part.clear_diameter, (name, part.name, distance)
        if specs[name].mesh.is_watertight:
            assert float(scenes[name].compute_occupancy(c).numpy()[0]) == 0.0


def _material_extents(scene, center, axis, n_dirs=36):
    """For rays from the centre in the loop plane: (radial thickness, extent along the axis,
    distance from the centre to the far side) of the first material hit, or None."""
    e1, e2 = plane_basis(axis)
    out = []
    for t in 2 * np.pi * np.arange(n_dirs) / n_dirs:
        d = np.cos(t) * e1 + np.sin(t) * e2
        t_in = _cast(scene, center[None], d[None])[0]
        if not np.isfinite(t_in) or t_in > 0.3:
            continue
        eps = 1e-5
        t_out = _cast(scene, (center + (t_in + eps) * d)[None], d[None])[0] + eps
        q = center + (t_in + 0.5 * t_out) * d
        along = _cast(scene, np.array([q, q]), np.array([axis, -axis])).sum()
        out.append((t_out, along, t_in + t_out))
    return out


def test_material_fits_in_the_closed_loop(specs, scenes):
    """Some side of every hole is thin enough to be caged: one of the material's two extents
    (across, along the axis) fits between the closed rods, the other within the finger length,
    and its far side is within reach of the fingers from the centre."""
    for name, part in _parts(specs):
        extents = _material_extents(scenes[name], part.center_O, part.axis_O)
        assert extents, (name, part.name)
        ok = [
            min(r, a) <= CAGE_GAP and max(r, a) <= GRIPPER.finger_length
            and far <= GRIPPER.finger_length
            for r, a, far in extents
        ]
        assert any(ok), (name, part.name, extents[:4])
