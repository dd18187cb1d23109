"""The hook gripper of the paper (Sec. 2.1): a Franka hand with one straight rod and one L rod.

This module is the single source of truth for the gripper's geometry. The Drake model
(``models/hook_gripper.sdf``) is generated from it (:mod:`gbh_drake.modeling.gripper_sdf`) and a test
checks that the file on disk and this module agree, so the gripper that collides in simulation
is the gripper the algorithm reasons about.

Frame G (the "gripper" frame), all lengths in metres:

* origin at the palm centre, where both fingers leave the hand;
* ``+z_G`` from the palm toward the fingertips (the approach direction);
* ``+y_G`` the closing axis, from the L rod toward the straight rod;
* ``+x_G = y_G x z_G`` the palm's thickness direction.

Each finger sits at ``|y| = q`` where ``q`` is one finger's joint position (half the opening
``w = 2 q``). The straight rod runs from ``p4 = (0, q, 0)`` to its tip ``p2 = (0, q, l_f)``; the L rod
from ``p5 = (0, -q, 0)`` to the bend ``p3 = (0, -q, l_f)`` and then along ``+y_G`` to the bar tip
``p1 = (0, l_h - q, l_f)``. The hand's ends are ``p7`` (palm centre, the origin) and ``p6`` (the
wrist end of the hand, on ``-z_G``). So, with the paper's definitions,

* ``n1 = unit(p6 - p7) = -z_G`` (from the fingertips back toward the wrist: a top-down approach has
  ``n1 = +z_W``, which is what makes ``S_alpha`` reward it);
* ``n2 = unit(p1 - p3) = +y_G``;
* ``p_M = (p1 + p2) / 2 = (0, l_h / 2, l_f)`` for every opening, because the fingers move
  symmetrically.

The fingers close until the bar tip meets the straight rod's inner face; the closed loop
(palm, two rods, bar) then cages whatever passes through it.

Retracted bar (the paper's Sec. 4 proposal, used by the antipodal baseline and fallback of
:mod:`gbh_drake.core.antipodal`): a revolute joint about the ``x_G`` axis through the bend ``p3``
folds the bar back along the L rod toward the palm. Its angle is 0 when released (bar along
``+y_G``) and :attr:`HookGripperGeometry.bar_retracted_angle` ``= -pi/2`` when retracted (a
right-handed rotation about ``+x_G``, which takes ``+y_G`` to ``-z_G``): the bar then lies on the
L rod's last ``l_h`` of length (its box inside the L rod's box), so the hand has two straight rods
of the same length, the fairness rule of the paper's Sec. 3.1, and the fingers can close until
the rods touch, at ``q = rod_width / 2`` (:attr:`HookGripperGeometry.q_closed_retracted`). Every
solid-model method takes ``bar_retracted`` (default False: the hook as above).

The wedge bar (beyond the paper, for the scoop of :mod:`gbh_drake.core.scoop`): with
``bar_ramp > 0`` the bar's tip is chamfered: its outer face (the one away from the palm,
``z = l_f + rod_width/2``) runs to the tip (``bar_nose`` past ``p1``; 0 by default), and a
ramp ``bar_ramp`` long rises from that edge back to the bar's inner face: a wedge whose sharp
edge slides along the table and under material lying on it. Its slope matters: material pushed
up a ramp of angle theta against the straight rod, friction mu on both, rises only if
tan(theta) < (1 - mu^2) / (2 mu), 46 deg at mu = 0.4; a 45 deg ramp all but jams (simulated: a
7 mm wire stayed pinched on it), so the default ramp is 16 mm long, 26.6 deg. The default wedge
has no nose (``bar_nose`` = 0): the chamfer lies inside the paper's bar, so the wedge's solid
model, its closing sweep and every rule of GbH are the paper bar's, and only the physics sees the
chamfer; when the loop closes, the edge meets the straight rod's inner face. A nose (the outer
face running on past the tip into a slot of the straight rod, at most a rod's width) was the first
design: it narrowed the way down between the bar's tip and the straight rod by 8 mm, to 15 mm,
and refused every parallel hook of a 14 mm handle (the watering can's: the experiment's
``gbh+`` at 26a9a43, docs/scoop.md).
:data:`WEDGE_GRIPPER` is that variant; :data:`HOOK_GRIPPER`, the paper's square bar, stays
the default everywhere.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: Bar joint angle (rad) when deployed (the hook, the paper's gripper) and when folded onto the
#: L rod (two straight rods: the baseline's gripper, the revolute joint the paper proposes in
#: Sec. 4). The SDF model's joint limits are generated from these.
BAR_DEPLOYED = 0.0
BAR_RETRACTED = -0.5 * np.pi
#: Keypoint names in the paper's order.
KEYPOINT_NAMES = ("p1", "p2", "p3", "p4", "p5", "p6", "p7", "pM")


@dataclass(frozen=True)
class Box:
    """An axis-aligned box in frame G: ``center`` (3,) and ``half_extents`` (3,), metres."""

    name: str
    center: tuple[float, float, float]
    half_extents: tuple[float, float, float]

    @property
    def size(self) -> np.ndarray:
        return 2.0 * np.asarray(self.half_extents)


@dataclass(frozen=True)
class HookGripperGeometry:
    """Dimensions of the hook gripper (paper Sec. 2.1 and Fig. 3). Metres, kilograms.

    The paper's values: ``finger_length = l_f = 0.08``, ``max_opening = l_w = 0.08``,
    ``bar_length = l_h = 0.03``. The rest describes our model of the hardware.
    """

    finger_length: float = 0.08
    """l_f: length of both rods from the palm to the tip (z_G)."""
    max_opening: float = 0.08
    """l_w: largest distance between the two rods' centre lines (y_G)."""
    bar_length: float = 0.03
    """l_h: horizontal part of the L rod, from the L rod's centre line to the bar tip p1 (y_G)."""
    rod_width: float = 0.008
    """Side of the square cross-section of both rods and the bar."""
    hand_half_extents: tuple[float, float, float] = (0.0316, 0.104, 0.0422)
    """Half extents of the Franka hand body (x_G, y_G, z_G); it lies entirely on z_G < 0."""
    palm_offset_in_hand: float = 0.0584
    """Distance from the Franka hand frame's origin (the flange) to the palm along z, i.e. the
    translation of G in the ``panda_hand`` frame (the fingers' joint origin in Franka's model)."""
    hand_mass: float = 0.73
    finger_mass: float = 0.05
    bar_nose: float = 0.0
    """How far (m) the bar's outer face runs on past its tip as a wedge (0: the paper's square
    bar; at most ``rod_width``: the nose ends flush with the straight rod's outer face when the
    loop closes)."""
    bar_ramp: float = 0.0
    """Length (m, along y_G) of the wedge's ramp, from the tip's (or nose's) edge back to where
    it meets the bar's inner face (``bar_nose`` <= ``bar_ramp`` <= ``bar_nose`` + ``bar_length``
    - ``rod_width``: the inner face keeps a rod's width past the L rod's; ``bar_nose`` when 0,
    and 0 for the paper's square bar)."""

    def __post_init__(self) -> None:
        if not 0.0 <= self.bar_nose <= self.rod_width + 1e-12:
            raise ValueError(f"bar_nose {self.bar_nose} m outside [0, rod_width = "
                             f"{self.rod_width} m]")
        if self.bar_ramp and not (self.bar_nose <= self.bar_ramp
                                  <= self.bar_nose + self.bar_length - self.rod_width + 1e-12):
            raise ValueError(f"bar_ramp {self.bar_ramp} m outside [bar_nose, bar_nose + "
                             f"bar_length - rod_width]")

    @property
    def ramp(self) -> float:
        """The wedge's ramp length (m): ``bar_ramp``, or ``bar_nose`` when that is 0."""
        return self.bar_ramp or self.bar_nose

    # ---- openings -------------------------------------------------------------------------
    @property
    def q_open(self) -> float:
        """One finger's joint position when fully open (half of l_w)."""
        return 0.5 * self.max_opening

    @property
    def q_closed(self) -> float:
        """One finger's joint position when the bar tip touches the straight rod's inner face.

        The bar tip is at y = l_h - q and the straight rod's inner face at y = q - rod_width / 2.
        """
        return 0.5 * (self.bar_length + 0.5 * self.rod_width)

    @property
    def q_closed_retracted(self) -> float:
        """One finger's joint position when the bar is retracted and the rods' inner faces touch
        (rod_width / 2: the rods' centre lines are one rod width apart)."""
        return 0.5 * self.rod_width

    def q_min(self, bar_retracted: bool = False) -> float:
        """Smallest finger position: :attr:`q_closed` (bar released) or
        :attr:`q_closed_retracted` (bar retracted)."""
        return self.q_closed_retracted if bar_retracted else self.q_closed

    def check_opening(self, q: float, bar_retracted: bool = False) -> float:
        q = float(q)
        q_min = self.q_min(bar_retracted)
        if not (q_min - 1e-9 <= q <= self.q_open + 1e-9):
            raise ValueError(
                f"finger position q={q:.4f} m outside [{q_min:.4f}, {self.q_open:.4f}]"
            )
        return q

    # ---- keypoints --------------------------------------------------------------------------
    def keypoints_G(self, q: float | None = None) -> dict[str, np.ndarray]:
        """Keypoints p1..p7 and pM in frame G for finger position ``q`` (default: fully open;
        below :attr:`q_closed` only with the bar retracted, as a pinch closes)."""
        q = self.q_open if q is None else self.check_opening(q, bar_retracted=q < self.q_closed)
        lf, lh = self.finger_length, self.bar_length
        hand_back = -2.0 * self.hand_half_extents[2]
        p = {
            "p1": np.array([0.0, lh - q, lf]),
            "p2": np.array([0.0, q, lf]),
            "p3": np.array([0.0, -q, lf]),
            "p4": np.array([0.0, q, 0.0]),
            "p5": np.array([0.0, -q, 0.0]),
            "p6": np.array([0.0, 0.0, hand_back]),
            "p7": np.zeros(3),
        }
        p["pM"] = 0.5 * (p["p1"] + p["p2"])
        return p

    @property
    def n1_G(self) -> np.ndarray:
        """n1 = unit(p6 - p7) in G: from the palm toward the wrist, -z_G."""
        p = self.keypoints_G()
        d = p["p6"] - p["p7"]
        return d / np.linalg.norm(d)

    @property
    def n2_G(self) -> np.ndarray:
        """n2 = unit(p1 - p3) in G: along the bar toward its tip, +y_G."""
        p = self.keypoints_G()
        d = p["p1"] - p["p3"]
        return d / np.linalg.norm(d)

    # ---- solid model --------------------------------------------------------------------------
    def hand_box(self) -> Box:
        hx, hy, hz = self.hand_half_extents
        return Box("hand", (0.0, 0.0, -hz), (hx, hy, hz))

    def straight_finger_boxes(self) -> list[Box]:
        """Boxes of the straight finger in its own finger frame F (= G shifted by +q along y_G)."""
        r = 0.5 * self.rod_width
        lf = self.finger_length
        # The rod reaches r beyond the tip keypoint so that the bar (centred at z = l_f) closes
        # flush against it.
        return [Box("straight_rod", (0.0, 0.0, 0.5 * (lf + r)), (r, r, 0.5 * (lf + r)))]

    def l_finger_boxes(self, bar_retracted: bool = False) -> list[Box]:
        """Boxes of the L finger in its own finger frame F (= G shifted by -q along y_G); with
        ``bar_retracted`` the bar is :meth:`retracted_bar_box` (inside the rod's box). A wedge
        bar adds its nose's bounding box (``bar_nose``; the ramp inside it, conservative)."""
        r = 0.5 * self.rod_width
        lf, lh = self.finger_length, self.bar_length
        boxes = [
            Box("l_rod", (0.0, 0.0, 0.5 * (lf + r)), (r, r, 0.5 * (lf + r))),
            # From the rod's outer face (y = -r) to the bar tip (y = l_h).
            self.retracted_bar_box() if bar_retracted
            else Box("bar", (0.0, 0.5 * (lh - r), lf), (r, 0.5 * (lh + r), r)),
        ]
        if self.bar_nose > 0.0 and not bar_retracted:
            boxes.append(Box("bar_nose", (0.0, lh + 0.5 * self.bar_nose, lf),
                             (r, 0.5 * self.bar_nose, r)))
        return boxes

    def bar_profile_pivot(self) -> np.ndarray:
        """(k, 2) the deployed bar's cross-section in the (y, z) plane of its pivot frame (the
        bend p3 at the origin, axes of G), counter-clockwise seen from +x: a rectangle from
        the L rod's outer face to the tip, its tip chamfered into a wedge when :attr:`ramp` > 0
        (the outer face running on ``bar_nose`` past the tip; the bar's solid is this profile
        extruded over +-rod_width/2 in x)."""
        r, lh, nose = 0.5 * self.rod_width, self.bar_length, self.bar_nose
        if self.ramp <= 0.0:
            return np.array([(-r, -r), (lh, -r), (lh, r), (-r, r)])
        return np.array([(-r, -r), (lh + nose - self.ramp, -r), (lh + nose, r), (-r, r)])

    # ---- the retractable bar (paper Sec. 4) ---------------------------------------------------
    @property
    def bar_retracted_angle(self) -> float:
        """Radians: the bar joint's angle when retracted, a rotation about ``+x_G`` through the
        bend p3 that takes the bar's direction ``+y_G`` to ``-z_G`` (0 = released)."""
        return -0.5 * np.pi

    @property
    def bar_pivot_F(self) -> np.ndarray:
        """(3,) the bar joint's origin, the bend p3, in the L finger's frame F (metres); its axis
        is ``+x_G`` (= +x_F)."""
        return np.array([0.0, 0.0, self.finger_length])

    def retracted_bar_box(self) -> Box:
        """The bar's box in the L finger's frame F once retracted: the released bar's box
        rotated by :attr:`bar_retracted_angle` about ``x`` through :attr:`bar_pivot_F`. It spans
        ``y`` in [-r, r] and ``z`` in [l_f - l_h, l_f + r] (r = rod_width / 2): the L rod's last
        l_h of length, inside the rod's box."""
        released = self.l_finger_boxes(bar_retracted=False)[1]
        c, s = np.cos(self.bar_retracted_angle), np.sin(self.bar_retracted_angle)
        R = np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])
        R = np.round(R)  # a quarter turn: exact, and the box stays axis-aligned
        pivot = self.bar_pivot_F
        center = pivot + R @ (np.asarray(released.center) - pivot)
        half = np.abs(R) @ np.asarray(released.half_extents)
        return Box("bar", tuple(float(v) for v in center), tuple(float(v) for v in half))

    def solid_boxes_G(self, q: float | None = None, bar_retracted: bool = False) -> list[Box]:
        """The gripper's solid model in G at finger position ``q``: hand, rods and bar (the bar
        folded onto the L rod with ``bar_retracted``, where q may go down to
        :attr:`q_closed_retracted`)."""
        q = self.q_open if q is None else self.check_opening(q, bar_retracted)
        boxes = [self.hand_box()]
        for b in self.straight_finger_boxes():
            c = np.asarray(b.center) + (0.0, q, 0.0)
            boxes.append(Box(b.name, tuple(c), b.half_extents))
        for b in self.l_finger_boxes(bar_retracted):
            c = np.asarray(b.center) + (0.0, -q, 0.0)
            boxes.append(Box(b.name, tuple(c), b.half_extents))
        return boxes

    def count_points_inside(
        self, p_GQ: np.ndarray, q: float | None = None, margin: float = 0.0,
        bar_retracted: bool = False,
    ) -> int:
        """Number of points ``p_GQ`` (n, 3) in G that lie inside the solid model (grown by margin)."""
        return int(self.points_inside_mask(p_GQ, q, margin, bar_retracted).sum())

    def points_inside_mask(
        self, p_GQ: np.ndarray, q: float | None = None, margin: float = 0.0,
        bar_retracted: bool = False,
    ) -> np.ndarray:
        """Boolean mask (n,) of the points ``p_GQ`` (n, 3) inside the solid model (grown by margin)."""
        p = np.asarray(p_GQ, dtype=float).reshape(-1, 3)
        return self.inside_solid_model(p[:, 0], p[:, 1], p[:, 2], q, margin, bar_retracted)

    def inside_solid_model(
        self, x: np.ndarray, y: np.ndarray, z: np.ndarray, q: float | None = None,
        margin: float = 0.0, bar_retracted: bool = False,
    ) -> np.ndarray:
        """Boolean mask of points given by their G coordinates ``x, y, z`` (arrays of one shape,
        metres) inside the solid model (grown by margin; bar folded onto the L rod with
        ``bar_retracted``); column-wise, so batches of poses can pass (N, M) coordinate arrays
        without reshaping."""
        inside = np.zeros(np.shape(x), dtype=bool)
        for b in self.solid_boxes_G(q, bar_retracted):
            # Python floats keep float32 input in float32 (NumPy scalars would upcast it).
            cx, cy, cz = (float(v) for v in b.center)
            hx, hy, hz = (float(v) + margin for v in b.half_extents)
            box = np.abs(z - cz) <= hz
            box &= np.abs(y - cy) <= hy
            box &= np.abs(x - cx) <= hx
            inside |= box
        return inside

    def loop_polygon_G(self, q: float | None = None) -> np.ndarray:
        """The closed loop formed by palm, straight rod, bar and L rod, as a polygon (4, 3) in G.

        Vertices along the centre lines: p5 -> p4 -> p2 -> p3 (the bar closes p2-p3 when the
        gripper is closed). Used to check that a grasp's loop links a ring (the cage)."""
        p = self.keypoints_G(self.q_closed if q is None else q)
        return np.stack([p["p5"], p["p4"], p["p2"], p["p3"]])


#: The gripper used throughout the project (paper dimensions).
HOOK_GRIPPER = HookGripperGeometry()
#: The same gripper with a wedge bar (its tip chamfered over twice the rod's width: 26.6 deg,
#: inside the paper's bar), for the scoop (beyond the paper; ``robot.gripper: wedge``).
WEDGE_GRIPPER = HookGripperGeometry(bar_ramp=2.0 * HOOK_GRIPPER.rod_width)
#: The grippers by name (``RobotConfig.gripper``).
GRIPPERS = {"paper": HOOK_GRIPPER, "wedge": WEDGE_GRIPPER}


def keypoints_W(X_WG: np.ndarray, q: float | None = None, geometry: HookGripperGeometry =
                HOOK_GRIPPER) -> dict[str, np.ndarray]:
    """Keypoints in world W for the gripper pose ``X_WG`` (4, 4 homogeneous matrix)."""
    X = np.asarray(X_WG, dtype=float)
    return {k: X[:3, :3] @ v + X[:3, 3] for k, v in geometry.keypoints_G(q).items()}


# ---- the frame contract: where G is on a Franka's flange --------------------------------------
#: Degrees about z of Franka's hand frame H (``panda_hand``) on the flange ``panda_link8``: the
#: hand is mounted turned by -45 deg, as Franka mounts it (the station's directives weld it so:
#: ``scenario/schema.py``'s ``DEFAULT_DIRECTIVES``; ``tests/modeling`` checks that a plant
#: built from them puts G where :func:`X_link8_G` says).
HAND_MOUNT_YAW_DEG = -45.0


def X_link8_H(yaw_deg: float = HAND_MOUNT_YAW_DEG) -> np.ndarray:
    """(4, 4) pose of the hand frame H (``panda_hand``, the hook gripper's base link) in the
    flange frame ``panda_link8``: a turn of ``yaw_deg`` about z, no offset."""
    c, s = np.cos(np.radians(yaw_deg)), np.sin(np.radians(yaw_deg))
    X = np.eye(4)
    X[:2, :2] = [[c, -s], [s, c]]
    return X


def X_H_G(geometry: HookGripperGeometry = HOOK_GRIPPER) -> np.ndarray:
    """(4, 4) pose of the gripper frame G (palm centre) in the hand frame H:
    ``palm_offset_in_hand`` along z_H, axes parallel (the SDF's frame ``G``)."""
    X = np.eye(4)
    X[2, 3] = geometry.palm_offset_in_hand
    return X


def X_link8_G(geometry: HookGripperGeometry = HOOK_GRIPPER,
              yaw_deg: float = HAND_MOUNT_YAW_DEG) -> np.ndarray:
    """(4, 4) pose of the gripper frame G in the flange frame ``panda_link8`` of a Franka with
    the hook gripper mounted as in the station: X_link8_H X_H_G. A grasp X_BG (G in the
    robot's base frame B) puts the flange at X_B_link8 = X_BG X_link8_G^-1
    (:func:`X_B_link8`)."""
    return X_link8_H(yaw_deg) @ X_H_G(geometry)


def X_B_link8(X_BG: np.ndarray, geometry: HookGripperGeometry = HOOK_GRIPPER) -> np.ndarray:
    """(4, 4) the flange's pose ``panda_link8`` in B for the gripper frame at ``X_BG`` (4, 4)."""
    return np.asarray(X_BG, dtype=float) @ np.linalg.inv(X_link8_G(geometry))


def p_G_hook(geometry: HookGripperGeometry = HOOK_GRIPPER) -> np.ndarray:
    """(3,) the hook point T in G, metres: the middle of the closed loop's bar, between the
    rods' centre lines (0, 0, l_f). A parallel grasp puts the hole's centre c there (it stays
    there as the fingers close symmetrically); the planner lifts the object from it. This
    gripper's tool centre point (TCP)."""
    return np.array([0.0, 0.0, geometry.finger_length])
