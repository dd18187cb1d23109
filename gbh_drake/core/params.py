"""Every tunable number of the GbH algorithm core (and of the antipodal baseline), in plain
dataclasses: the configuration's ground floor, importing nothing of the pipeline.

Values marked *paper* are from Li, Su, Chirikjian (Sec. 2.3-3.1); the others are our documented
defaults (see ``/work/shared/design.md`` Sec. 3-4 for the measurements behind them). The class is
a plain dataclass of float/int/bool/str/list[float] fields, each with a default, so a scenario
YAML can load it with Drake's ``yaml_load_typed(schema=GbhParams, ...)``.

Lengths are metres and angles degrees; every position/direction the algorithm returns is in the
frame the mesh is given in (called W in the docstrings).
"""

# No ``from __future__ import annotations`` here: yaml_load_typed reads the field types at run
# time and needs real types, not strings.
import copy
import dataclasses
import functools
from dataclasses import dataclass

import numpy as np

from gbh_drake.core.ranges import (
    FieldError,
    Int,
    Items,
    NonNeg,
    OneOf,
    Pos,
    Range,
    Relation,
    checker,
    ranged,
    sibling,
)
from gbh_drake.core.results import GbhInputError

#: Segment samples per cluster GbH may test (max_contacts_per_cluster x n_segment_samples).
MAX_SEGMENT_SAMPLES = 50_000
#: A count of object points is bounded by the points sampled.
_AT_MOST_N_POINTS = Relation("<=", "n_points", "no more object points can be counted than are "
                                               "sampled: the rule would keep every grasp")


@dataclass
class GbhParams:
    """Parameters of hangability detection, grasp synthesis, collision checking and scoring.

    ``preset`` names where the defaults of the fields that go beyond the paper come from:
    ``""`` (gbh_drake's, below) or ``"paper"`` (the paper's rules alone, :data:`PRESETS`).
    ``GbhParams(preset="paper", d2=0.005)`` in code, ``gbh: {preset: paper, d2: 0.005}`` in a
    scenario and ``GbhParams(d2=0.005).with_preset("paper")`` give the same parameters: the
    preset's values, and the fields given beside it win. (``dataclasses.replace(p,
    preset=...)`` passes every field and so applies no preset's values: use
    :meth:`with_preset`.)"""

    preset: str = ranged("", OneOf(("", "paper", "robust"),
                                   "'paper': the paper's rules alone; 'robust': the provisional "
                                   "rules on, opt-in until swept"))
    """``""``: gbh_drake's defaults; ``"paper"``: the paper's rules where ours go beyond them;
    ``"robust"``: the provisional (unswept) rules on at their provisional values
    (:data:`PRESETS`, docs/robustness.md)."""

    # ---- sampling ---------------------------------------------------------------------------
    n_points: int = ranged(5000, Int(100, 50_000, "sampling and ray casting grow with it"))
    """Number of Poisson-disk points sampled on the mesh (at most; a few fewer on tiny meshes).
    design.md Sec. 3: 5000 points found a mug handle, 3000 missed it."""
    oversampling: int = ranged(5, Int(1, 20))
    """Uniform candidates per Poisson-disk point (the disk elimination keeps about 1 in this)."""
    require_watertight: bool = False
    """Raise GbhInputError for open/non-manifold meshes instead of the best effort (surface
    centroid as CoM, normals as wound)."""

    # ---- hangability: contact points and hanging positions ----------------------------------
    contact_angle_deg: float = ranged(35.0, Range(0.0, 90.0, lo_open=True, hi_open=True, unit="deg"))
    """Degrees. A point is a hanging-contact candidate when its outward normal is within this
    angle of the direction to the CoM (design.md Sec. 3: 30 found a mug handle on the true mesh,
    25 missed it). On scans the TSDF (2.5 mm voxels) rounds a handle's 8-12 mm section, and
    views from 40-70 deg elevation never see an arched handle's underside (the kettle: 35 deg
    at best on its scan, 17 samples within 30 deg on its true mesh). Chosen from the sweep over
    every trial of the experiment (docs/thresholds.md): 35 finds a true part in 95/95 10-view
    trials (30: 90) and puts the best grasp on one in 57 (56) and 36/95 on one view (33),
    with no control hit; 40 loses grasps and 45 hooks a control. The paper preset keeps 30."""
    cluster_radius: float = ranged(2.5, Pos(100.0))
    """Contact points closer than this many mean sample spacings are in one cluster
    (single-linkage, i.e. DBSCAN with min_samples = 1). Dimensionless."""
    min_cluster_size: int = ranged(1, Int(1, 50_000), relations=(
        Relation("<=", "n_points", "a cluster of contact points larger than the surface "
                                   "samples can never form: nothing would be hangable"),))
    """Clusters with fewer contact points are ignored. 1 keeps isolated candidates: on a thin
    wire (a bucket's bail, a bag's strap) at 5000 points the few candidates on its underside
    lie farther apart than the cluster radius; the through-hole test removes noise."""
    max_contacts_per_cluster: int = ranged(48, Int(1, 1000))
    """Contact points of a cluster whose segments are searched (a deterministic random subset
    when the cluster is larger; bounds the cost on big clusters such as a cup's inner wall)."""
    n_segment_samples: int = ranged(32, Int(2, 1000))
    """Points sampled on the free part of each contact-to-CoM segment to find the clearance max."""
    max_hanging_distance: float = ranged(0.05, Pos(1.0, "m"))
    """Metres. c is searched on the segment toward the CoM at most this far from the contact
    point: the gripper's loop is l_f = 8 cm long, so a c farther from the material it hooks
    cannot be used; without the cap, a bucket's bail hands its c to the bucket's cavity."""
    min_clearance: float = ranged(0.002, NonNeg(0.1, "m"), relations=(
        Relation("<", "max_hanging_distance", "c lies at most max_hanging_distance from the "
                 "material it hooks, so its clearance is never more: nothing would be "
                 "hangable"),))
    """Metres. Hanging positions closer than this to the surface are dropped (nothing fits)."""
    positions_per_cluster: int = ranged(1, Int(1, 1000))
    """Ours: a cluster keeps up to this many hanging positions, chosen by non-maximum
    suppression over its members' positions (largest clearance first; each removes those
    inside its free ball, ``dedup_radius_factor``), each with its exact clearance. 1: the
    paper's one position per cluster, its member of largest *approximate* clearance: single
    linkage joins a handle's contacts to the body's next to it, and the cluster's one position
    then lies inside the cup or in a corner where nothing fits, and the handle is lost (a mug
    and a teapot of the external set, issue 42). Provisional: 1 (the paper's) until swept;
    preset ``robust``: 4 (docs/robustness.md says which sweep decides it)."""
    cluster_fallback: bool = True
    """Ours: a cluster all of whose kept positions are refused (not a through-hole, or by the
    exit proof) tries its other members' positions, largest exact clearance first (outside
    the refused positions' free balls, non-maximum suppressed), until ``positions_per_cluster``
    pass (:func:`~gbh_drake.core.hangability.fallback_positions`). Single linkage joins a
    handle's contacts to the body's next to it; the cluster's one position then lies in the
    cup or a corner, is refused, and the handle is lost, and which contacts chain into one
    cluster turns on a tenth of a millimetre (a basket's handle lost by a start 0.1 mm higher,
    docs/candidates.md). A cluster whose position passes is unchanged; no threshold. Measured
    on every method over both object sets, screened and re-run (4 verdicts gained, 1 lost to a
    structure on no true part, no rate fell; the knife edge one fewer: docs/robustness.md).
    False: the paper's one position per cluster (preset ``paper``)."""
    hang_segment_seen: bool = True
    """Ours, with ``unknown_is_occupied``: a contact's hanging position is searched only on
    the part of its segment toward the CoM that the cameras saw free, up to where the segment
    first enters unseen space (:func:`~gbh_drake.core.hangability.seen_prefix`). A scanned
    wall behind a handle can keep a gap the TSDF did not close; the segment then runs through
    it into the cup's unseen cavity, whose larger free ball wins the cluster, and the exit
    proof refuses it: the handle is lost (two mugs of the external set lying upside down or
    on their side, docs/robustness.md). A position in unseen space is always refused by the
    exit proof; one seen free again beyond an unseen stretch is given up too (the hook would
    pass where the scan may have lost material). False: the segment up to the mesh (the
    paper's reading)."""
    dedup_radius_factor: float = ranged(1.0, NonNeg(100.0))
    """Two hanging positions coincide when one lies within this factor times the other's
    clearance (its free ball); the one with more clearance is kept. Dimensionless."""

    # ---- hangability: hanging direction ---------------------------------------------------------
    n_plane_normals: int = ranged(400, Int(2, 10_000))
    """Candidate plane normals u on a Fibonacci sphere (u, -u are one plane: half are cast)."""
    n_rays_per_plane: int = ranged(36, Int(3, 720))
    """Rays cast from c_i in each candidate plane (K in the paper); also the size bound of H_i."""
    refine_cone_deg: float = ranged(15.0, Range(0.0, 90.0, hi_open=True, unit="deg"))
    """Degrees. Half-angle of the cone around the coarse best normal searched by the refinement."""
    n_refine_normals: int = ranged(120, Int(1, 5000))
    """Normals tried in the refinement cone."""

    # ---- grasp synthesis ------------------------------------------------------------------------
    parallel_grasps: bool = True
    """Generate parallel grasps (bar along +-v_i through c_i, the caged material centred between
    the rods; grasp_synthesis says why not the paper's p_M at c_i)."""
    vertical_grasps: bool = True
    """Generate vertical grasps (straight finger along +-v_i or the ground normal, the bar's inner
    face ``cage_clearance + d2`` beyond q_f)."""
    ground_normal: list[float] = ranged(lambda: [0.0, 0.0, 1.0], Items(3, what="components"))
    """Unit anti-gravity direction (ground normal) in W; normalised on use."""
    p_theta: float = ranged(0.95, Range(0.0, 1.0, lo_open=True))
    """*paper*: the straight finger snaps to the ground normal when cos(theta) > p_theta."""
    snap_tilt_max_deg: float = ranged(45.0, Range(0.0, 90.0, hi_open=True, unit="deg"))
    """Ours (beyond the paper), degrees: a vertical grasp whose hole axis is tilted from the
    ground normal by more than the paper's snap (acos p_theta = 18 deg) but less than this is
    tried both ways, the straight finger along the axis and along the ground normal; the
    collision, sweep and table checks decide. From the gripper: a straight rod of width w
    crossing material of thickness t at a tilt theta to a hole of clear width D needs
    w / cos(theta) + t tan(theta) <= D; for the set's smallest caging hole (the 8 mm rod, 1 cm
    of material, 2 cm clear) that holds up to 42 deg, and past 45 deg the finger is nearer the
    hole's plane than its axis. docs/thresholds.md has the sweep. 0: the paper's rule only."""
    approach_rotations_deg: list[float] = ranged(
        lambda: [0.0, -20.0, 20.0, -40.0, 40.0],
        Items(None, Range(-90.0, 90.0, unit="deg"), what="angles (deg)"))
    """Ours (beyond the paper), degrees: every grasp is also tried turned by each of these angles
    about the hole's axis v (parallel: the approach swings round the hole, the bar stays in it)
    or about the straight finger (vertical: the L rod swings round the straight rod in the
    hole), scored as the paper scores them; so a reachable approach exists when the paper's
    single pose points away from the robot or into the table. [0]: the paper's poses only."""
    d1: float = ranged(0.01, NonNeg(0.1, "m"))
    """*paper*, metres: q_1 = h + d1 unit(c - h) (eq. 1)."""
    d1_centred: bool = True
    """Ours: a vertical grasp's straight rod no farther from h than the hole's centre c, q_1 =
    h + min(d1, |c - h|) unit(c - h) (at least half a rod from h): in a hole narrower than
    2 d1 the paper's rod crosses the centre and stands against the far side (a frying pan's
    11 mm slot: the 8 mm rod's axis 1 mm from the far edge), here it stands in the middle.
    Geometry, measured on both object sets (docs/robustness.md); preset ``paper``: False (eq. 1
    as written)."""
    d2: float = ranged(0.0, Range(-0.05, 0.05, unit="m"))
    """*paper*, metres: q_m = q_2 + d2 v (eq. 3). 0 for 10-view scans, 0.005 for one view.
    Added on top of ``cage_clearance`` (see grasp_synthesis: the paper's p2 is a point of a
    rod of no thickness; ours is the centre line of an 8 mm bar)."""
    cage_clearance: float = ranged(0.003, NonNeg(0.05, "m"))
    """Metres. A vertical grasp puts the bar's inner face (z_G = l_f - rod_width / 2) this far
    beyond the farthest caged material point q_f (plus d2), so the bar closes past the material
    instead of onto it. Ours, not the paper's: the paper's p2 has no thickness."""
    slice_half_width: float = ranged(0.005, Pos(0.05, "m"))
    """Metres. Half thickness of the slab (about the gripper's plane) that selects the caged
    points Q of a grasp (vertical: q_f; parallel: the material centred between the rods); a bit
    more than half a rod so a sparse cloud still has points."""

    # ---- collision checking ------------------------------------------------------------------
    ground_height: float = ranged(0.0, Range(-1.0, 1.0, unit="m"))
    """m: height of the supporting surface (the table top) along ``ground_normal``, in W."""
    ground_clearance: float = ranged(0.003, Range(-1.0, 0.1, unit="m", note="negative: no ground check"))
    """m: the gripper's solid model (hand, rods, bar) at the grasp pose, open, during the
    closing sweep and closed, must stay at least this far above the supporting surface
    (``ground_height`` along ``ground_normal``); grasps that come closer (rods under a flat
    object lying on the table, fingers-up grasps from below) are not ranked. This is the one
    clearance rule for ranking and planning: the motion planner pads the table by (at most)
    this number for the segments near the grasp (descend, close, lift), so a ranked grasp is
    not refused there for touching the table. A negative value turns the check off (e.g. an
    object in free space)."""
    p_c: int = ranged(10, Int(1, 50_000), relations=(_AT_MOST_N_POINTS,))
    """*paper*: a grasp is kept only if fewer than p_c object points are inside the gripper
    (open, at the grasp pose)."""
    p_sweep: int = ranged(1, Int(1, 50_000), relations=(_AT_MOST_N_POINTS,))
    """Ours: a grasp is kept only if fewer than p_sweep object points lie in the volume the
    gripper sweeps while closing (hand, rods and bar moving from the open to the closed pose,
    the closed pose included) that are not already counted in N_c. Default 1: none, because
    the closing motion must not meet material (that is a pinch, not a cage); see scoring.py."""
    sampling_votes: int = ranged(1, Int(1, 9))
    """Ours: a candidate near a collision threshold (N_c < 2 p_c and N_sweep < 2 p_sweep + 2)
    is counted again on ``sampling_votes - 1`` more samplings of the same surface (other
    seeds, derived from the trial's) and kept only if it passes on most of them: a
    zero-tolerance count on one sampled cloud flips on one point (the same trial with only the
    sampling seed changed found the basket's top-down grasp first in 4 of 9 seeds). 1 (the
    default, the paper's single count): measured by bench/bench_stability.py over the 19
    objects upright, 3 votes kept the best grasp exactly as often as 1 (95 % under 1e-6 m of
    noise, 76 % under another seed) at 2.5x the time: what flips is the structures found, not
    the counts."""
    sweep_margin_spacings: float = ranged(0.25, NonNeg(10.0))
    """Ours, in sample spacings (the Poisson-disk radius of the object's points: about 0.5 mm on
    a key ring, 2.4 mm on a mug, 4.2 mm on a pot): for N_sweep the moving parts' swept boxes are
    grown by this much, because material can cut into a box between two samples unseen. Only a
    full spacing would guarantee that nothing is missed; 0.25 is a compromise measured on the
    object set: it rejects the pot's grasp whose hand sweeps 1 mm into the rim between samples
    4.2 mm apart (found with 20k samples), and keeps the headphones' top-down grasps, whose 24 mm
    band is caged with 1 mm to spare on each side of the 26 mm loop (0.5 would reject them)."""
    rod_clearance: float = ranged(-1.0, Range(-1.0, 0.05, unit="m",
                                               note="negative: no such check"))
    """Ours, metres: the rods and the bar, at the grasp pose and swept while closing, must stay
    this far from the object's surface, tested so that nothing thinner than the sample spacing
    slips through (:func:`~gbh_drake.core.collision.count_rod_contacts`: the samples near the
    rods, then the exact distance to the surface where they are near). N_c < p_c allows 9
    samples inside the gripper: an 8 mm rod crossing a 3-5 mm wire or grazing a thin handle arm
    meets only 2-5 of 5000 samples 2-5 mm apart, and the executed hand is off the plan by the
    IK's tolerance (1 mm and 0.01 rad at the palm: measured 2.1-2.4 mm at the rods' corners
    over 35 ranked grasps, docs/thresholds.md). Negative: the paper's N_c alone. Provisional:
    -1 (off) until swept; preset ``robust``: 0.0025 (docs/robustness.md says which sweep
    decides it)."""
    loop_must_enclose: bool = True
    """Ours: a hook is ranked only if its loop, closed at the grasp (the hand moved with the
    fingers for a vertical grasp), holds the object's surface in its hole and runs clear of it
    (:func:`~gbh_drake.core.enclosure.planned_loop_material`; the cage test's geometry, no
    threshold). A turned grasp's plane can pass beside the material (a headband, a teapot's
    handle: the rod in the hole, the loop closing on air), and the hand then lifts nothing.
    Checked lazily like the rods' clearance, best score first. False: the paper's rules (preset
    ``paper``)."""
    collision_margin: float = ranged(0.0, NonNeg(0.05, "m"))
    """Metres by which every box of the gripper's solid model is grown for the point count."""
    unknown_is_occupied: bool = True
    """Ours: when the object comes with what the cameras saw free (a scan's
    ``core.free_space.FreeSpace``), space no camera saw is possibly occupied: a hanging
    structure's through-hole must be proven by a line through c that the cameras saw free
    (``through_proof_exit``, ``through_proof_angle_deg``; and, with ``unknown_sweep``, the
    unknown space the closing motion sweeps counts in N_sweep). A one-view scan lacks the
    unseen material, so without this its "holes" are often only space the view never saw (the
    paper's "holes on the cup wall"). With the exit proof, over the experiment's 230 stable
    scans (docs/thresholds.md), the one-view best grasps on a false part fall from 28 to 9 and
    those on a true part rise from 36 to 38; ten views keep every ranked list. In the
    experiment (docs/experiment, stable): gbh-1 41/95 carried, 37 caged, 0 pinches on no true
    part (off: 50, 31 caged, 15 pinches on no true part); gbh-10 the same 57 trials either way.
    False: the paper's reading (the mesh alone, preset ``paper``); a plain mesh (no free
    space) is always so."""
    unknown_sweep: bool = False
    """Ours, with ``unknown_is_occupied``: also count the unknown space the closing motion
    sweeps in N_sweep. Off by default, as measured: on one view it refused every grasp of the
    true handles of mug_classic and pybullet_mug (experiment trial 0), whose L rod sweeps the
    handle's own shadow; the through-hole proof alone removed the false holes there."""
    through_proof_length: float = ranged(0.025, Pos(1.0, "m"))
    """Ours, metres: how far from c along +v and -v the through-hole rays must run in
    observed-free space (with ``unknown_is_occupied``; at most out of the bounding box): the
    length a rod through the hole occupies, the parallel grasp's bar l_h / 2 = 15 mm either
    side of c plus a rod width. Farther along the ray, unseen space is the closing sweep's
    business (an object's own shadow on one view starts 2-6 cm out on a headband: a longer
    proof refuses real handles)."""

    through_proof_angle_deg: float = ranged(60.0, Range(0.0, 89.0, unit="deg"))
    """Ours, with ``unknown_is_occupied``: the through-hole proof looks for a straight line
    through c within this angle of the hole's axis v that runs in observed-free space for
    ``through_proof_length`` on both sides of c, staying above the table band
    (:func:`~gbh_drake.core.hangability.observed_through`): a hole a camera saw through
    obliquely is proven, unseen space and a hole the table closes are not. 60 deg: the line
    then covers at least half the proof length along v on either side (12.5 mm), more than the
    half thickness of the object set's loops (<= 10 mm), so it cannot stay inside the hole's
    own slab. 0: only the axis itself, out of the bounding box, with the table band skipped
    (the rule measured in docs/experiment/unknown_occupied)."""
    through_proof_exit: bool = True
    """Ours, with ``unknown_is_occupied``: the through-hole proof's line must lead out of the
    object on both sides through observed-free space, not only ``through_proof_length`` round
    c: until it leaves the bounding box, or comes down to the table where a camera saw the
    table itself, or runs ``through_proof_max_length``
    (:func:`~gbh_drake.core.hangability.observed_through_exit`). A one-view cup's "hole" whose
    far wall the view never saw leads nowhere; a container's floor inside the table band is
    not the table. False: the local proof, ``through_proof_length`` either side of c, which
    kept 23 of the 28 false one-view best grasps and lost 3 true ones (docs/thresholds.md)."""
    table_seen_tolerance: float = ranged(0.001, NonNeg(0.01, "m"))
    """Ours, metres, with ``through_proof_exit``: how near to the table plane
    (``ground_height``) the surface a pixel measured through a hole must lie to be the table
    itself (plus the scan's depth error, 0 without noise; ``FreeSpace.saw_plane``). Below the
    height a container's floor stands at (its thickness less what it sinks into the table)."""
    through_proof_max_length: float = ranged(0.3, Pos(1.0, "m"))
    """Ours, metres, with ``through_proof_exit``: a proof line that has run this far from c in
    observed-free space leads out. 0.3: the object set's largest objects span about 30 cm, so
    their lines end at the bounding box or the table first (15 cm let a line from high inside a
    bucket end in its open interior: 4 more false structures over the 230 stable scans, no
    best grasp changed, docs/thresholds.md)."""

    # ---- scoring -------------------------------------------------------------------------------
    gamma_alpha: float = ranged(0.04, Pos(100.0, "rad^2"))
    """*paper*, rad^2: S_alpha = exp(-alpha^2 / gamma_alpha)."""
    gamma_beta: float = ranged(2.0, Pos(100.0, "rad^2"))
    """*paper*, rad^2: S_beta = exp(-beta^2 / gamma_beta) when m_i < 1."""
    top_k: int = ranged(40, Int(1, 100))
    """Number of best grasps returned for execution (the paper's ten: preset ``paper``). Of
    these the planner tries the best ``pick.max_grasps`` (10) the arm reaches
    (``pick.reach_check``): the paper's ten may all lie out of reach (a pot on its side, every
    one of them on the far handle: scores 1e-6 to 1e-16) while the near handle's rank lower;
    the ten reachable of forty are planned instead (docs/robustness.md, "More grasps offered")."""
    distinct_distance: float = ranged(0.005, NonNeg(0.05, "m", "0 with distinct_angle_deg 0: "
                                                             "no de-duplication"))
    """Ours (beyond the paper), metres: the ranked list holds distinct grasps. A grasp whose
    origin lies closer than this to that of a better ranked grasp of the same kind, turned by
    less than ``distinct_angle_deg`` from it, is a copy and takes no place in the top k
    (:func:`~gbh_drake.core.scoring.rank_grasps`). The turned approaches land on the
    neighbouring contacts (20 and 40 deg turns, contacts every 360 / n_rays_per_plane =
    10 deg): without this, a closed handle's top ten were two poses, five exact copies each.
    5 mm: two TSDF voxels, below what the scan resolves; distinct poses of one structure lie
    at least 10 deg and 14 mm apart (the loop's 8 cm turned by one contact). The paper ranks
    without it (preset ``paper``: 0)."""
    distinct_angle_deg: float = ranged(5.0, Range(0.0, 90.0, unit="deg"))
    """Ours, degrees: the angle below which two grasps of the same kind, with origins closer
    than ``distinct_distance``, are one (half the 10 deg between neighbouring contacts, so
    no two distinct contacts' grasps merge)."""
    ties_by_collisions: bool = True
    """Ours: among grasps of equal score (to 6 significant digits), fewer object points in the
    open gripper (N_c) first, i.e. the one with more room round its rods. The score saturates
    at 1 for a closed loop hooked level, so many grasps tie: a frying pan's handle slot, whose
    first-made grasp ran its straight rod 2.4 mm from the slot's edge (N_c = 3 < p_c) and came
    away empty, ranked sixth the same grasp 0.9 mm clear. False: the paper's order, ties kept
    in the order they were made (preset ``paper``)."""
    hang_slide_scale: float = ranged(0.0, NonNeg(1.0, "m", "0: the paper's score"))
    """Ours, metres: a grasp's score is multiplied by S_hang = exp(-(d / this)^2), d being how
    much deeper the object hangs once the material the grasp cages slides along the
    structure's rim to where it comes to rest (:mod:`gbh_drake.core.sliding`: the material
    slides while that takes it farther from the CoM). A hook's curve, a handle's outermost
    point or a triangle's corner hold it where it is (d = 0); the middle of a straight wire or
    bar does not (the paper's contact rule finds exactly that point: the normal there points to
    the CoM), and from a hanger's triangle side the object slides 7-10 cm to the corner. The
    paper's score has no such term: a tilted triangle side snapped top-down (``snap_tilt_max_deg``)
    scored 1.0, above the hanger's hook. Provisional: 0 (off, the paper's score) until
    swept; preset ``robust``: 0.02 (docs/robustness.md says which sweep decides it)."""
    min_miss_resultant: float = ranged(0.2, Range(0.0, 1.0))
    """Ours, in [0, 1]: when m_i < 1 but the mean of the missing rays' unit directions is
    shorter than this (the openings lie on opposite sides and cancel), the loop has no opening
    direction and beta is pi/2 (neutral). One opening of angular width phi has a mean of length
    sin(phi/2) / (phi/2), above 0.2 for phi < 290 degrees."""

    check = checker(GbhInputError)

    def with_preset(self, name: str) -> "GbhParams":
        """A copy with ``preset = name`` and the preset's values of :data:`PRESETS` fields
        (``""``: gbh_drake's defaults of those fields)."""
        if not isinstance(name, str) or name not in PRESETS:
            raise GbhInputError(f"GbhParams.preset: one of {', '.join(map(repr, PRESETS))}, got "
                                f"{name!r}")
        ours = GbhParams()
        values = {k: PRESETS[name].get(k, getattr(ours, k)) for k in _PRESET_FIELDS
                  if hasattr(self, k)}
        return dataclasses.replace(self, preset=name, **copy.deepcopy(values))

    def check_relations(self, at: tuple = ()) -> None:
        """The rules between fields no :class:`Relation` states (``at``: where these parameters
        are, for the messages)."""
        _check_nonzero(self.ground_normal, at + ("ground_normal",))
        work = self.max_contacts_per_cluster * self.n_segment_samples
        if work > MAX_SEGMENT_SAMPLES:
            raise FieldError(at + ("n_segment_samples",), f"{sibling(at, 'max_contacts_per_cluster')} x "
                             f"n_segment_samples = {work}; at most {MAX_SEGMENT_SAMPLES} per cluster "
                             "(1000 x 1000 took two minutes on a mug)")


#: Presets of :class:`GbhParams`: the fields whose values differ from gbh_drake's defaults.
#: ``paper``: the paper's rules alone, where ours go beyond them (no both-ways snap, the single
#: approach per contact point, the design note's contact angle, unseen space taken as free, the
#: top ten ranked without de-duplication, eq. 1's d1 past a narrow hole's centre, no check that
#: the closed loop holds material, ties ranked as made, a refused cluster given up). ``robust``:
#: the provisional rules of issue 42 on at their provisional values, opt-in until swept over
#: both object sets (docs/robustness.md): the hang's slide in the score, four hanging positions
#: per cluster, the rods' 2.5 mm clearance.
PRESETS: dict[str, dict] = {
    "": {},
    "paper": {"snap_tilt_max_deg": 0.0, "approach_rotations_deg": [0.0],
              "contact_angle_deg": 30.0, "unknown_is_occupied": False,
              "distinct_distance": 0.0, "distinct_angle_deg": 0.0, "d1_centred": False,
              "loop_must_enclose": False, "ties_by_collisions": False,
              "cluster_fallback": False, "top_k": 10},
    "robust": {"hang_slide_scale": 0.02, "positions_per_cluster": 4, "rod_clearance": 0.0025},
}
#: The fields a preset may set.
_PRESET_FIELDS = tuple(dict.fromkeys(k for values in PRESETS.values() for k in values))


def _init_with_preset(init):
    """``GbhParams.__init__``: the dataclass's own, then, for a known ``preset``, the preset's
    values in the fields not given (as ``gbh: {preset: ...}`` in a scenario does)."""
    fields = {f.name: f for f in dataclasses.fields(GbhParams)}
    names = list(fields)

    @functools.wraps(init)
    def __init__(self, *args, **kwargs):  # noqa: N807
        init(self, *args, **kwargs)
        if isinstance(self.preset, str) and self.preset in PRESETS:
            given = set(names[:len(args)]) | set(kwargs)
            for name in _PRESET_FIELDS:
                if name not in given:
                    f = fields[name]
                    ours = f.default if f.default_factory is dataclasses.MISSING \
                        else f.default_factory()
                    setattr(self, name, copy.deepcopy(PRESETS[self.preset].get(name, ours)))

    return __init__


GbhParams.__init__ = _init_with_preset(GbhParams.__init__)


@dataclass
class AntipodalParams:
    """Parameters of the antipodal baseline; lengths metres, angles degrees."""

    n_points: int = ranged(5000, Int(100, 50_000))
    """Poisson-disk surface points (the samples' pool and the collision cloud) for a mesh input."""
    n_samples: int = ranged(300, Int(1, 10_000))
    """Surface points A drawn as first contacts (without replacement; all if fewer)."""
    n_rolls: int = ranged(7, Int(1, 360))
    """Rotations about the closing axis tried per contact pair."""
    max_roll_deg: float = ranged(90.0, Range(0.0, 90.0, unit="deg"))
    """Degrees: rolls span [-max, +max] about the most downward approach (the course: 60; 90
    adds the side approaches a handle's pinch may need). At most 90: beyond, the approach would
    point upward."""
    contact_depth: float = ranged(0.015, NonNeg(0.08, "m"))
    """m: the contacts' distance behind the rods' tip keypoint p2 (z_G = l_f): the finger pads."""
    min_contact_depth: float = ranged(0.006, NonNeg(0.08, "m"),
                                      relations=(Relation("<=", "contact_depth", "the hand "
                                                          "backs off from contact_depth to it"),))
    """m: the hand may be backed off along -z_G (to clear the supporting surface) until the
    contacts are this close to the tips, no closer."""
    opening_margin: float = ranged(0.003, NonNeg(0.04, "m"))
    """m: the contact opening q must be at most q_open minus this (room to open around it);
    with ``narrow_pregrasp`` also the least room the approach keeps around the contacts."""
    narrow_pregrasp: bool = True
    """Beyond the course (whose hand always opens fully; GraspNet's grasps carry a width): a
    pinch whose fully open hand meets material is tried again with the fingers opened less,
    down to the contacts plus ``opening_margin`` (:func:`~gbh_drake.core.antipodal.
    pregrasp_openings`), and approached so: a rod inside a ring lying flat no longer lands on
    its far side. False: the hand always approaches fully open (the baseline of before)."""
    side_pass: bool = False
    """Beyond the course (on in ``gbh_plus``'s and ``gbh_regrasp``'s pinch tiers, off for the
    baseline): when no pinch clears the table and the collision count, a second pass draws
    its contacts only on the object's sides (normals within the friction cone of the table's
    plane), closes level, on the material's extremes, and lets the contacts come down to the
    rods' end faces: a flat object thinner than the pads' reach above the table (scissors, a
    ring lying flat), which the first pass cannot pinch (module :mod:`~gbh_drake.core.
    antipodal`, step 7). It runs only when the first pass found nothing."""
    min_width: float = ranged(0.001, NonNeg(0.08, "m"))
    """m: thinner material between the contacts is not pinched."""
    friction_coefficient: float = ranged(0.4, Pos(10.0))
    """mu: both contact normals must lie within atan(mu) of the closing axis (21.8 deg)."""
    contact_tolerance: float = ranged(0.001, NonNeg(0.01, "m"))
    """m: the swept collision volume of the rods stops this short of the contacts."""
    approach_distance: float = ranged(0.10, NonNeg(0.5, "m"))
    """m: the open gripper descends along +z_G from this far back (the pick's pre-grasp offset,
    ``PickParams.approach_distance``); the material it would pass through counts in N_c.
    0: only the grasp pose and the closing are checked (as GbH's N_c)."""
    p_c: int = ranged(10, Int(1, 50_000), relations=(_AT_MOST_N_POINTS,))
    """Keep grasps with fewer than p_c object points inside the swept solid model (GbH's p_c)."""
    collision_margin: float = ranged(0.0, NonNeg(0.05, "m"))
    """m: every box of the solid model is grown by this for the point count."""
    ground_normal: list[float] = ranged(lambda: [0.0, 0.0, 1.0], Items(3, what="components"))
    """Unit anti-gravity direction (the supporting surface's normal) in W; normalised on use."""
    ground_height: float = ranged(0.0, Range(-1.0, 1.0, unit="m"))
    """m: height of the supporting surface along ``ground_normal`` (as GbhParams')."""
    ground_clearance: float = ranged(0.002, Range(-1.0, 0.1, unit="m"))
    """m: the swept solid model's lowest corner must be at least this far above the surface."""
    check_ground: bool = True
    """Apply the supporting-surface rule (off for objects floating in space)."""
    weight_direction: float = ranged(1.0, Range(-1e3, 1e3))
    """Cost per unit of z_G . up (the approach's upward component)."""
    weight_antipodal: float = ranged(5.0, Range(-1e3, 1e3))
    """Cost per unit of 1 - mean (n . y_G)^2 over the two contacts."""
    weight_com: float = ranged(10.0, Range(-1e3, 1e3, unit="1/m"))
    """1/m: cost per metre between the CoM and the closing line."""
    top_k: int = ranged(10, Int(1, 1000))
    """Number of best grasps returned."""
    prefer_hanging: bool = False
    """Rank pinches first by how far the object's centre of mass falls as it swings about the
    pinch axis once lifted (to rest below the axis, :mod:`gbh_drake.core.pinch`, in steps of
    ``DROP_STEP``), then by cost: pinches above the centre of mass first (beyond the paper;
    ``gbh_plus`` and ``gbh_regrasp`` turn it on for their fallback and regrasp pinches)."""

    check = checker(GbhInputError)

    def check_relations(self, at: tuple = ()) -> None:
        """The rules between fields no :class:`Relation` states (``at``: where these parameters
        are, for the messages)."""
        _check_nonzero(self.ground_normal, at + ("ground_normal",))


def _check_nonzero(vector, path: tuple) -> None:
    if not np.linalg.norm(np.asarray(vector, float)) > 0:
        raise FieldError(path, f"must not be zero, got {list(vector)}")


@dataclass
class ScoopParams:
    """The scoop (beyond the paper, :mod:`gbh_drake.core.scoop`): hooking material that lies on
    the table with the wedge bar (``robot.gripper: wedge``). Its synthesis (which structures,
    where) and its execution (the press and the close). Lengths in metres, forces in newtons."""

    tilt_max_deg: float = ranged(30.0, Range(0.0, 90.0, unit="deg"))
    """Degrees: a structure is scooped only when its hole's axis is within this of the ground
    normal (material lying flat: the straight rod goes down through the hole to the table)."""
    max_height: float = ranged(0.008, Pos(0.1, "m", "the wedge rises one rod width"))
    """m: the material in the bar's path must lie this low (its top at most this far above the
    table): the wedge lifts what it slides under by its own height, one rod width (8 mm), so
    taller material (a tape roll's 19 mm wall) is pushed, not lifted onto the bar."""
    tall: bool = True
    """Offer the scoops that fail only ``max_height`` (and whose hand meets nothing) apart, as
    *tall scoops* (:mod:`gbh_drake.core.scoop`): a round underside (a thick ring's) is lifted
    onto the bar, a square one flush on the table (a tape roll's) is pushed and pinched, and the
    scan, cut 4 mm above the table, cannot tell them apart; a method tries them after its surer
    tiers (``gbh_plus``: after the regrasp). False: never offered."""
    rod_gap: float = ranged(0.0015, NonNeg(0.02, "m"))
    """m: the straight rod goes down this far inside the hole's edge (between its face and the
    material's inner surface), where it keeps the material from sliding away from the wedge."""
    hover: float = ranged(0.0005, NonNeg(0.01, "m"), relations=(
        Relation("<", "press_depth", "the press, at most press_depth below the grasp pose, "
                                     "would never reach the table"),))
    """m: the rods' tips stop this far above the table at the grasp pose; the press goes on down."""
    press_force: float = ranged(2.0, Pos(50.0, "N"))
    """N: at the grasp pose the arm goes on down until the table pushes the hand up this hard
    (the wrist load, as Franka senses it), so the wedge's edge slides along the table ..."""
    press_depth: float = ranged(0.006, Pos(0.05, "m"))
    """... at most this far (m) below the grasp pose."""
    min_lift: float = ranged(0.20, Pos(1.0, "m"))
    """m: a scoop lifts at least this far (more where the scan says so): the scan loses what
    lies within ``scan.crop_z_min`` of the table (a key ring's 2 mm keys), which may hang below
    the scooped material once lifted."""
    max_per_structure: int = ranged(24, Int(1, 1000))
    """At most this many scoops per structure (its contact points, evenly spread)."""
    p_sweep: int = ranged(1, Int(1, 50_000))
    """Keep scoops whose moving parts (the L rod above the bar, the hand) meet fewer than this
    many object points while closing (material they would push instead of the wedge lifting it)."""
    min_scooped: int = ranged(1, Int(1, 50_000))
    """At least this many object points must lie in the bar's path (something to scoop)."""


@dataclass
class RegraspParams:
    """The regrasp (beyond the paper, :mod:`gbh_drake.core.regrasp`): when GbH finds a hanging
    structure but no hook grasp of the object as it lies, pick it with a pinch (the bar folded),
    set it down in a resting pose in which GbH can hook it, re-scan and hook it."""

    max_regrasps: int = ranged(1, Int(0, 3, "each regrasp is a pick-and-place and a re-scan"))
    """How many times an object may be set down anew before the trial gives up (0: never)."""
    min_turn_deg: float = ranged(15.0, Range(0.0, 180.0, unit="deg"))
    """Degrees: resting poses this close to the present one are not offered (the same pose)."""
    min_probability: float = ranged(0.02, Range(0.0, 1.0))
    """Resting poses whose family is less probable than this are not offered (they tip over at a
    touch); a family is the orientations an object rolls between on a curved side (a roll or a
    ring on its rim: many facets, one pose; :func:`~gbh_drake.core.regrasp.family_probabilities`),
    its probability their sum."""
    max_poses: int = ranged(3, Int(1, 20))
    """At most this many resting poses are planned for, best first."""
    max_pinches: int = ranged(10, Int(1, 100))
    """At most this many of the fallback's pinches are planned for each resting pose."""


#: Completions of a partial scan (:class:`CompletionParams`): ``symmetry`` (a body of
#: revolution about a fitted axis, :mod:`gbh_drake.core.completion`).
COMPLETIONS = ("symmetry",)


@dataclass
class CompletionParams:
    """Shape completion of a partial scan (beyond the paper: its Sec. 4 names shape completion as
    the remedy for one view; method ``gbh_completed``, :mod:`gbh_drake.core.completion`). The
    unseen space is classified likely occupied, likely free or uncertain; GbH runs on the scan
    with the completed surface added, and takes as free what a camera saw free or what the
    completion calls free with ``confidence`` (the exit proof, the unknown space of a sweep)."""

    method: str = ranged("symmetry", OneOf(COMPLETIONS))
    """``symmetry``: the body as a surface of revolution about an axis fitted to the scan's
    normals (or the table's normal), its seen cells voting per ring (r, h) about the axis."""
    confidence: float = ranged(0.9, Range(0.5, 1.0, lo_open=True, hi_open=True))
    """An unseen point is likely occupied (free) when the posterior probability of its ring
    being occupied (free) is at least this: the completed surface is the contour at this level,
    and only likely-free unseen space proves a hole. Swept over both object sets before
    execution (0.7-0.99, docs/experiment/oneview_sweep): 0.9 puts the best grasp on a true part
    most often, with and without the view choice."""
    prior: float = ranged(1.0, Pos(100.0))
    """Beta pseudo-counts on each side of a ring's votes (1: uniform): a ring needs about
    ``prior`` x confidence / (1 - confidence) votes of one kind and none of the other to be
    confident (9 cells at 0.9)."""
    cell: float = ranged(0.0025, Range(0.001, 0.02, unit="m",
                                       note="the votes' grid is coarsened to 800 000 cells"))
    """m: the voting grid's cell and the rings' width in r and h: the TSDF voxel of the scan, so
    that a wall of two voxels is two rings."""
    erode: str = ranged("none", OneOf(("none", "coarse", "all")))
    """Which views' free space a completed scan takes only where a pixel's neighbours agree
    (``FreeSpace.eroded``), for the completion's votes and the GbH core: ``none`` (the
    default: every view as it is); ``coarse``, the views whose pixels are wider than ``cell``
    at the object (the first look's, 5 mm at 0.8 m: their one ray per pixel can pass beside a
    thin rim and "see through" the wall under it); ``all``. Opt-in until swept over both
    object sets (``tools/sweep_oneview.py ... --sweep erode=none,coarse``, docs/one_view.md)."""
    min_explained: float = ranged(0.7, Range(0.0, 1.0))
    """The completion is made only when at least this fraction of the measured cells lie in
    rings where they are the majority (the body of revolution explains at least this much of
    what was seen); else nothing is completed and unseen space stays unknown. Measured on
    one-view scans of the own set: bodies of revolution with a handle or a spout 0.73-0.98, a
    box or a bag 0.09-0.32 (a box seen face-on, ray cast without noise: 0.53-0.60, its face a
    disk about any axis along its normal). Provisional: not yet swept over both object sets
    (``tools/sweep_oneview.py ... --sweep min_explained=...``, docs/one_view.md)."""
