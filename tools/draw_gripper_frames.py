"""Draws the frame contract of the hook gripper on a Franka's flange: ``docs/gripper_frames.png``.

The flange frame ``panda_link8``, Franka's hand frame H (``panda_hand``, the gripper's base link),
the gripper frame G (the palm's centre) and the hook point T (the TCP) as axes (x red, y green,
z blue), the solid model (hand, straight rod, L rod and bar, open) in grey, and the transforms as
numbers, all from :mod:`gbh_drake.core.gripper` (the module the SDF is generated from)::

    .venv/bin/python tools/draw_gripper_frames.py [OUT.png]
"""

from __future__ import annotations

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402

from gbh_drake import REPO_ROOT  # noqa: E402
from gbh_drake.core.gripper import (  # noqa: E402
    HAND_MOUNT_YAW_DEG,
    HOOK_GRIPPER,
    X_H_G,
    X_link8_G,
    X_link8_H,
    p_G_hook,
)

OUT = REPO_ROOT / "docs" / "gripper_frames.png"
#: Axis length (m) of the drawn frames.
AXIS = 0.035


def _box_faces(centre, half, X):
    """The 6 faces (4 corners each) of a box in G, mapped by X (4, 4, G -> link8)."""
    c, h = np.asarray(centre), np.asarray(half)
    corners = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]) * h + c
    p = corners @ X[:3, :3].T + X[:3, 3]
    quads = [(0, 1, 3, 2), (4, 5, 7, 6), (0, 1, 5, 4), (2, 3, 7, 6), (0, 2, 6, 4), (1, 3, 7, 5)]
    return [p[list(q)] for q in quads]


def _frame(ax, X, name, offset=(0.004, 0.004, 0.0)):
    origin = X[:3, 3]
    for k, colour in enumerate(("tab:red", "tab:green", "tab:blue")):
        tip = origin + AXIS * X[:3, k]
        ax.plot(*np.stack([origin, tip]).T, color=colour, linewidth=2.5)
    ax.text(*(origin + np.asarray(offset)), name, fontsize=10, weight="bold")


def _matrix(X) -> str:
    return "\n".join("  [" + " ".join(f"{v:7.4f}" for v in row) + "]" for row in X)


def draw(out: Path = OUT) -> Path:
    g = HOOK_GRIPPER
    X_8G = X_link8_G(g)
    X_GT = np.eye(4)
    X_GT[:3, 3] = p_G_hook(g)
    fig = plt.figure(figsize=(12, 7.5))
    ax = fig.add_axes([0.0, 0.0, 0.56, 0.93], projection="3d")
    faces = []
    for box in g.solid_boxes_G(g.q_open):
        faces += _box_faces(box.center, box.half_extents, X_8G)
    ax.add_collection3d(Poly3DCollection(faces, facecolor=(0.75, 0.75, 0.78, 0.25),
                                         edgecolor=(0.3, 0.3, 0.3, 0.45), linewidth=0.5))
    _frame(ax, np.eye(4), "panda_link8 (flange)", offset=(-0.075, 0.0, -0.006))
    _frame(ax, X_link8_H(), "H: panda_hand (same origin)", offset=(0.006, 0.0, 0.018))
    _frame(ax, X_8G, "G (palm centre)")
    _frame(ax, X_8G @ X_GT, "T: hook point (TCP)")
    ax.set_xlim(-0.09, 0.09)
    ax.set_ylim(-0.09, 0.09)
    ax.set_zlim(-0.01, 0.17)
    ax.set_box_aspect((1, 1, 1))
    ax.invert_zaxis()  # the flange on top, the fingertips below (a top-down grasp)
    ax.view_init(elev=-18, azim=-58)
    ax.set_xlabel("x_link8 (m)")
    ax.set_ylabel("y_link8 (m)")
    ax.set_zlabel("z_link8 (m)")
    fig.suptitle("The hook gripper on a Franka's flange, open: axes x red, y green, z blue; the "
                 "solid model grey\n(the hand's box is its collision model, larger than the hand)",
                 fontsize=10, y=0.99)
    text = (
        "Frames (all from gbh_drake.core.gripper, the module\n"
        "models/hook_gripper.sdf is generated from):\n\n"
        f"X_link8_H: panda_hand turned {HAND_MOUNT_YAW_DEG:g} deg about z_link8\n"
        f"{_matrix(X_link8_H())}\n\n"
        f"X_H_G: G {g.palm_offset_in_hand} m along z_H (palm_offset_in_hand)\n"
        f"{_matrix(X_H_G(g))}\n\n"
        "X_link8_G = X_link8_H X_H_G        (X_link8_G())\n"
        f"{_matrix(X_8G)}\n\n"
        f"p_GT = (0, 0, l_f) = (0, 0, {g.finger_length}) m    (p_G_hook())\n\n"
        "G: +z_G approach (palm -> fingertips), +y_G closing\n"
        "   (L rod -> straight rod), x_G = y_G x z_G.\n"
        f"Rods {g.rod_width * 1e3:.0f} mm square, l_f = {g.finger_length} m; bar l_h = "
        f"{g.bar_length} m;\n"
        f"open q = {g.q_open} m per finger (width {2 * g.q_open} m), closed (bar tip on\n"
        f"the straight rod) q = {g.q_closed} m (width {2 * g.q_closed:.3f} m).\n\n"
        "A grasp X_BG (G in the robot's base frame B = panda_link0)\n"
        "puts the flange at X_B_link8 = X_BG X_link8_G^-1:\n"
        "    from gbh_drake.core.gripper import X_B_link8\n"
        "    X_B_link8(X_BG)")
    fig.text(0.6, 0.5, text, family="monospace", fontsize=8.6, va="center")
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return out


if __name__ == "__main__":
    print(f"wrote {draw(Path(sys.argv[1]) if len(sys.argv) > 1 else OUT)}")
