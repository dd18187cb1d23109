"""Small watertight test shapes for the GbH core, built with trimesh and manifold3d (metres).

A plain module (not conftest) so tests and bench/bench_core.py can import it by a unique name.
"""

from __future__ import annotations

import manifold3d as m3d
import numpy as np
import trimesh

#: Ring: torus in the xy plane about +z, hole radius RING_R - RING_r.
RING_R, RING_r = 0.05, 0.01
#: Mug: cup about +z (outer radius, height), handle in the xz plane (axis +y).
CUP_RADIUS, CUP_HEIGHT = 0.04, 0.10
HANDLE_CENTER = np.array([0.052, 0.0, 0.055])
HANDLE_R, HANDLE_r = 0.026, 0.006


def _to_trimesh(solid: m3d.Manifold) -> trimesh.Trimesh:
    mesh = solid.to_mesh()
    return trimesh.Trimesh(np.asarray(mesh.vert_properties)[:, :3], np.asarray(mesh.tri_verts))


def _torus(R: float, r: float, n_major: int = 96, n_minor: int = 24) -> m3d.Manifold:
    """Torus about +z centred at the origin."""
    return m3d.Manifold.revolve(m3d.CrossSection.circle(r, n_minor).translate((R, 0.0)), n_major)


def make_ring() -> trimesh.Trimesh:
    return _to_trimesh(_torus(RING_R, RING_r))


def make_mug(segments: int = 64) -> trimesh.Trimesh:
    """Cup (open at the top, 4 mm wall, 6 mm bottom) with a D handle in the xz plane at +x."""
    cavity = m3d.Manifold.cylinder(CUP_HEIGHT, CUP_RADIUS - 0.004, circular_segments=segments)
    cup = m3d.Manifold.cylinder(CUP_HEIGHT, CUP_RADIUS, circular_segments=segments)
    cup = cup - cavity.translate((0.0, 0.0, 0.006))
    handle = _torus(HANDLE_R, HANDLE_r, segments, max(segments // 3, 12)).rotate((90.0, 0.0, 0.0))
    handle = handle.translate(tuple(HANDLE_CENTER)) - m3d.Manifold.cylinder(
        CUP_HEIGHT, CUP_RADIUS - 0.002, circular_segments=segments
    )
    return _to_trimesh(cup + handle)


def make_hook() -> trimesh.Trimesh:
    """Open half ring (radius 3 cm, 4 mm wire) in the xy plane, open toward -y: a hanger's hook."""
    half = _torus(0.03, 0.004) ^ m3d.Manifold.cube((0.1, 0.05, 0.02)).translate((-0.05, 0.0, -0.01))
    return _to_trimesh(half)


def make_bottle() -> trimesh.Trimesh:
    """Hollow bottle about +z with an open neck (2 mm wall)."""
    outer = [(0.0, 0.0), (0.035, 0.0), (0.035, 0.12), (0.012, 0.16), (0.012, 0.20), (0.0, 0.20)]
    inner = [(0.0, 0.002), (0.033, 0.002), (0.033, 0.12), (0.010, 0.158), (0.010, 0.21),
             (0.0, 0.21)]
    solid = m3d.Manifold.revolve(m3d.CrossSection([outer]), 64)
    return _to_trimesh(solid - m3d.Manifold.revolve(m3d.CrossSection([inner]), 64))


# ---- shapes held by the hook gripper, in its frame G (core/enclosure.py, the cage test) ------
def torus_at(centre, axis, major: float, minor: float) -> trimesh.Trimesh:
    """A ring of tube radius ``minor`` about ``axis`` (unit) through ``centre``."""
    ring = trimesh.creation.torus(major_radius=major, minor_radius=minor, major_sections=96,
                                  minor_sections=24)
    ring.apply_transform(trimesh.geometry.align_vectors([0.0, 0.0, 1.0], np.asarray(axis)))
    ring.apply_translation(centre)
    return ring


def mug_on_the_bar(finger_length: float = 0.08) -> trimesh.Trimesh:
    """A mug hung by its ring handle from the hook's bar, in G: the ring (tube 10 mm thick) in
    the x-z plane around the bar (z = ``finger_length``), its top through the loop's hole at
    z = l_f - 30 mm, its body beside the loop (x from 27 mm on)."""
    handle = torus_at([0.0, 0.0, finger_length], [0.0, 1.0, 0.0], 0.030, 0.005)
    body = trimesh.creation.cylinder(radius=0.040, height=0.100, sections=64)
    body.apply_translation([0.067, 0.0, finger_length])
    return trimesh.boolean.union([handle, body], engine="manifold")


def cup_on_the_straight_rod(q: float, bar_length: float = 0.03) -> trimesh.Trimesh:
    """A cup (outer radius 40 mm, 3.8 mm wall, 4 mm bottom, 100 mm tall) in G with the
    straight rod inside it, its rim at z = 40 mm toward the palm and the outer face of its wall
    on the bar's tip face (fingers at ``q``: y = ``bar_length`` - q)."""
    outer = trimesh.creation.cylinder(radius=0.040, height=0.100, sections=96)
    inner = trimesh.creation.cylinder(radius=0.0362, height=0.100, sections=96)
    inner.apply_translation([0.0, 0.0, -0.004])
    cup = trimesh.boolean.difference([outer, inner], engine="manifold")
    return cup.apply_translation([0.0, bar_length - q + 0.040, 0.090])
