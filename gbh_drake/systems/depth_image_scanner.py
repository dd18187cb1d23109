"""The ``DepthImageScanner`` system: depth images from cameras (real or simulated) and their poses
in, the object's scan out, as the simulated ``Scanner`` makes it.

Its output is the same :class:`~gbh_drake.perception.scan.ScanResult` by the same function
(:func:`~gbh_drake.perception.scan.scan_depth_images`: table fit, segmentation, TSDF fusion, cut
and cap, free space), so the GbH systems (``HangabilityDetector`` and on) and ``PickAndCarry``
run on camera streams unchanged. The views are where the cameras are: nothing is aimed (a
Scanner with ``aim_views`` off looks from fixed poses the same way).
"""

from __future__ import annotations

import numpy as np
from pydrake.common.value import AbstractValue
from pydrake.math import RigidTransform
from pydrake.systems.framework import LeafSystem
from pydrake.systems.sensors import CameraInfo, ImageDepth32F

from gbh_drake.core.arguments import argument_problem, require
from gbh_drake.core.ranges import is_sequence
from gbh_drake.perception.camera import CameraIntrinsics
from gbh_drake.perception.config import ScanConfig
from gbh_drake.perception.scan import ScanResult, scan_depth_images
from gbh_drake.systems.scanner import NOT_SCANNED_YET, check_scan_arguments, is_time, no_scan


class DepthImageScanner(LeafSystem):
    """Fuses the depth images of ``num_cameras`` cameras into the object's mesh in W.

    .. pydrake_system::

        name: DepthImageScanner
        input_ports:
        - depth_image_0
        - X_WC_0
        - ...
        - depth_image_{n-1}
        - X_WC_{n-1}
        output_ports:
        - mesh_W

    ``depth_image_i`` (``ImageDepth32F``, metres; 0 or inf: no measurement): camera i's depth
    image, as Drake's ``RgbdSensor.depth_image_32f_output_port()`` and the LCM receiver
    ``LcmImageArrayToImages``'s ``depth_image`` deliver it. ``X_WC_i`` (``RigidTransform``):
    camera i's pose in W (C: +z along the optical axis, +x right, +y down), as an
    ``RgbdSensor``'s ``body_pose_in_world`` gives it when its camera sits at the sensor's body
    (the default), or your robot's kinematics and calibration do. ``mesh_W``
    (:class:`~gbh_drake.perception.scan.ScanResult`): as the ``Scanner``'s.

    Without ``capture_times`` the output is a function of the inputs, cached until they
    change: each camera gives one view. With ``capture_times`` (s) every camera's image and
    pose are taken at each of those times (a camera on the wrist, moved between them, gives a
    view each time) and fused after the last; until then the output is the Scanner's "not
    scanned yet" placeholder (a ``PickAndCarry`` waits for the scan).
    """

    def __init__(self, config: ScanConfig, intrinsics: CameraIntrinsics | CameraInfo, p_WT, *,
                 num_cameras: int = 1, capture_times=None, sensor_error: float | None = None,
                 far_is_free: bool = True, noise_seed: int = 0):
        """``intrinsics``: the cameras' pinhole (all alike; Drake's ``CameraInfo`` or a
        :class:`~gbh_drake.perception.camera.CameraIntrinsics`); ``p_WT`` (3,) m: where the
        object is expected in W; ``sensor_error`` (m): how far a depth may lie from the surface
        it hit (the free space's margin adds it; default: ``config``'s noise model, 0 without
        noise); ``far_is_free``: an inf pixel means nothing was hit within
        ``config.depth_max`` (Drake's renderer; False for a sensor whose "no return" may hide
        a surface); ``noise_seed``: the depth noise's (``config.noise``: simulated images)."""
        super().__init__()
        name = "DepthImageScanner"
        self._config = config
        self._p_WT = check_scan_arguments(name, config, p_WT, noise_seed)
        require(name, "intrinsics", intrinsics, (CameraIntrinsics, CameraInfo),
                "a pydrake CameraInfo or a CameraIntrinsics")
        if not (isinstance(num_cameras, int | np.integer) and not isinstance(num_cameras, bool)
                and num_cameras >= 1):
            raise TypeError(argument_problem(name, "num_cameras", "an integer >= 1",
                                             num_cameras))
        if sensor_error is not None and not is_time(sensor_error):  # (finite, >= 0)
            raise TypeError(argument_problem(name, "sensor_error", "a distance >= 0 (m) or None",
                                             sensor_error))
        if capture_times is not None and not (is_sequence(capture_times) and len(capture_times)
                                              and all(is_time(t) for t in capture_times)):
            raise TypeError(argument_problem(name, "capture_times", "a non-empty list of times "
                                             ">= 0 (s), or None (scan on demand)", capture_times))
        self._intrinsics = _intrinsics(intrinsics)
        self._sensor_error = sensor_error
        self._far_is_free = bool(far_is_free)
        self._noise_seed = int(noise_seed)
        self._images, self._poses = [], []
        for i in range(num_cameras):
            self._images.append(self.DeclareAbstractInputPort(
                f"depth_image_{i}", AbstractValue.Make(ImageDepth32F())))
            self._poses.append(self.DeclareAbstractInputPort(
                f"X_WC_{i}", AbstractValue.Make(RigidTransform())))
        model = AbstractValue.Make(no_scan(NOT_SCANNED_YET))
        if capture_times is None:
            tickets = {p.ticket() for p in self._images + self._poses}
            self.DeclareAbstractOutputPort("mesh_W", model.Clone, self._calc_scan,
                                           prerequisites_of_calc=tickets)
            return
        times = sorted(float(t) for t in capture_times)
        self._taken = self.DeclareAbstractState(AbstractValue.Make(_Captures()))
        self._held = self.DeclareAbstractState(model)
        for k, t in enumerate(times):
            last = k == len(times) - 1
            self.DeclarePeriodicUnrestrictedUpdateEvent(
                1e9, t, lambda context, state, last=last: self._capture(context, state, last))
        self.DeclareStateOutputPort("mesh_W", self._held)

    @property
    def intrinsics(self) -> CameraIntrinsics:
        return self._intrinsics

    def scan(self, depths: list[np.ndarray], X_WCs: list[RigidTransform]) -> ScanResult:
        """The scan of ``depths`` (h, w) float32 from cameras at ``X_WCs``."""
        return scan_depth_images(depths, self._intrinsics, X_WCs, self._config, self._p_WT,
                                 noise_seed=self._noise_seed, far_is_free=self._far_is_free,
                                 sensor_error=self._sensor_error)

    def _read(self, context) -> tuple[list[np.ndarray], list[RigidTransform]]:
        """Every camera's image (checked against the intrinsics) and pose, now."""
        depths, poses = [], []
        k = self._intrinsics
        for image_port, pose_port in zip(self._images, self._poses, strict=True):
            image = image_port.Eval(context)
            if (image.width(), image.height()) != (k.width, k.height):
                raise ValueError(f"{self.get_name() or 'DepthImageScanner'}: "
                                 f"{image_port.get_name()} is {image.width()}x{image.height()} "
                                 f"pixels; the intrinsics say {k.width}x{k.height}")
            depths.append(np.array(image.data[:, :, 0], dtype=np.float32))
            poses.append(RigidTransform(pose_port.Eval(context)))
        return depths, poses

    def _calc_scan(self, context, output) -> None:
        result = self.scan(*self._read(context))
        result.taken_at = context.get_time()
        output.set_value(result)

    def _capture(self, context, state, last: bool) -> None:
        captures: _Captures = context.get_abstract_state(self._taken).get_value()
        depths, poses = self._read(context)
        captures = _Captures(captures.depths + depths, captures.X_WCs + poses)
        state.get_mutable_abstract_state(self._taken).set_value(captures)
        if last:
            result = self.scan(captures.depths, captures.X_WCs)
            result.taken_at = context.get_time()
            state.get_mutable_abstract_state(self._held).set_value(result)


class _Captures:
    """The images and poses taken so far (shared, not copied: never modified in place)."""

    def __init__(self, depths=(), X_WCs=()):
        self.depths, self.X_WCs = list(depths), list(X_WCs)

    def __deepcopy__(self, memo):
        return _Captures(self.depths, self.X_WCs)


def _intrinsics(k: CameraIntrinsics | CameraInfo) -> CameraIntrinsics:
    if isinstance(k, CameraIntrinsics):
        return k
    return CameraIntrinsics(k.width(), k.height(), k.focal_x(), k.focal_y(), k.center_x(),
                            k.center_y())
