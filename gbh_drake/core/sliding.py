"""Where hooked material slides to once the object hangs (beyond the paper), all in W.

A hooked object hangs with its centre of mass (CoM) straight below the point p of its material
that rests on the loop, its CoM then ``|p - CoM|`` below that point. Material that threads
through the loop can slide through it: p moves along the material, and it does so while that
lowers the CoM, i.e. while ``|p - CoM|`` grows. It comes to rest where ``|p - CoM|`` has a local
maximum along the material: the top of a hook's curve, a handle's outermost point, the corner
of a wire triangle. A point in the middle of a straight wire or bar (the foot of the
perpendicular from the CoM, which the paper's contact rule finds: there the normal points to
the CoM) is a local *minimum*: from there the material slides to the wire's end, and the object
hangs deeper by the difference.

Two uses, one idea:

* :func:`rim_slide`, for scoring: along a hanging structure's rim (the hit points of its ray
  plane, in ray order), how much deeper each hit point would let the object hang once the
  material slides to the local maximum it leads to (``GbhParams.hang_slide_scale``);
* :func:`slide_region`, for the lift: the scan points the caged material can reach by sliding
  through the closed loop, through material whose cross-section fits the loop's opening
  (``planning.pick`` bounds the lift over every one of them).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from gbh_drake.core.lazy import lazy_module

csgraph = lazy_module("scipy.sparse.csgraph")
sparse = lazy_module("scipy.sparse")
spatial = lazy_module("scipy.spatial")


def rim_slide(H: np.ndarray, hit_index: np.ndarray, n_rays: int, com: np.ndarray,
              tolerance: float = 0.0) -> np.ndarray:
    """(K,) metres: for each hit point ``H`` (K, 3) of a structure's rim (``hit_index`` (K,):
    its ray's index among the plane's ``n_rays``, so adjacent rays are adjacent along the rim;
    a ray that missed ends the rim there), how much farther from the centre of mass ``com``
    (3,) the material gets by sliding from it along the rim while that takes it farther
    (quasi-statically, each way; the larger). 0 at a local maximum of ``|p - com|`` (a stable
    hang point). ``tolerance`` (m): a dip of at most this much does not stop the slide (a
    scan's surface noise)."""
    H = np.asarray(H, dtype=float).reshape(-1, 3)
    idx = np.asarray(hit_index, dtype=int).reshape(-1)
    if len(H) == 0:
        return np.zeros(0)
    r = np.full(n_rays, np.nan)
    r[idx % n_rays] = np.linalg.norm(H - np.asarray(com, dtype=float), axis=1)
    out = np.zeros(len(H))
    for i, j in enumerate(idx % n_rays):
        best = r[j]
        for step in (1, -1):
            k, top = j, r[j]
            for _ in range(n_rays - 1):
                k = (k + step) % n_rays
                if np.isnan(r[k]) or r[k] < top - tolerance:
                    break
                top = max(top, r[k])
            best = max(best, top)
        out[i] = best - r[j]
    return out


# ---- sliding through the closed loop (the lift) ----------------------------------------------


@dataclass(frozen=True)
class LoopOpening:
    """The closed loop's inner opening (m): ``width`` across (between the rods' inner faces),
    ``length`` (from the palm to the bar's inner face) and ``thickness`` (the rods', along the
    loop's normal): material whose cross-section fits ``width`` x ``length`` passes through."""

    width: float
    length: float
    thickness: float


@dataclass
class SlideRegion:
    """What :func:`slide_region` found: ``reachable`` (m,) mask over the material graph's
    thinned points (the caged ones included), how many points were tested for the cross-section
    (``tested``) and how many passed (``thin``)."""

    reachable: np.ndarray
    tested: int = 0
    thin: int = 0


@dataclass
class MaterialGraph:
    """A scan's points thinned to a voxel grid (``points`` (m, 3), ``voxel`` m), with their
    neighbour graph (points within ``link`` m are linked), a k-d tree and a cache of which
    points' cross-sections fit the loop (:func:`fits_loop`): made once per scan, used for every
    grasp planned on it (:func:`material_graph`)."""

    points: np.ndarray
    voxel: float
    link: float
    tree: object
    graph: object
    source_index: np.ndarray
    """(n,) for each of the original points, the index of its thinned point."""
    fits: dict = field(default_factory=dict)


def material_graph(points: np.ndarray, voxel: float) -> MaterialGraph:
    """The points (n, 3, m) thinned to one per ``voxel`` (their mean) and linked to their
    neighbours within 1.8 voxels (a surface sampled on the grid stays connected across a
    diagonal, and two surfaces two voxels apart stay apart)."""
    p = np.asarray(points, dtype=float).reshape(-1, 3)
    keys = np.floor(p / voxel).astype(np.int64)
    _, source_index, counts = np.unique(keys, axis=0, return_inverse=True, return_counts=True)
    source_index = source_index.reshape(-1)
    sums = np.zeros((len(counts), 3))
    np.add.at(sums, source_index, p)
    thin = sums / counts[:, None]
    link = 1.8 * voxel
    tree = spatial.cKDTree(thin)
    pairs = tree.query_pairs(link, output_type="ndarray")
    n = len(thin)
    graph = sparse.coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])),
                              shape=(n, n)).tocsr()
    graph = (graph + graph.T).tocsr()
    return MaterialGraph(thin, voxel, link, tree, graph, source_index)


def fits_loop(mg: MaterialGraph, i: int, opening: LoopOpening) -> bool:
    """Whether the material at thinned point ``i`` could pass through the closed loop: its
    direction t is the principal axis of the points within half the loop's width; the
    cross-section is the slab of points within half the rods' thickness of the plane through
    it normal to t, the part of it connected to the point (within the loop's diagonal); it
    must fit the opening (its extents along its own principal axes within ``length`` and
    ``width``). A wire, a handle's arm or a bar passes; where it joins a body, a wall or a
    sheet, the cross-section is the body's and does not."""
    if i in mg.fits:
        return mg.fits[i]
    p = mg.points[i]
    near = mg.tree.query_ball_point(p, 0.5 * opening.width)
    ok = False
    if len(near) >= 3:
        q = mg.points[near] - p
        t = np.linalg.svd(q - q.mean(axis=0), full_matrices=False)[2][0]
        reach = float(np.hypot(opening.width, opening.length))
        ball = np.asarray(mg.tree.query_ball_point(p, reach), dtype=int)
        d = mg.points[ball] - p
        slab = ball[np.abs(d @ t) <= 0.5 * opening.thickness + 0.5 * mg.voxel]
        sub = mg.graph[slab][:, slab]
        _, labels = csgraph.connected_components(sub, directed=False)
        own = slab[labels == labels[int(np.flatnonzero(slab == i)[0])]]
        section = mg.points[own] - p
        section = section - np.outer(section @ t, t)
        far = np.linalg.norm(section, axis=1).max() if len(section) else 0.0
        if far < reach - mg.link:  # the section ends inside the search ball
            centred = section - section.mean(axis=0)
            axes = np.linalg.svd(centred, full_matrices=False)[2][:2] if len(own) > 1 else \
                np.eye(3)[:2]
            extent = np.ptp(centred @ axes.T, axis=0) if len(own) > 1 else np.zeros(2)
            ok = bool(extent[0] <= opening.length - mg.voxel
                      and extent[1] <= opening.width - mg.voxel)
    mg.fits[i] = ok
    return ok


def slide_region(mg: MaterialGraph, caged: np.ndarray, opening: LoopOpening,
                 max_points: int = 4000) -> SlideRegion:
    """The thinned points the caged material can slide to through the closed loop: from the
    thinned points of the caged ones (``caged``: indices into the original points), along
    the neighbour graph through points whose cross-section fits the loop (:func:`fits_loop`).
    A caged point that does not fit still holds the object where it is. Stops after testing
    ``max_points`` (the region so far)."""
    n = len(mg.points)
    start = np.unique(mg.source_index[np.asarray(caged, dtype=int)])
    reach = np.zeros(n, dtype=bool)
    reach[start] = True
    frontier = [int(i) for i in start if fits_loop(mg, int(i), opening)]
    tested = len(start)
    seen = set(int(i) for i in start)
    indptr, indices = mg.graph.indptr, mg.graph.indices
    while frontier and tested < max_points:
        i = frontier.pop()
        for j in indices[indptr[i]:indptr[i + 1]]:
            j = int(j)
            if j in seen:
                continue
            seen.add(j)
            tested += 1
            if fits_loop(mg, j, opening):
                reach[j] = True
                frontier.append(j)
    thin = int(sum(mg.fits.get(int(i), False) for i in seen))
    return SlideRegion(reach, tested, thin)
