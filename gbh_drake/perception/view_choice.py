"""One view, chosen: from the first look, the single full view that sees the candidate holes best.

The first look (``scan.first_look``: two small side views, taken anyway to find and frame the
object) is a coarse silhouette of the object. With ``ScanConfig.view_choice`` ``holes`` or
``material`` and one view, :func:`choose_view` fuses the first look's object pixels into a coarse mesh
(:func:`first_look_model`), finds GbH's candidate hanging structures on it (its hangability
stage at ``GbhParams``' defaults, unseen space not held against them: candidates, not proofs),
and scores the candidate views (:func:`candidate_directions`: the fixed view, then the spiral
layout of ``view_candidates`` views, all aimed and backed off as the fixed view is) with
:func:`gbh_drake.core.view_choice.hole_view_scores`. The best scoring view is taken; the fixed
view keeps the choice when no candidate scores higher (no candidate hole, or none seen better).

GbH then fuses that one full view, as it fuses the fixed one; the first look's two small
images are never fused (their free space goes with the scan, as for every method).
"""

from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass, field

import numpy as np

from gbh_drake.core.lazy import lazy_module
from gbh_drake.core.params import GbhParams
from gbh_drake.perception.config import ScanConfig

spatial = lazy_module("scipy.spatial")
trimesh = lazy_module("trimesh")

#: m: the first look's coarse model is fused at this voxel (its pixels are about 5 mm at 0.8 m).
MODEL_VOXEL = 0.004
#: A candidate must score this much more than the fixed view to be taken instead.
MIN_GAIN = 1e-6


@dataclass
class ViewChoice:
    """The view chosen and why: ``index`` into the candidates (0: the fixed view), their unit
    directions from the object toward the camera (W), their scores, the candidate structures
    found on the first look's model (their centres, W) and the wall seconds it took."""

    index: int
    directions: np.ndarray
    scores: np.ndarray
    hole_centres: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    seconds: float = 0.0
    message: str = ""

    @property
    def direction(self) -> np.ndarray:
        return self.directions[self.index]


def candidate_directions(config: ScanConfig, n: int | None = None) -> np.ndarray:
    """(1 + n, 3) unit vectors from the object toward each candidate camera, in W: the fixed
    one-view direction (``azimuth_deg``, ``elevation_deg``), then a spiral of ``n`` (default
    ``config.view_candidates``) over the band ``elevation_deg``-``elevation_max_deg``, the
    layout of ``n`` spiral views (the ten-view scan's, for 10)."""
    from gbh_drake.perception.viewpoints import view_directions

    n = config.view_candidates if n is None else int(n)
    fixed = view_directions(dataclasses.replace(config, num_views=1))
    spiral = view_directions(dataclasses.replace(config, num_views=n, layout="spiral"))
    return np.concatenate([fixed, spiral])


def view_config(config: ScanConfig, direction) -> ScanConfig:
    """``config`` for one view from ``direction`` (3,) (from the object toward the camera)."""
    u = np.asarray(direction, dtype=float)
    elevation = float(np.degrees(np.arcsin(np.clip(u[2], -1.0, 1.0))))
    azimuth = float(np.degrees(np.arctan2(u[1], u[0])))
    return dataclasses.replace(config, num_views=1, azimuth_deg=azimuth,
                               elevation_deg=elevation,
                               elevation_max_deg=max(elevation, config.elevation_max_deg))


def candidate_configs(config: ScanConfig, n: int | None = None) -> list[ScanConfig]:
    """One one-view config per candidate direction (:func:`candidate_directions`)."""
    return [view_config(config, u) for u in candidate_directions(config, n)]


def first_look_model(look, config: ScanConfig) -> trimesh.Trimesh:
    """The object as the first look saw it: its depth images' pixels that lie within two
    cluster cells of the object's points (``look.p_W_object``), fused by TSDF at
    :data:`MODEL_VOXEL`, cut at the scan's ``crop_z_min`` above the table. Empty when the look
    found nothing."""
    from pydrake.math import RigidTransform

    from gbh_drake.perception.camera import CameraIntrinsics
    from gbh_drake.perception.cap import cut_at_height
    from gbh_drake.perception.fusion import integrate

    if look is None or look.free_space is None or len(look.p_W_object) == 0:
        return trimesh.Trimesh()
    tree = spatial.cKDTree(np.asarray(look.p_W_object, dtype=float))
    depths, X_WCs = [], []
    view0 = look.free_space.views[0]
    for view in look.free_space.views:
        d = np.asarray(view.depth, dtype=np.float32)
        X_WC = np.linalg.inv(view.X_CW)
        v, u = np.nonzero(np.isfinite(d) & (d < config.depth_max))
        z = d[v, u].astype(float)
        p_C = np.stack([(u + 0.5 - view.cx) / view.fx * z, (v + 0.5 - view.cy) / view.fy * z, z],
                       axis=1)
        p_W = p_C @ X_WC[:3, :3].T + X_WC[:3, 3]
        near, _ = tree.query(p_W, distance_upper_bound=2.0 * config.cluster_cell)
        keep = np.isfinite(near)
        masked = np.zeros(d.shape, dtype=np.float32)
        masked[v[keep], u[keep]] = d[v[keep], u[keep]]
        depths.append(masked)
        X_WCs.append(RigidTransform(X_WC))
    intrinsics = CameraIntrinsics(view0.width, view0.height, view0.fx, view0.fy, view0.cx,
                                  view0.cy)
    coarse = dataclasses.replace(config, width=view0.width, height=view0.height,
                                 voxel_size=MODEL_VOXEL, sdf_trunc=3.0 * MODEL_VOXEL)
    mesh = integrate(depths, intrinsics, X_WCs, coarse)
    return cut_at_height(mesh, look.table, config.crop_z_min) if len(mesh.faces) else mesh


def first_look_candidates(look, config: ScanConfig, params: GbhParams | None = None):
    """(model, structures): the first look's model (:func:`first_look_model`) completed by
    symmetry (on the look's object points and free space, at :data:`MODEL_VOXEL`; the two side
    views see a cup's front and back walls obliquely or not at all, and its inside would pass
    for a hole through them) as a prepared :class:`~gbh_drake.core.object_model.ObjectModel`,
    and the hanging structures on it that the look proves: GbH's stages at ``params`` (default
    ``GbhParams()``) with the exit proof in the look's free space and what its completion calls
    free (:class:`~gbh_drake.core.completion.CompletedFreeSpace`). The two side views, from
    60 deg of elevation, prove most true handles (a line through them seen free) and refute a
    cup's inside (its floor is no table). None, [] when the look gave no usable model."""
    from gbh_drake.core.completion import CompletedFreeSpace, complete_by_symmetry
    from gbh_drake.core.hangability import detect_hangable_structures
    from gbh_drake.core.object_model import prepare_object
    from gbh_drake.core.params import CompletionParams
    from gbh_drake.core.results import GbhInputError
    from gbh_drake.perception.segment import ROI_MARGIN, ROI_SCALE  # the scan's region

    mesh = first_look_model(look, config)
    if len(mesh.faces) == 0:
        return None, []
    up = np.asarray(look.table.normal_W, dtype=float)
    free = look.free_space
    floor = float((np.asarray(mesh.vertices) @ up).min()) + max(
        free.view_margin(v) for v in free.views)
    half = ROI_SCALE * look.radius + ROI_MARGIN
    completion = complete_by_symmetry(
        mesh.vertices, mesh.vertex_normals, look.p_W_object, free,
        look.centre_W - half, look.centre_W + half,
        dataclasses.replace(CompletionParams(), cell=MODEL_VOXEL), up_W=up, floor=floor)
    if completion is not None and len(completion.mesh.faces):
        mesh = trimesh.util.concatenate([mesh, completion.mesh])
    params = dataclasses.replace(params or GbhParams(), unknown_is_occupied=True,
                                 through_proof_exit=True)
    proof = CompletedFreeSpace.of(free, completion)
    try:
        model = prepare_object(mesh, params, seed=0, free_space=proof)
        return model, detect_hangable_structures(model, params)
    except GbhInputError:
        return None, []


def choose_view(look, config: ScanConfig, aim_W, distance: float,
                params: GbhParams | None = None) -> ViewChoice:
    """The candidate view (:func:`candidate_directions`, at ``distance`` (m) from ``aim_W``
    (3,), as the views are aimed) that sees the first look's candidate holes
    (:func:`first_look_candidates`) best (module docstring; ``config.view_choice`` ``holes``:
    through them, ``material``: the material round them); ``params``: GbH's (default
    ``GbhParams()``)."""
    from gbh_drake.core.view_choice import hole_view_scores, material_view_scores

    params = params or GbhParams()
    start = time.perf_counter()
    directions = candidate_directions(config)
    scores = np.zeros(len(directions))
    model, structures = first_look_candidates(look, config, params)
    if model is None:
        return ViewChoice(0, directions, scores, seconds=time.perf_counter() - start,
                          message="the first look gave no model: the fixed view")
    cams = np.asarray(aim_W, dtype=float) + distance * directions
    if config.view_choice == "material":
        scores = material_view_scores(model, structures, cams, params.through_proof_length)
    else:
        scores = hole_view_scores(model, structures, cams, params.through_proof_angle_deg)
    best = int(np.argmax(scores))
    index = best if scores[best] > scores[0] + MIN_GAIN else 0
    centres = np.array([s.c for s in structures]).reshape(-1, 3)
    message = (f"{len(structures)} candidate hole(s) on the first look; view {index} of "
               f"{len(directions)} (score {scores[index]:.3f}, the fixed view {scores[0]:.3f})")
    return ViewChoice(index, directions, scores, centres, time.perf_counter() - start, message)


def chosen_config(look, config: ScanConfig) -> tuple[ScanConfig, ViewChoice | None]:
    """The config of the view to take after the first look ``look``: with ``view_choice``
    ``holes`` or ``material`` and one view, the chosen view's (:func:`choose_view`, aimed at the look's sphere
    from the distance that fits it, as ``scan_object`` aims), and the choice; otherwise
    ``config`` itself and None."""
    if config.view_choice == "fixed" or config.num_views != 1 or look is None or \
            not look.found:
        return config, None
    from gbh_drake.perception.viewpoints import fit_view_distance

    distance, _ = fit_view_distance(look.radius, config)
    choice = choose_view(look, config, look.centre_W, distance)
    return view_config(config, choice.direction), choice
