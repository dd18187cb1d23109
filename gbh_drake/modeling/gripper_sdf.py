"""Generates ``models/hook_gripper.sdf`` from :mod:`gbh_drake.core.gripper`.

The model: link ``panda_hand`` (the Franka hand, frame H = Franka's hand frame, welded to the
arm's flange ``panda_link8`` with a -45 deg yaw), a frame ``G`` (the gripper frame of
:mod:`gbh_drake.core.gripper`) at the palm, two prismatic fingers, ``straight_finger`` moving
along +y_G and ``l_finger`` moving along -y_G, each joint position being ``q`` of the geometry
module (so the opening is ``2 q``), and the L rod's horizontal ``bar`` on a revolute joint
``bar_joint`` at the bend p3 (about +x_G): at 0 the bar is deployed (the paper's hook), at
-pi/2 it is folded back onto the L rod, which makes the hand a plain two-rod gripper (the joint
the paper proposes in Sec. 4, used by the antipodal baseline and the GbH fallback).

The fingers close until something stops them: the material they squeeze, or the hand's width
command: with the bar deployed the command is q_closed, where the bar's tip meets the straight
rod and the loop is closed (the two do not collide: the command is the stop, as a Franka hand's
grasp(width)); the joints' own lower limit is where the two rods touch, for the two-rod
gripper. Their actuators' effort limit is Franka's peak grasp force; the hand driver
(:mod:`gbh_drake.systems.hand_driver`) sets the grasp force below it. Collision geometry is the
solid model of the geometry module (boxes), with compliant-hydroelastic properties; visuals add
Franka's hand and finger meshes.

The wedge variant (:data:`~gbh_drake.core.gripper.WEDGE_GRIPPER`, beyond the paper, for the
scoop) is written beside it as ``models/hook_gripper_wedge.sdf``: the same model whose bar is
the wedge prism of :meth:`~gbh_drake.core.gripper.HookGripperGeometry.bar_profile_pivot` (a
convex mesh, ``models/hook_gripper_wedge_bar.obj``, compliant like the boxes).

Run ``python -m gbh_drake.modeling.gripper_sdf`` to rewrite the files; a test checks they are
current.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from gbh_drake import MODELS_DIR
from gbh_drake.core.gripper import (
    BAR_DEPLOYED,
    BAR_RETRACTED,
    HOOK_GRIPPER,
    WEDGE_GRIPPER,
    Box,
    HookGripperGeometry,
)
from gbh_drake.modeling.sdf_text import (
    box_geometry,
    box_inertia,
    hydroelastic,
    inertial,
    material,
    mesh_geometry,
    pose,
)

GRIPPER_SDF = MODELS_DIR / "hook_gripper.sdf"
#: The wedge variant and its bar's mesh (``robot.gripper: wedge``).
WEDGE_GRIPPER_SDF = MODELS_DIR / "hook_gripper_wedge.sdf"
WEDGE_BAR_OBJ = MODELS_DIR / "hook_gripper_wedge_bar.obj"
#: Franka's finger, a copy of pybullet's collision mesh (tools/make_panda_urdf.py).
FRANKA_FINGER = "package://gbh_drake/franka/finger.obj"
#: Compliant modulus (Pa) of the rods, bar and hand.
GRIPPER_MODULUS = 5e7
#: Friction coefficient (static = dynamic) of the rods', bar's and hand's surface. The paper's
#: rods are metal or printed plastic; against ceramic or plastic objects such pairs have
#: coefficients of about 0.3-0.5 (e.g. steel on nylon 0.3-0.5, PLA on PLA about 0.35-0.5;
#: engineering tables such as the Engineering ToolBox's "friction coefficients"). Drake combines
#: two surfaces' coefficients as 2 mu1 mu2 / (mu1 + mu2): with objects at 0.4 the pair is 0.4.
GRIPPER_MU = 0.4
#: Effort limit (N) of each finger's actuator: Franka's peak grasp force.
FINGER_EFFORT_LIMIT = 140.0
#: Effort limit (N m) of the bar's actuator (a small servo; 10 N m holds 330 N at the bar's tip).
BAR_EFFORT_LIMIT = 10.0
#: Mass (kg) of the bar.
BAR_MASS = 0.01
ROD_RGBA = (0.55, 0.57, 0.6, 1.0)


def _box_element(kind: str, box: Box, frame: str, rgba) -> str:
    """A visual or collision element for ``box`` expressed in ``frame``."""
    body = box_geometry(box.size)
    if kind == "visual":
        return (f'<visual name="{box.name}_visual">{pose(box.center, relative_to=frame)}'
                f"{body}{material(rgba)}</visual>")
    props = hydroelastic("compliant", modulus=GRIPPER_MODULUS, mu=GRIPPER_MU)
    return (f'<collision name="{box.name}">{pose(box.center, relative_to=frame)}'
            f"{body}{props}</collision>")


def _finger_link(name: str, boxes: list[Box], sign: float, mass: float, frame: str) -> str:
    # Visual: Franka's finger at the finger frame (the L finger's mirrored by a half turn).
    yaw = 0.0 if sign > 0 else np.pi
    mesh_visual = (f'<visual name="{name}_franka_finger">{pose(rpy=(0, 0, yaw), relative_to=frame)}'
                   f"{mesh_geometry(FRANKA_FINGER)}</visual>")
    elements = [mesh_visual]
    for b in boxes:
        elements.append(_box_element("visual", b, frame, ROD_RGBA))
        elements.append(_box_element("collision", b, frame, ROD_RGBA))
    rod = boxes[0]
    return (
        f'<link name="{name}">{pose(relative_to=frame)}'
        f"{inertial(mass, rod.center, box_inertia(mass, rod.size))}"
        + "".join(elements)
        + "</link>"
    )


def make_gripper_sdf(geometry: HookGripperGeometry = HOOK_GRIPPER,
                     bar_mesh: str = f"package://gbh_drake/{WEDGE_BAR_OBJ.name}") -> str:
    """The SDFormat text of the hook gripper for ``geometry`` (a wedge bar, ``ramp`` > 0,
    is the mesh ``bar_mesh``: :func:`wedge_bar_obj`'s text)."""
    g = geometry
    hand = g.hand_box()
    props = hydroelastic("compliant", modulus=GRIPPER_MODULUS, mu=GRIPPER_MU)
    palm = (0.0, 0.0, g.palm_offset_in_hand)
    hand_com = np.asarray(hand.center) + palm
    parts = [
        '<?xml version="1.0"?>',
        "<!-- Generated by gbh_drake/modeling/gripper_sdf.py from gbh_drake/core/gripper.py. -->",
        '<sdf version="1.9">',
        '<model name="hook_gripper">',
        '<link name="panda_hand">',
        inertial(g.hand_mass, hand_com, box_inertia(g.hand_mass, hand.size)),
        f'<visual name="franka_hand">{mesh_geometry("package://gbh_drake/franka/hand.obj")}'
        f"{material((0.95, 0.95, 0.95, 1.0))}</visual>",
        f'<collision name="hand">{pose(hand_com)}{box_geometry(hand.size)}{props}</collision>',
        "</link>",
        f'<frame name="G" attached_to="panda_hand">{pose(palm, relative_to="panda_hand")}</frame>',
    ]
    l_rod, bar = g.l_finger_boxes()[:2]  # (a wedge's nose is part of the bar's mesh)
    fingers = (
        ("straight_finger", g.straight_finger_boxes(), +1.0),
        ("l_finger", [l_rod], -1.0),
    )
    for name, boxes, sign in fingers:
        parts.append(f'<frame name="{name}_zero" attached_to="G">{pose(relative_to="G")}</frame>')
        parts.append(_finger_link(name, boxes, sign, g.finger_mass, f"{name}_zero"))
        parts.append(
            f'<joint name="{name}_joint" type="prismatic">'
            f"<parent>panda_hand</parent><child>{name}</child>"
            f'<axis><xyz expressed_in="G">0 {sign:g} 0</xyz>'
            f"<limit><lower>{0.5 * g.rod_width:.9g}</lower><upper>{g.q_open:.9g}</upper>"
            f"<effort>{FINGER_EFFORT_LIMIT:g}</effort><velocity>0.2</velocity></limit>"
            "<dynamics><damping>0</damping></dynamics></axis></joint>"
        )
    parts += _bar(g, bar, bar_mesh)
    # The loop closes where the hand's width command stops the fingers (q_closed, as Franka's
    # grasp(width) does), not through a contact between the bar's tip and the straight rod: that
    # compliant-compliant contact surface had ~46 polygons under the 70 N squeeze and made the
    # carry several times slower.
    parts.append('<drake:collision_filter_group name="loop_closure">'
                 "<drake:member>bar</drake:member><drake:member>straight_finger</drake:member>"
                 "<drake:ignored_collision_filter_group>loop_closure"
                 "</drake:ignored_collision_filter_group></drake:collision_filter_group>")
    parts += ["</model>", "</sdf>", ""]
    return "\n".join(parts)


def _bar(g: HookGripperGeometry, bar: Box, bar_mesh: str) -> list[str]:
    """The bar as its own link on a revolute joint at the bend p3 of the L rod (about +x_G): a
    box, or the wedge's mesh (expressed in the pivot frame, as :func:`wedge_bar_obj`)."""
    pivot = (0.0, 0.0, g.finger_length)  # p3 in the L finger's frame
    in_pivot = Box(bar.name, tuple(np.asarray(bar.center) - pivot), bar.half_extents)
    if g.ramp > 0.0:
        props = hydroelastic("compliant", modulus=GRIPPER_MODULUS, mu=GRIPPER_MU)
        shape = mesh_geometry(bar_mesh)
        elements = (f'<visual name="bar_visual">{shape}{material(ROD_RGBA)}</visual>'
                    f'<collision name="bar">{shape}{props}</collision>')
    else:
        elements = (_box_element("visual", in_pivot, "bar", ROD_RGBA)
                    + _box_element("collision", in_pivot, "bar", ROD_RGBA))
    return [
        f'<frame name="bar_pivot" attached_to="l_finger">{pose(pivot, relative_to="l_finger")}'
        "</frame>",
        f'<link name="bar">{pose(relative_to="bar_pivot")}'
        f"{inertial(BAR_MASS, in_pivot.center, box_inertia(BAR_MASS, in_pivot.size))}"
        f"{elements}</link>",
        '<joint name="bar_joint" type="revolute"><parent>l_finger</parent><child>bar</child>'
        '<pose relative_to="bar_pivot">0 0 0 0 0 0</pose>'
        '<axis><xyz expressed_in="G">1 0 0</xyz>'
        f"<limit><lower>{BAR_RETRACTED:.9g}</lower><upper>{BAR_DEPLOYED:.9g}</upper>"
        f"<effort>{BAR_EFFORT_LIMIT:g}</effort><velocity>3</velocity></limit>"
        "<dynamics><damping>0</damping></dynamics></axis></joint>",
    ]


def wedge_bar_obj(geometry: HookGripperGeometry = WEDGE_GRIPPER) -> str:
    """OBJ text of the wedge bar in its pivot frame: the prism of
    :meth:`~gbh_drake.core.gripper.HookGripperGeometry.bar_profile_pivot` over x in
    +-rod_width/2, outward faces, with normals (Drake's visuals need them)."""
    profile = geometry.bar_profile_pivot()  # (k, 2) counter-clockwise seen from +x
    r, k = 0.5 * geometry.rod_width, len(profile)
    vertices = [(x, y, z) for x in (-r, r) for y, z in profile]
    faces = [[i for i in reversed(range(k))], [k + i for i in range(k)]]  # -x, +x caps
    faces += [[i, (i + 1) % k, k + (i + 1) % k, k + i] for i in range(k)]  # the sides
    lines = ["# Generated by gbh_drake/modeling/gripper_sdf.py: the wedge bar, pivot frame."]
    lines += [f"v {x:.9g} {y:.9g} {z:.9g}" for x, y, z in vertices]
    normals = []
    for face in faces:
        a, b, c = (np.asarray(vertices[i]) for i in face[:3])
        n = np.cross(b - a, c - a)
        normals.append(n / np.linalg.norm(n))
    lines += [f"vn {x:.9g} {y:.9g} {z:.9g}" for x, y, z in normals]
    for j, face in enumerate(faces):
        for t in range(1, len(face) - 1):  # fan triangles
            tri = (face[0], face[t], face[t + 1])
            lines.append("f " + " ".join(f"{i + 1}//{j + 1}" for i in tri))
    return "\n".join(lines) + "\n"


def write_gripper_sdf(path: Path = GRIPPER_SDF) -> Path:
    path.write_text(make_gripper_sdf())
    return path


def write_gripper_models() -> list[Path]:
    """Writes the paper's gripper and the wedge variant (SDF and bar mesh)."""
    WEDGE_GRIPPER_SDF.write_text(make_gripper_sdf(WEDGE_GRIPPER))
    WEDGE_BAR_OBJ.write_text(wedge_bar_obj())
    return [write_gripper_sdf(), WEDGE_GRIPPER_SDF, WEDGE_BAR_OBJ]


if __name__ == "__main__":
    for written in write_gripper_models():
        print(f"wrote {written}")
