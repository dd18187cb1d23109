"""The loop's enclosure (core/enclosure.py): what the hook's loop at the measured fingers
encloses of an object's surface, on meshes whose answer is known by construction (G frame,
metres; the loop lies in the plane x_G = 0, its hole between y = -q_l and q_straight, z from
the palm, 0, to the bar, l_f = 0.08)."""

import numpy as np
import pytest
import trimesh
from gbh_shapes import cup_on_the_straight_rod, mug_on_the_bar, torus_at

from gbh_drake.core.enclosure import (
    least_width,
    loop_enclosure,
    loop_polygon,
)
from gbh_drake.core.gripper import HOOK_GRIPPER, WEDGE_GRIPPER

Q = HOOK_GRIPPER.q_closed  # 17 mm: the loop closed
LF = HOOK_GRIPPER.finger_length


def enclosure(mesh: trimesh.Trimesh, q_straight: float = Q, q_l: float = Q, **kwargs):
    mesh = mesh.copy()
    mesh.merge_vertices()
    return loop_enclosure(mesh.vertices, mesh.faces, q_straight, q_l, **kwargs)


def test_a_mug_handle_through_the_closed_loop_is_enclosed():
    e = enclosure(mug_on_the_bar())
    assert e.linked and not e.crossed and e.gap == pytest.approx(0.0, abs=1e-12)
    assert e.thickness == pytest.approx(0.010, abs=5e-4)  # the tube's section
    assert e.encloses


def test_the_same_mug_turned_off_the_bar_is_not_linked():
    """The handle's ring beside the loop, not through it: nothing crosses the loop's disc."""
    mesh = mug_on_the_bar().apply_translation([0.0, 0.0, 0.2])
    e = enclosure(mesh)
    assert not e.linked and not e.crossed and not e.encloses


def test_a_cup_wall_between_the_bar_tip_and_the_straight_rod_is_a_pinch():
    """Issue 42: the straight rod inside a cup, the bar's tip stopped on its 3.8 mm wall
    (fingers at 18.9 mm, closed at 17.0: within the old 2 mm tolerance). The loop's closure
    runs through the wall."""
    q = 0.0189
    cup = cup_on_the_straight_rod(q)
    assert cup.is_watertight
    e = enclosure(cup, q, q)
    assert e.crossed and not e.encloses
    assert e.gap == pytest.approx(0.0038, abs=1e-9)
    assert "between the bar's tip and the straight rod" in e.text()


def test_a_ring_around_the_straight_rod_pinched_at_the_bar_tip_is_not_enclosed():
    """A key ring's 3.8 mm wire around the straight rod only, held in the gap between the bar's
    tip and the rod (fingers 18.9 mm): its material is where the loop would close."""
    q = 0.0189
    ring = torus_at([0.0, q, LF], [0.0, 0.0, 1.0], q - (HOOK_GRIPPER.bar_length - q) - 0.0019,
                 0.0019)
    e = enclosure(ring, q, q)
    assert e.crossed and not e.linked and not e.encloses


def test_a_ring_threaded_on_the_closed_loop_straight_rod_is_linked():
    """The same ring slid up the straight rod, the loop closed below it: it cannot leave (the
    bar blocks the rod's tip, the hand its root): linked and enclosed."""
    ring = torus_at([0.0, Q, 0.5 * LF], [0.0, 0.0, 1.0], 0.008, 0.0019)
    e = enclosure(ring)
    assert e.linked and not e.crossed and e.encloses


def test_material_in_the_hole_that_does_not_link_the_loop():
    """A bead lying in the hole and a ring poking through it twice cross the loop's disc with a
    net count of zero: in the hole (enclosed, if they stay there) but not linked."""
    bead = trimesh.creation.icosphere(subdivisions=3, radius=0.006)
    bead.apply_translation([0.0, 0.0, 0.04])
    ring = torus_at([0.0, 0.0, 0.04], [0.0, 1.0, 0.0], 0.02, 0.004)
    for mesh, width in ((bead, 0.012), (ring, 0.008)):
        e = enclosure(mesh)
        assert not e.crossed and not e.linked and e.inside and e.encloses
        assert e.thickness == pytest.approx(width, rel=0.05)
        assert e.text() == "its material passes through the loop, which does not link it"


def test_a_rod_on_legs_hung_on_the_bar_is_enclosed_not_linked():
    """A staple (a rod on two legs, genus 0) hung by its rod on the closed bar: held by the
    loop's shape, not by the squeeze, though the loop could be slid off over a leg's end."""
    rod = trimesh.creation.cylinder(radius=0.006, height=0.16, sections=24)
    rod.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, [0, 1, 0]))
    legs = [trimesh.creation.box([0.012, 0.03, 0.07]).apply_translation([x, 0.0, 0.035 + 0.07])
            for x in (-0.07, 0.07)]
    staple = trimesh.boolean.union([rod, *legs], engine="manifold")
    staple.apply_translation([0.0, 0.0, LF - 0.004 - 0.006])  # resting on the bar
    e = enclosure(staple)
    assert e.encloses and not e.linked
    assert e.thickness == pytest.approx(0.012, rel=0.02)


@pytest.mark.parametrize(("q", "encloses"), [(0.019, True), (0.022, False)])
def test_an_open_gap_encloses_only_material_thicker_than_it(q, encloses):
    """The handle in the loop, the fingers stopped apart with nothing in the gap (held apart by
    material between the rods): a 4 mm gap keeps a 10 mm handle in, a 10 mm gap does not."""
    e = enclosure(mug_on_the_bar(), q, q)
    assert e.linked and not e.crossed
    assert e.gap == pytest.approx(2 * (q - Q), abs=1e-9)
    assert e.encloses is encloses


@pytest.mark.parametrize(("q", "clause"), [(Q, False), (Q + 1e-5, False), (0.019, True)])
def test_the_reason_names_a_gap_only_when_it_shows(q, clause):
    """A loop stopped a hundredth of a millimetre open (the physics' last digits) reads as a
    closed one; a 4 mm gap is named, with the material's thickness."""
    text = enclosure(mug_on_the_bar(), q, q).text()
    assert text.startswith("its material passes through the loop, which links it")
    assert ("mm gap, the material" in text) is clause
    assert "0.0 mm gap" not in text


def test_the_wedge_closes_at_its_sharp_edge():
    """The wedge bar's tip-most point is its outer edge (a rod's half width past the bar's
    centre line, away from the palm): its loop closes there, so a wire ring whose strand sits
    in the V between the ramp and the straight rod, just inside that edge, is enclosed."""
    polygon, gap = loop_polygon(Q, Q, 0.0, WEDGE_GRIPPER)
    r = 0.5 * WEDGE_GRIPPER.rod_width
    assert polygon[3] == pytest.approx([0.0, WEDGE_GRIPPER.bar_length - Q, LF + r])
    assert gap == pytest.approx(0.0, abs=1e-12)
    # The strand (3 mm thick) at y = 11 mm, z = 81 mm: under the ramp (at 83 mm there), 0.5 mm
    # from the straight rod's inner face (13 mm).
    ring = torus_at([0.0, 0.011, 0.081 + 0.03], [0.0, 1.0, 0.0], 0.03, 0.0015)
    e = enclosure(ring, gripper=WEDGE_GRIPPER)
    assert e.linked and not e.crossed and e.encloses


def test_least_width_of_a_section():
    square = np.array([[0, 0], [0.01, 0], [0.01, 0.01], [0, 0.01], [0.005, 0.005]])
    assert least_width(square) == pytest.approx(0.01)
    turned = square @ np.array([[np.cos(0.3), -np.sin(0.3)], [np.sin(0.3), np.cos(0.3)]])
    assert least_width(turned) == pytest.approx(0.01)
    assert least_width(np.array([[0, 0], [1, 1], [2, 2]])) == 0.0


# ---- before the grasp: the planned loop's material (GbH's loop_must_enclose rule) ----------

def _planned(mesh: trimesh.Trimesh):
    from gbh_drake.core.enclosure import planned_loop_material

    return planned_loop_material(mesh.vertices[mesh.faces], Q)


def test_a_planned_loop_round_a_handle_holds_it():
    from gbh_drake.core.enclosure import LoopMaterial

    assert _planned(mug_on_the_bar()) == LoopMaterial.HELD


def _rail(dx: float) -> trimesh.Trimesh:
    """A 10 mm rail 20 mm long along y_G, mid-finger, ``dx`` off the loop's plane."""
    rail = trimesh.creation.cylinder(radius=0.005, height=0.02, sections=24)
    rail.apply_transform(trimesh.geometry.align_vectors([0, 0, 1.0], [0, 1.0, 0]))
    return rail.apply_translation([dx, 0.0, 0.5 * LF])


@pytest.mark.parametrize("dx", [0.006, -0.012, 0.03])
def test_a_planned_loop_beside_the_material_holds_nothing(dx):
    """The rail moved off the loop's plane by more than its radius: the loop closes beside it
    (a turned grasp beside a headband); on the plane it holds it."""
    from gbh_drake.core.enclosure import LoopMaterial

    assert _planned(_rail(dx)) == LoopMaterial.EMPTY
    assert _planned(_rail(0.0)) == _planned(_rail(0.004)) == LoopMaterial.HELD


def test_a_wire_through_the_straight_rod_is_through_the_loop():
    """A 4 mm wire across the straight rod's centre line, mid-finger: the loop runs through it."""
    from gbh_drake.core.enclosure import LoopMaterial

    wire = trimesh.creation.cylinder(radius=0.002, height=0.1, sections=24)
    wire.apply_transform(trimesh.geometry.align_vectors([0, 0, 1.0], [1.0, 0, 0]))
    wire.apply_translation([0.0, Q, 0.5 * LF])
    assert _planned(wire) == LoopMaterial.THROUGH
    assert _planned(wire.copy().apply_translation([0.0, -Q, 0.0])) == LoopMaterial.HELD


def test_far_triangles_do_not_count():
    """Material beyond the loop's reach (loop_reach) is empty, whatever its shape."""
    from gbh_drake.core.enclosure import LoopMaterial, loop_reach

    centre, radius = loop_reach(Q)
    ring = torus_at(centre + [0.0, 0.0, radius + 0.03], [0.0, 1.0, 0.0], 0.02, 0.005)
    assert _planned(ring) == LoopMaterial.EMPTY
