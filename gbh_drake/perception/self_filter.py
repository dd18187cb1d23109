"""The robot's own pixels, found by render label and left out of the object's scan (issue 42).

A robot filters its own body out of its depth images with its model: it renders the model at
the measured joint positions and ignores the pixels where the model is what the camera sees
(MoveIt's ``depth_image_octomap_updater`` self filter, ``robot_self_filter``). The simulated
cameras render label images of the same scene, and Drake's ``MultibodyPlant`` labels each
body's perception geometry with the body's index, so the robot's pixels are those whose label
belongs to one of the robot's bodies: the arm's and the gripper's. Without the filter, the hook
gripper hanging above a tall object at the robot's home pose was fused into the object's scan
(``tools/scan_vs_truth.py``: the tote bag, held-out natural trial 0).

The filtered pixels are no measurement for the object (its points, its segmentation and the
TSDF); they stay measurements for free space: the ray to the robot's surface crossed free
space, and what lies behind the robot is unknown, as for any other surface. The scan applies
the masks (:func:`gbh_drake.perception.scan.scan_depth_images`' ``robot_masks``); a real robot's
masks come from its own model rendered at its measured joints, the same way.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

import numpy as np
from pydrake.geometry import ColorRenderCamera, DepthRenderCamera, QueryObject, RenderLabel, Role
from pydrake.math import RigidTransform


def robot_labels(query_object: QueryObject, model_instances: Iterable[int]) -> frozenset[int]:
    """The render labels of the perception geometry whose frame belongs to one of
    ``model_instances`` (``MultibodyPlant`` model instance indices: a plant's frames are grouped
    by model instance, and a scene copied from it keeps the groups, as the station's camera
    scene does)."""
    instances = {int(i) for i in model_instances}
    inspector = query_object.inspector()
    labels = set()
    for g in inspector.GetAllGeometryIds(Role.kPerception):
        if inspector.GetFrameGroup(inspector.GetFrameId(g)) in instances:
            label = inspector.GetPerceptionProperties(g).GetPropertyOrDefault(
                "label", "id", RenderLabel.kDontCare)
            labels.add(int(label))
    return frozenset(labels)


def robot_masks(query_object: QueryObject, camera: DepthRenderCamera,
                X_WCs: Sequence[RigidTransform], labels: frozenset[int]) -> list[np.ndarray]:
    """One (height, width) bool image per camera pose X_WC: the pixels whose render label is
    one of ``labels`` (the robot's), rendered with ``camera``'s core (same image, renderer and
    pose as its depth images). Empty ``labels``: no image is rendered, every mask is empty."""
    if not labels:
        width, height = camera.core().intrinsics().width(), camera.core().intrinsics().height()
        return [np.zeros((height, width), dtype=bool) for _ in X_WCs]
    color = ColorRenderCamera(camera.core(), False)
    world = query_object.inspector().world_frame_id()
    wanted = np.array(sorted(labels))
    return [np.isin(np.asarray(query_object.RenderLabelImage(color, world, X_WC).data)[:, :, 0],
                    wanted) for X_WC in X_WCs]


def without_pixels(depths: Sequence[np.ndarray], masks: Sequence[np.ndarray] | None
                   ) -> list[np.ndarray]:
    """Copies of ``depths`` whose ``masks`` pixels hold 0 (no measurement); ``depths`` as they
    are without masks."""
    if masks is None:
        return list(depths)
    return [np.where(mask, np.float32(0.0), depth).astype(np.float32)
            for depth, mask in zip(depths, masks, strict=True)]
