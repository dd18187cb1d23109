"""Hangability detection (paper Sec. 2.2; our reading in design.md Sec. 3), all in the mesh frame W.

Stages, each vectorised over all candidates (rays are batched into one Embree call per stage):

1. contact candidates: samples whose outward normal is within ``contact_angle_deg`` of the
   direction to the CoM h_c (a frictionless hanging contact pushes along the normal through h_c);
2. clusters of candidates (single linkage at ``cluster_radius`` sample spacings);
3. hanging position c of a cluster: on each member's segment to h_c, only the first free interval
   (up to the first surface hit, and at most ``max_hanging_distance`` from the contact point: the
   gripper's reach), the point farthest from the surface; the cluster keeps its
   member with the largest such clearance (the paper's one position per cluster) or, beyond the
   paper, up to ``positions_per_cluster`` of them by non-maximum suppression (a cluster that
   spans a cup's wall and its handle keeps both). Positions inside another one's free ball
   coincide;
4. hanging direction v: the normal u of the plane through c whose K rays hit the mesh most often
   (coarse Fibonacci sphere, then cones of shrinking size around the best). Ties (e.g. a ring
   seen from slightly tilted planes: all rays still hit) go to the plane with the smallest mean
   hit distance, which is the plane that cuts the material most squarely;
5. through-hole test: rays from c along +v and -v must both miss. When the object comes with
   what the cameras saw free (``ObjectModel.free_space``, a scan's) and
   ``GbhParams.unknown_is_occupied`` is set, a straight line through c near the axis must also
   lead out of the object through observed-free space (:func:`observed_through_exit`; or, with
   ``through_proof_exit`` off, stay free for ``through_proof_length`` round c,
   :func:`observed_through_line`; or the axis alone, :func:`observed_through`): a ray that
   "misses" because the material it would meet was never seen proves no hole.
"""

from __future__ import annotations

import numpy as np

from gbh_drake.core.completion import CompletedFreeSpace
from gbh_drake.core.free_space import FreeSpace
from gbh_drake.core.geometry import fibonacci_cap, fibonacci_sphere, orthonormal_basis, unit
from gbh_drake.core.lazy import lazy_module
from gbh_drake.core.object_model import ObjectModel, prepare_object
from gbh_drake.core.params import GbhParams
from gbh_drake.core.results import HangabilityReport, HangingStructure, RefusedPosition
from gbh_drake.core.sliding import rim_slide

csgraph = lazy_module("scipy.sparse.csgraph")
sparse = lazy_module("scipy.sparse")
spatial = lazy_module("scipy.spatial")
trimesh = lazy_module("trimesh")

#: Each refinement level searches a cone this many times narrower than the previous one.
_REFINE_SHRINK = 4.0
#: A dip of the rim's distance from the CoM of at most this many sample spacings does not stop
#: the material sliding along it (the scan's surface noise; :func:`~gbh_drake.core.sliding.rim_slide`).
RIM_TOLERANCE_SPACINGS = 0.5
#: Refinement levels after the coarse sphere search.
_REFINE_LEVELS = 2
#: The through-hole rays are checked in the free space this far (in sample spacings) beyond
#: the object's bounding box, at steps of half a sample spacing.
_RAY_BEYOND_BOX_SPACINGS = 2.0


def detect_hangable_structures(
    mesh: trimesh.Trimesh | ObjectModel, params: GbhParams, seed: int = 0,
    free_space: FreeSpace | None = None,
) -> list[HangingStructure]:
    """Hangable structures of ``mesh`` (vertices in W, metres), best (largest m) first;
    ``seed``: the surface sampler's (when ``mesh`` is not prepared yet); ``free_space``: what
    the cameras saw free (else the prepared model's, if any; see the module docstring, 5.).

    An object with nothing hangable gives an empty list. Raises GbhInputError for unusable input.
    """
    return detect_with_report(mesh, params, seed, free_space)[0]


def detect_with_report(
    mesh: trimesh.Trimesh | ObjectModel, params: GbhParams, seed: int = 0,
    free_space: FreeSpace | None = None,
) -> tuple[list[HangingStructure], HangabilityReport]:
    """:func:`detect_hangable_structures` and what the detector saw and refused on the way
    (:class:`~gbh_drake.core.results.HangabilityReport`)."""
    obj = prepare_object(mesh, params, seed, free_space)
    free = active_free_space(obj, params)
    idx = contact_candidates(obj, params)
    report = HangabilityReport(len(obj.points), len(idx), params.contact_angle_deg,
                               _best_contact_angle(obj), exit_proof=free is not None)
    labels = cluster_points(obj.points[idx], params.cluster_radius * obj.spacing,
                            params.min_cluster_size)
    sel = _subsample_clusters(labels, params.max_contacts_per_cluster)
    lab = labels[sel]
    members = member_positions(obj, idx[sel], lab, params)
    first, clear_all = chosen_members(obj, members, lab, params)
    c_all, contact_all = members[0][first], members[2][first]
    keep, small = select_positions(c_all, clear_all, params)
    c, clearance, contact = c_all[keep], clear_all[keep], contact_all[keep]
    report.clusters, report.positions = len(np.unique(lab)), len(keep)
    report.merged = len(c_all) - len(small) - len(keep)
    report.refused += [RefusedPosition(c_all[i], float(clear_all[i]), "too small")
                       for i in small]
    if len(c) == 0:
        return [], report
    v, t, dirs, mesh_through, through = _tested_positions(obj, free, c, params)
    report.refused += _refusals(c, clearance, v, t, mesh_through, through)
    if params.cluster_fallback:
        more, clear2 = fallback_positions(obj, members, lab, np.delete(first, small), c,
                                          clearance, through, params)
        if len(more):
            c2, contact2 = members[0][more], members[2][more]
            v2, t2, dirs2, mesh2, through2 = _tested_positions(obj, free, c2, params)
            tried = _tried_in_order(lab[more], through2, params.positions_per_cluster)
            report.positions += int(tried.sum())
            report.refused += _refusals(c2[tried], clear2[tried], v2[tried], t2[tried],
                                        mesh2[tried], through2[tried])
            take = tried & through2
            c, clearance, contact = np.r_[c, c2[take]], np.r_[clearance, clear2[take]], \
                np.r_[contact, contact2[take]]
            v, t, dirs = np.r_[v, v2[take]], np.r_[t, t2[take]], np.r_[dirs, dirs2[take]]
            through = np.r_[through, through2[take]]
    structures = [
        _structure(c[i], v[i], t[i], dirs[i], clearance[i], contact[i], obj.com,
                   RIM_TOLERANCE_SPACINGS * obj.spacing)
        for i in np.flatnonzero(through)
    ]
    structures.sort(key=lambda s: (-s.m, -s.clearance))
    report.structures = len(structures)
    return structures, report


def _refusals(c: np.ndarray, clearance: np.ndarray, v: np.ndarray, t: np.ndarray,
              mesh_through: np.ndarray, through: np.ndarray) -> list[RefusedPosition]:
    """The refused positions among ``c`` (P, 3), rule by rule (the mesh's through-hole test,
    then the exit proof)."""
    m = np.isfinite(t).mean(axis=1)
    return [RefusedPosition(c[i], float(clearance[i]), rule, v[i], float(m[i]))
            for rule, refused in (("not a through-hole", ~mesh_through),
                                  ("exit proof", mesh_through & ~through))
            for i in np.flatnonzero(refused)]


def _tried_in_order(labels: np.ndarray, passing: np.ndarray, per_cluster: int) -> np.ndarray:
    """Mask of the positions (in order, ``labels`` their clusters') tried before each cluster
    has ``per_cluster`` passing ones: a cluster's later positions are not needed."""
    tried = np.zeros(len(labels), dtype=bool)
    found: dict[int, int] = {}
    for i, label in enumerate(labels):
        if found.get(int(label), 0) < per_cluster:
            tried[i] = True
            found[int(label)] = found.get(int(label), 0) + int(passing[i])
    return tried


def _tested_positions(obj: ObjectModel, free: FreeSpace | None, c: np.ndarray,
                      params: GbhParams
                      ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(v, t, dirs, mesh_through, through) of the hanging positions ``c`` (P, 3): their
    hanging directions (:func:`hanging_directions`), whether the mesh makes each a
    through-hole, and whether it is one (with the cameras' free space ``free``, by the exit
    proof too)."""
    v, t, dirs = hanging_directions(obj, c, params)
    mesh_through = through_hole(obj, c, v)
    through = mesh_through.copy()
    if free is not None:
        floor = unknown_floor(obj, free, params)
        if params.through_proof_exit:
            if params.ground_clearance < 0:
                floor = -np.inf
            through &= observed_through_exit(obj, free, c, v, params.ground_normal,
                                             params.ground_height, floor,
                                             params.through_proof_max_length,
                                             params.through_proof_angle_deg,
                                             params.table_seen_tolerance)
        elif params.through_proof_angle_deg > 0:
            if params.ground_clearance < 0:  # no supporting surface: no table band either
                floor = -np.inf
            through &= observed_through_line(obj, free, c, v, params.ground_normal, floor,
                                             params.through_proof_length,
                                             params.through_proof_angle_deg)
        else:
            through &= observed_through(obj, free, c, v, params.ground_normal, floor,
                                        params.through_proof_length)
    return v, t, dirs, mesh_through, through


def _best_contact_angle(obj: ObjectModel) -> float:
    """The smallest angle (deg) between a sample's outward normal and its direction to the CoM
    (samples within a spacing of the CoM left out, as by :func:`contact_candidates`)."""
    cos, far = _normal_to_com_cosines(obj)
    return float(np.degrees(np.arccos(np.clip(cos[far].max(), -1.0, 1.0)))) if far.any() \
        else float("nan")


def contact_candidates(obj: ObjectModel, params: GbhParams) -> np.ndarray:
    """Indices of samples whose outward normal points to the CoM within ``contact_angle_deg``.
    On a completed scan (its free space a :class:`~gbh_drake.core.completion.CompletedFreeSpace`)
    only samples of material a camera saw: a hanging contact on the completion's guess of the
    unseen side would hook a loop that may not be there (the completion closes false holes and
    counts in the collision checks, it makes no structure)."""
    cos, far = _normal_to_com_cosines(obj)
    ok = (cos > np.cos(np.radians(params.contact_angle_deg))) & far
    if isinstance(obj.free_space, CompletedFreeSpace) and obj.free_space.completion is not None:
        idx = np.flatnonzero(ok)
        ok[idx[obj.free_space.completion.on_surface(obj.points[idx])]] = False
    return np.flatnonzero(ok)


def _normal_to_com_cosines(obj: ObjectModel) -> tuple[np.ndarray, np.ndarray]:
    """(cos (n,), far (n,)): the cosine of the angle between each sample's outward normal and
    its direction to the CoM, and whether it is farther than a sample spacing from the CoM."""
    to_com = obj.com - obj.points
    dist = np.linalg.norm(to_com, axis=1)
    return np.sum(obj.normals * to_com, axis=1) / np.maximum(dist, 1e-12), dist > obj.spacing


def cluster_points(points: np.ndarray, radius: float, min_size: int) -> np.ndarray:
    """Single-linkage cluster labels (n,) of ``points`` (n, 3) at ``radius`` metres.

    Labels are connected-component numbers (>= 0); clusters smaller than ``min_size`` get -1.
    """
    n = len(points)
    if n == 0:
        return np.zeros(0, dtype=int)
    pairs = spatial.cKDTree(points).query_pairs(radius, output_type="ndarray")
    graph = sparse.coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    _, labels = csgraph.connected_components(graph, directed=False)
    sizes = np.bincount(labels)
    return np.where(sizes[labels] >= min_size, labels, -1)


def _subsample_clusters(labels: np.ndarray, max_per_cluster: int) -> np.ndarray:
    """Indices of at most ``max_per_cluster`` members of every cluster (label >= 0), evenly
    strided (the samples are in random order, so this is a seeded random subset)."""
    idx = np.flatnonzero(labels >= 0)
    order = idx[np.argsort(labels[idx], kind="stable")]
    lab = labels[order]
    start = np.searchsorted(lab, lab, side="left")
    size = np.searchsorted(lab, lab, side="right") - start
    rank = np.arange(len(order)) - start
    stride = np.maximum(1, -(-size // max(max_per_cluster, 1)))  # ceil(size / max)
    return np.sort(order[rank % stride == 0])


def hanging_positions(
    obj: ObjectModel, idx: np.ndarray, labels: np.ndarray, params: GbhParams
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Hanging positions (P, 3), their clearances (P,) and contact points (P, 3), metres.

    ``idx`` are sample indices of contact candidates and ``labels`` their cluster labels:
    each cluster's positions (:func:`cluster_positions`); positions with clearance <
    ``min_clearance`` are dropped and coincident ones (within another's free ball) merged,
    keeping the larger ball.
    """
    c, clearance, contact = cluster_positions(obj, idx, labels, params)
    keep, _ = select_positions(c, clearance, params)
    return c[keep], clearance[keep], contact[keep]


def select_positions(c: np.ndarray, clearance: np.ndarray, params: GbhParams
                     ) -> tuple[np.ndarray, np.ndarray]:
    """(kept, too small): indices of the positions c (P, 3) kept (clearance (P,) at least
    ``min_clearance``, and not inside a kept one's free ball: :func:`_merge_coincident`) and
    of those under ``min_clearance``."""
    big = np.flatnonzero(clearance >= params.min_clearance)
    keep = big[_merge_coincident(c[big], clearance[big], params.dedup_radius_factor)]
    return keep, np.flatnonzero(clearance < params.min_clearance)


def cluster_positions(
    obj: ObjectModel, idx: np.ndarray, labels: np.ndarray, params: GbhParams
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The hanging positions of the clusters (P, 3), their exact clearances (P,) and contact
    points (P, 3), metres, in the order of the clusters' labels: :func:`member_positions`,
    then :func:`chosen_members`."""
    members = member_positions(obj, idx, labels, params)
    first, clearance = chosen_members(obj, members, labels, params)
    return members[0][first], clearance, members[2][first]


def member_positions(
    obj: ObjectModel, idx: np.ndarray, labels: np.ndarray, params: GbhParams
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Each contact candidate's hanging position (M, 3), its approximate clearance (M,) and the
    contact point (M, 3), metres (``idx``: sample indices, ``labels`` their clusters').

    For each member, the free part of its segment to the CoM (up to the first hit, at most
    ``max_hanging_distance`` long; with ``hang_segment_seen`` only up to where it leaves the
    space the cameras saw free, :func:`seen_prefix`) is sampled and its sample farthest from
    the surface is the member's position."""
    p = obj.points[idx]
    if len(p) == 0:
        return np.zeros((0, 3)), np.zeros(0), np.zeros((0, 3))
    d = obj.com - p
    length = np.linalg.norm(d, axis=1)
    d /= length[:, None]
    eps = 0.05 * obj.spacing  # leave the sample's own triangle before casting
    reach = np.minimum(length, params.max_hanging_distance)
    free = np.minimum(obj.cast(p + eps * d, d) + eps, reach)
    frac = np.arange(1, params.n_segment_samples + 1) / params.n_segment_samples
    samples = p[:, None] + d[:, None] * (free[:, None, None] * frac[None, :, None])
    dist = obj.approx_distance(samples.reshape(-1, 3)).reshape(len(p), -1)
    seen = active_free_space(obj, params) if params.hang_segment_seen else None
    if seen is not None:
        dist[~seen_prefix(obj, seen, samples, params)] = -np.inf
    k = dist.argmax(axis=1)
    return samples[np.arange(len(p)), k], dist[np.arange(len(p)), k], p


def chosen_members(obj: ObjectModel, members: tuple[np.ndarray, np.ndarray, np.ndarray],
                   labels: np.ndarray, params: GbhParams) -> tuple[np.ndarray, np.ndarray]:
    """(indices (P,) of the members whose positions the clusters keep, in the order of the
    clusters' labels; their exact clearances (P,), m). A cluster keeps the position of its
    member with the largest approximate clearance, the paper's one per cluster, or, with
    ``positions_per_cluster`` > 1, up to that many by non-maximum suppression over its
    members' exact clearances: largest first, each kept position removing the others inside
    its free ball, so a cluster that spans a cup's inside and its handle keeps both."""
    member_c, member_clear, _ = members
    if len(member_c) == 0:
        return np.zeros(0, dtype=int), np.zeros(0)
    order = np.lexsort((-member_clear, labels))
    first = order[np.r_[True, np.diff(labels[order]) != 0]]
    if params.positions_per_cluster > 1:
        exact = obj.distance(member_c)
        first = np.concatenate([
            members_of[_merge_coincident(member_c[members_of], exact[members_of],
                                         params.dedup_radius_factor)
                       [:params.positions_per_cluster]]
            for members_of in (np.flatnonzero(labels == lab) for lab in np.unique(labels))])
        return first, exact[first]
    return first, obj.distance(member_c[first])


def fallback_positions(obj: ObjectModel, members: tuple[np.ndarray, np.ndarray, np.ndarray],
                       labels: np.ndarray, chosen: np.ndarray, c: np.ndarray,
                       clearance: np.ndarray, through: np.ndarray, params: GbhParams
                       ) -> tuple[np.ndarray, np.ndarray]:
    """(indices, exact clearances (m)) of the members (in order: cluster by cluster, largest
    exact clearance first) whose positions a cluster tries next when no position it chose
    stands as a hanging structure (``GbhParams.cluster_fallback``): each was refused, or merged
    into a position that was. ``chosen``: the members whose positions the clusters chose (at least
    ``min_clearance``); ``c`` (P, 3): the positions tested, with their ``clearance`` (P,) and
    verdict ``through`` (P,). A candidate lies outside the free ball of every tested position
    (inside one it is that position again), has at least ``min_clearance``, and is not inside
    a better candidate's ball (non-maximum suppression, as :func:`chosen_members`)."""
    member_c = members[0]
    radius = params.dedup_radius_factor * clearance
    passing_c, passing_r = c[through], radius[through]
    stands = np.any(np.linalg.norm(member_c[chosen, None] - passing_c[None], axis=2)
                    < passing_r[None], axis=1) if len(passing_c) else \
        np.zeros(len(chosen), dtype=bool)
    lost = np.setdiff1d(labels[chosen], labels[chosen[stands]])
    out, out_clear = [], []
    for label in lost:
        mine = np.flatnonzero(labels == label)
        mine = mine[np.all(np.linalg.norm(member_c[mine, None] - c[None], axis=2)
                           >= radius[None], axis=1)]
        if len(mine) == 0:
            continue
        exact = obj.distance(member_c[mine])
        big = exact >= params.min_clearance
        mine, exact = mine[big], exact[big]
        kept = _merge_coincident(member_c[mine], exact, params.dedup_radius_factor)
        out.append(mine[kept])
        out_clear.append(exact[kept])
    if not out:
        return np.zeros(0, dtype=int), np.zeros(0)
    return np.concatenate(out), np.concatenate(out_clear)


def seen_prefix(obj: ObjectModel, free: FreeSpace, samples: np.ndarray, params: GbhParams
                ) -> np.ndarray:
    """Mask (P, K): the samples (P, K, 3, W) of each contact-to-CoM segment, in order from the
    contact, that come before the segment first leaves the space the cameras saw free
    (``GbhParams.hang_segment_seen``). The samples before the first seen-free one are kept (a
    free-space margin round the contact's own surface is never seen free), and so are those
    below the table band (:func:`unknown_floor`, which no camera sees into; none without a
    supporting surface, ``ground_clearance`` < 0). A segment that
    runs from seen-free space into unseen space has passed through material the scan lost (a
    gap the TSDF left in a wall behind a handle): the free ball beyond it lies in a cavity,
    no hook reaches it that way, and it is refused by the exit proof, while the cluster's
    true position (in the handle, short of the wall) would have passed. A segment nowhere
    seen free is kept whole."""
    n = np.asarray(params.ground_normal, dtype=float)
    floor = unknown_floor(obj, free, params) if params.ground_clearance >= 0 else -np.inf
    free_mask = samples @ (n / np.linalg.norm(n)) <= floor
    ask = ~free_mask
    free_mask[ask] = free.known_free(samples[ask])
    after_free = np.cumsum(free_mask, axis=1) - free_mask > 0  # a seen-free sample before
    left = np.cumsum(~free_mask & after_free, axis=1) > 0
    return ~left


def _merge_coincident(c: np.ndarray, clearance: np.ndarray, factor: float) -> np.ndarray:
    """Indices of positions kept by non-maximum suppression: largest clearance first, each kept
    position removes the others inside its free ball (radius ``factor * clearance``)."""
    order = np.argsort(-clearance, kind="stable")
    dist = np.linalg.norm(c[:, None] - c[None], axis=2)
    alive = np.ones(len(c), dtype=bool)
    keep = []
    for i in order:
        if alive[i]:
            keep.append(i)
            alive &= dist[i] >= factor * clearance[i]
    return np.asarray(keep, dtype=int)


def plane_ray_directions(normals: np.ndarray, n_rays: int) -> np.ndarray:
    """(..., K, 3) unit directions of ``n_rays`` rays equally spaced in the planes normal to
    the unit ``normals`` (..., 3)."""
    shape = normals.shape[:-1]
    e1, e2 = orthonormal_basis(normals.reshape(-1, 3))
    theta = 2.0 * np.pi * np.arange(n_rays) / n_rays
    dirs = np.cos(theta)[None, :, None] * e1[:, None] + np.sin(theta)[None, :, None] * e2[:, None]
    return dirs.reshape(*shape, n_rays, 3)


def _evaluate_planes(
    obj: ObjectModel, c: np.ndarray, normals: np.ndarray, n_rays: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Cast ``n_rays`` rays from each c (P, 3) in the planes ``normals`` (P, D, 3).

    Returns the index (P,) of the best plane per position (most hits, then smallest mean hit
    distance), the hit distances (P, D, K) (inf = miss) and the ray directions (P, D, K, 3).
    """
    dirs = plane_ray_directions(normals, n_rays)
    origins = np.broadcast_to(c[:, None, None], dirs.shape)
    t = obj.cast(origins.reshape(-1, 3), dirs.reshape(-1, 3)).reshape(dirs.shape[:-1])
    hit = np.isfinite(t)
    count = hit.sum(axis=2)
    mean_t = np.where(hit, t, 0.0).sum(axis=2) / np.maximum(count, 1)
    tie_break = np.where(count == count.max(axis=1, keepdims=True), mean_t, np.inf)
    return tie_break.argmin(axis=1), t, dirs


def hanging_directions(
    obj: ObjectModel, c: np.ndarray, params: GbhParams
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Hanging directions v (P, 3) at positions c (P, 3), with their planes' hit distances (P, K)
    and ray directions (P, K, 3): a coarse Fibonacci-sphere search, then shrinking cones."""
    P, K = len(c), params.n_rays_per_plane
    sphere = fibonacci_sphere(max(params.n_plane_normals // 2, 1), hemisphere=True)
    normals = np.broadcast_to(sphere, (P, *sphere.shape))
    half_angle = np.radians(params.refine_cone_deg)
    for level in range(_REFINE_LEVELS + 1):
        best, t, dirs = _evaluate_planes(obj, c, normals, K)
        rows = np.arange(P)
        v, t, dirs = normals[rows, best], t[rows, best], dirs[rows, best]
        if level < _REFINE_LEVELS:
            normals = np.stack([fibonacci_cap(u, half_angle, params.n_refine_normals) for u in v])
            half_angle /= _REFINE_SHRINK
    return v, t, dirs


def through_hole(obj: ObjectModel, c: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Mask (P,): the rays from c along +v and along -v both miss the mesh."""
    t = obj.cast(np.concatenate([c, c]), np.concatenate([v, -v]))
    return ~np.isfinite(t).reshape(2, -1).any(axis=0)


def active_free_space(obj: ObjectModel, params: GbhParams) -> FreeSpace | None:
    """The model's free space when ``params.unknown_is_occupied`` asks for it, else None."""
    return obj.free_space if params.unknown_is_occupied else None


def unknown_floor(obj: ObjectModel, free: FreeSpace, params: GbhParams) -> float:
    """Height (m, along ``params.ground_normal``, as ``ground_height``) below which unseen space
    is not held against a hole or a sweep: two free-space margins above the lowest point of the
    mesh, and at least one above the supporting plane. A scan cuts the object a little above
    the table (nothing lower is in the mesh) and the table's own depth band is no camera's free
    space; under an overhang (a pan's handle) the table is in the object's shadow as well."""
    n = np.asarray(params.ground_normal, dtype=float)
    n = n / np.linalg.norm(n)
    lowest = float((np.asarray(obj.mesh.vertices) @ n).min())
    return max(params.ground_height + free.margin, lowest + 2.0 * free.margin)


def observed_through(obj: ObjectModel, free: FreeSpace, c: np.ndarray, v: np.ndarray,
                     ground_normal=(0.0, 0.0, 1.0), floor: float = -np.inf,
                     max_length: float = np.inf) -> np.ndarray:
    """Mask (P,): the rays from c (P, 3) along +v and -v (P, 3) run in known-free space
    (``free.known_free``: seen free, or completed free with confidence) from c until they are
    ``_RAY_BEYOND_BOX_SPACINGS`` sample spacings out of the mesh's bounding box, or
    ``max_length`` (m) from c if that comes
    first (``GbhParams.through_proof_length``), sampled every half spacing. All samples
    must be free: one unseen stretch may be the material the view did not see. Samples lower
    than ``floor`` along ``ground_normal`` (:func:`unknown_floor`) are not asked: the table is
    not the object (the scan cut it away), and no camera sees into it."""
    if len(c) == 0:
        return np.zeros(0, dtype=bool)
    origins = np.concatenate([c, c])
    dirs = np.concatenate([v, -v])
    lo, hi = np.asarray(obj.mesh.bounds, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        exit_t = np.where(dirs > 0, (hi - origins) / dirs,
                          np.where(dirs < 0, (lo - origins) / dirs, np.inf)).min(axis=1)
    length = np.minimum(np.maximum(exit_t, 0.0) + _RAY_BEYOND_BOX_SPACINGS * obj.spacing,
                        max_length)
    step = 0.5 * obj.spacing
    n = int(np.ceil(length.max() / step)) + 1
    t = np.arange(n) * step  # (n,)
    used = t[None, :] <= length[:, None]  # (2P, n)
    samples = origins[:, None] + t[None, :, None] * dirs[:, None]
    n_g = np.asarray(ground_normal, dtype=float)
    used &= samples @ (n_g / np.linalg.norm(n_g)) > floor
    free_mask = np.ones(used.shape, dtype=bool)
    free_mask[used] = free.known_free(samples[used])
    return free_mask.all(axis=1).reshape(2, -1).all(axis=0)


#: Tilts (fractions of the largest angle) and azimuth steps (deg) of the lines tried through c
#: by :func:`observed_through_line`.
_LINE_TILTS = (0.0, 0.25, 0.5, 0.75, 1.0)
_LINE_AZIMUTH_STEP_DEG = 30.0


def observed_through_line(obj: ObjectModel, free: FreeSpace, c: np.ndarray, v: np.ndarray,
                          ground_normal=(0.0, 0.0, 1.0), floor: float = -np.inf,
                          length: float = 0.025, max_angle_deg: float = 60.0) -> np.ndarray:
    """Mask (P,): some straight line through c (P, 3) within ``max_angle_deg`` of the hole's
    axis v (P, 3) runs in known-free space (``free.known_free``: seen free at its margin, or
    completed free with confidence) for
    ``length`` (m) on both sides of c, every sample (half a sample spacing apart) higher than
    ``floor`` along ``ground_normal`` (:func:`unknown_floor`).

    A camera that saw through the hole saw such a line: the line crosses the loop's plane at c
    and leaves the loop's slab on both sides (see ``GbhParams.through_proof_angle_deg``).
    Space no camera saw (the far side of a cup one view looked into) proves nothing, nor does
    a line that runs into the table band: a hole whose every line within the angle ends in
    the table (a ring lying flat, a mug resting on its handle, a cup's unseen bottom) is
    closed by the table. Lines tried: tilts of 0, 1/4 ... 1 x the angle from v, every 30 deg
    of azimuth."""
    if len(c) == 0:
        return np.zeros(0, dtype=bool)
    d = _proof_lines(v, max_angle_deg)  # (P, L, 3)
    step = 0.5 * obj.spacing
    s = np.arange(-length, length + 0.5 * step, step)  # (S,)
    samples = c[:, None, None] + s[None, None, :, None] * d[:, :, None]  # (P, L, S, 3)
    n_g = np.asarray(ground_normal, dtype=float)
    above = samples @ (n_g / np.linalg.norm(n_g)) > floor
    ok = above.all(axis=2)  # (P, L): lines that stay out of the table band
    free_mask = np.zeros(samples.shape[:3], dtype=bool)
    ask = ok[:, :, None] & np.ones(len(s), dtype=bool)
    free_mask[ask] = free.known_free(samples[ask])
    return (ok & free_mask.all(axis=2)).any(axis=1)


def _proof_lines(v: np.ndarray, max_angle_deg: float) -> np.ndarray:
    """(P, L, 3) unit directions of the proof lines through each hole: the axis v (P, 3), then
    tilts of 1/4 ... 1 x ``max_angle_deg`` from it, every 30 deg of azimuth."""
    v = np.asarray(v, dtype=float)
    v = v / np.linalg.norm(v, axis=1, keepdims=True)
    e1, e2 = orthonormal_basis(v)
    tilts = np.radians(max_angle_deg) * np.asarray(_LINE_TILTS)
    azimuths = np.radians(np.arange(0.0, 360.0, _LINE_AZIMUTH_STEP_DEG))
    pairs = [(0.0, 0.0)] + [(t, a) for t in tilts[1:] for a in azimuths]
    ct = np.array([np.cos(t) for t, _ in pairs])
    st_ca = np.array([np.sin(t) * np.cos(a) for t, a in pairs])
    st_sa = np.array([np.sin(t) * np.sin(a) for t, a in pairs])
    return (ct[None, :, None] * v[:, None] + st_ca[None, :, None] * e1[:, None]
            + st_sa[None, :, None] * e2[:, None])


def observed_through_exit(obj: ObjectModel, free: FreeSpace, c: np.ndarray, v: np.ndarray,
                          ground_normal=(0.0, 0.0, 1.0), ground_height: float = 0.0,
                          floor: float = -np.inf, max_length: float = 0.3,
                          max_angle_deg: float = 60.0,
                          table_tolerance: float = 0.001) -> np.ndarray:
    """Mask (P,): some straight line through c (P, 3) within ``max_angle_deg`` of the hole's
    axis v (P, 3) leads out of the object on both sides through space the cameras saw free
    (``GbhParams.through_proof_exit``). Each half-line is followed from c, every half sample
    spacing, until it

    * leaves the mesh's bounding box grown by ``_RAY_BEYOND_BOX_SPACINGS`` sample spacings:
      out of the object;
    * or comes down to ``floor`` (the table band, :func:`unknown_floor`, along
      ``ground_normal``): out of the object only if a camera saw the table there, through
      everything above it (:meth:`FreeSpace.saw_plane` with the plane ``ground_normal . p =
      ground_height``, within ``table_tolerance`` m). A container's floor or a cup's bottom
      inside the band is not the table;
    * or runs ``max_length`` (m) from c: far enough;

    and every sample before that end must be known free (:meth:`FreeSpace.known_free`: seen
    free, or, on a completed scan, free by the completion with confidence; never merely
    unseen).
    A hole's neighbourhood seen free proves only that much: the cup one view looked into has a
    far wall 4-7 cm out that the view never saw, and a line that ends there leads nowhere
    (docs/thresholds.md)."""
    if len(c) == 0:
        return np.zeros(0, dtype=bool)
    d = _proof_lines(v, max_angle_deg)  # (P, L, 3)
    n_g = np.asarray(ground_normal, dtype=float)
    n_g = n_g / np.linalg.norm(n_g)
    step = 0.5 * obj.spacing
    t = np.arange(0.0, max_length + 0.5 * step, step)  # (K,)
    grow = _RAY_BEYOND_BOX_SPACINGS * obj.spacing
    lo, hi = np.asarray(obj.mesh.bounds, dtype=float)
    ok = np.ones(d.shape[:2], dtype=bool)  # (P, L)
    for sign in (1.0, -1.0):
        dirs = sign * d
        samples = c[:, None, None] + t[None, None, :, None] * dirs[:, :, None]  # (P, L, K, 3)
        out = ((samples < lo - grow) | (samples > hi + grow)).any(axis=3)
        below = samples @ n_g <= floor
        ends = out | below
        end = np.where(ends.any(axis=2), ends.argmax(axis=2), len(t))  # (P, L)
        asked = np.arange(len(t))[None, None, :] < end[:, :, None]
        free_mask = np.ones(asked.shape, dtype=bool)
        free_mask[asked] = free.known_free(samples[asked])
        side = free_mask.all(axis=2)
        at_floor = (end < len(t)) & below[np.arange(len(c))[:, None],
                                          np.arange(d.shape[1])[None], np.minimum(end, len(t) - 1)]
        ask = at_floor & side
        if ask.any():
            down = dirs[ask] @ n_g  # < 0: the line comes down to the floor
            c_at = np.broadcast_to(c[:, None], dirs.shape)[ask]
            s_floor = (floor - c_at @ n_g) / np.where(down < 0, down, -1.0)
            crossing = c_at + np.maximum(s_floor, 0.0)[:, None] * dirs[ask]
            side[ask] = free.saw_plane(crossing, n_g, ground_height, table_tolerance)
        ok &= side
    return ok.any(axis=1)


def _structure(
    c: np.ndarray, v: np.ndarray, t: np.ndarray, dirs: np.ndarray, clearance: float,
    contact: np.ndarray, com: np.ndarray, rim_tolerance: float,
) -> HangingStructure:
    """A HangingStructure from the chosen plane's hit distances t (K,) and directions (K, 3),
    with how far each hit point's material slides from the CoM ``com`` along the rim
    (:func:`~gbh_drake.core.sliding.rim_slide`, dips of ``rim_tolerance`` m ignored)."""
    hit = np.isfinite(t)
    miss_mean = dirs[~hit].mean(axis=0) if (~hit).any() else np.zeros(3)
    H = c + t[hit, None] * dirs[hit]
    hit_index = np.flatnonzero(hit)
    return HangingStructure(
        c=c.copy(),
        v=unit(v),
        H=H,
        m=float(hit.mean()),
        a=unit(miss_mean),
        clearance=float(clearance),
        contact_point=contact.copy(),
        n_rays=len(t),
        miss_directions=dirs[~hit],
        hit_index=hit_index,
        hang_drop=rim_slide(H, hit_index, len(t), com, rim_tolerance),
    )
