"""The ``Scanner`` system: depth views of the scene around a target, fused into the object mesh."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from pydrake.common.value import AbstractValue
from pydrake.geometry import QueryObject
from pydrake.systems.framework import LeafSystem

from gbh_drake.core.arguments import argument_problem, require
from gbh_drake.core.ranges import is_number, is_sequence
from gbh_drake.perception.config import ScanConfig
from gbh_drake.perception.scan import ScanResult, scan_object
from gbh_drake.perception.self_filter import robot_labels


class Scanner(LeafSystem):
    """Scans the scene with simulated depth views and outputs the fused mesh in W.

    .. pydrake_system::

        name: Scanner
        input_ports:
        - query_object
        - object.state (optional; only with scan_time)
        - scan_request (optional; only with scan_time)
        output_ports:
        - mesh_W

    ``query_object`` (``QueryObject``): the query output port of a scene graph that holds a
    render engine named ``config.renderer_name`` (in a diagram of one's own, add it:
    ``scene_graph.AddRenderer("default", MakeRenderEngineVtk(RenderEngineVtkParams()))``);
    in a Station, ``camera_query_object`` for the station's own renderer ``default``
    (:func:`gbh_drake.station.scene_query_port` names the port for a renderer).
    ``mesh_W`` (:class:`~gbh_drake.perception.scan.ScanResult`): the object's mesh in W,
    segmented from the table and the robot (a first look finds it near ``p_WT``, then the views
    are aimed at it), its points, the camera poses X_WC, warnings (e.g. the object reaches the
    edge of what the cameras see) and timing; ``empty`` and ``message`` when nothing was seen.

    Two ways to use it. Without ``scan_time`` the output is a function of the input, cached
    until the scene's poses change (evaluate it when you need a scan). With ``scan_time`` (s) the
    Scanner takes one scan, keeps it in its state and outputs it from then on (scan first, then
    act); until then the output is the "not scanned yet" placeholder (:func:`scan_pending`).
    When is the scan taken? With ``object.state`` unconnected, at ``scan_time``. Connected (the
    station's ``object.state``: [quaternion (4), p (3), w (3), v (3)] in W), the Scanner watches
    the object every ``config.still_period`` and scans once it is at rest
    (:func:`still_decision`): slower than ``still_speed`` and ``still_angular_speed_deg`` for
    ``still_dwell`` s, not before ``scan_time``, and at ``scan_time + still_max_wait`` at the
    latest (then with a warning in the scan's warnings). ``ScanResult.taken_at`` says when.

    Scanning again: ``scan_request`` (4: [n, x, y, z]), when connected, asks for the n-th scan
    since the first, around the target (x, y, z) m in W (a pick-and-place set the object down
    there anew). Once n exceeds the requests answered so far, the Scanner scans again by the
    same stillness rule, counted from the moment it saw the request, and holds the new scan
    (``ScanResult.request`` = n; everything fed by ``mesh_W`` then computes anew).
    """

    def __init__(self, config: ScanConfig, p_WT, *, scan_time: float | None = None,
                 noise_seed: int = 0, robot: Sequence[int] = ()):
        """``p_WT`` (3,) m: where the object is expected in W (the first look searches around it,
        then the views aim at what it found);
        ``noise_seed``: seed of the depth noise (when ``config.noise``); ``robot``: the model
        instances (indices) of the robot, whose pixels are filtered out of the depth images by
        their render labels before anything is fused (a self filter,
        :mod:`gbh_drake.perception.self_filter`; empty: none)."""
        super().__init__()
        self._config = config
        self._p_WT = check_scan_arguments("Scanner", config, p_WT, noise_seed)
        if scan_time is not None and not is_time(scan_time):
            raise TypeError(argument_problem("Scanner", "scan_time", "a time >= 0 (s) or None",
                                             scan_time))
        self._noise_seed = int(noise_seed)
        self._robot = tuple(int(i) for i in robot)
        self._query = self.DeclareAbstractInputPort("query_object",
                                                    AbstractValue.Make(QueryObject()))
        model = AbstractValue.Make(no_scan(NOT_SCANNED_YET))
        self._scan_time = None if scan_time is None else float(scan_time)
        if scan_time is None:
            self.DeclareAbstractOutputPort("mesh_W", model.Clone, self._calc_scan,
                                           prerequisites_of_calc={self._query.ticket()})
        else:
            self._object_state = self.DeclareVectorInputPort("object.state", 13)
            self._request = self.DeclareVectorInputPort("scan_request", 4)
            self._held = self.DeclareAbstractState(model)
            # When the object became still (s; nan: moving or not watched yet); the requests
            # answered; when the unanswered one was first seen (s; nan: none).
            self._still_since = self.DeclareDiscreteState([np.nan, 0.0, np.nan])
            # Unconnected object.state: one scan at scan_time, as before the watch existed.
            self.DeclarePeriodicUnrestrictedUpdateEvent(1e9, self._scan_time, self._take_scan)
            self.DeclarePeriodicUnrestrictedUpdateEvent(config.still_period, 0.0, self._watch)
            self.DeclareStateOutputPort("mesh_W", self._held)

    @property
    def config(self) -> ScanConfig:
        return self._config

    @property
    def p_WT(self) -> np.ndarray:
        return self._p_WT.copy()

    def scan(self, context, p_WT=None) -> ScanResult:
        """A scan of the scene as ``context`` has it now, around ``p_WT`` (default: the
        constructor's)."""
        query = self._query.Eval(context)
        return scan_object(query, self._config,
                           self._p_WT if p_WT is None else np.asarray(p_WT, dtype=float),
                           noise_seed=self._noise_seed,
                           robot_labels=robot_labels(query, self._robot) if self._robot
                           else frozenset())

    def _calc_scan(self, context, output) -> None:
        result = self.scan(context)
        result.taken_at = context.get_time()
        output.set_value(result)

    def _taken(self, context) -> bool:
        return not scan_pending(context.get_abstract_state(self._held).get_value())

    def _latch(self, context, state, warnings: list[str], p_WT=None, request: int = 0) -> None:
        result = self.scan(context, p_WT)
        result.taken_at = context.get_time()
        result.request = request
        result.warnings = warnings + result.warnings
        state.get_mutable_abstract_state(self._held).set_value(result)

    def _take_scan(self, context, state) -> None:
        if not self._object_state.HasValue(context) and not self._taken(context):
            self._latch(context, state, [])

    def _watch(self, context, state) -> None:
        if not self._object_state.HasValue(context):
            return
        t = context.get_time()
        still_since, answered, seen_at = context.get_discrete_state(self._still_since).value()
        scan_time, request, p_WT = self._scan_time, 0, None
        if self._taken(context):
            if not self._request.HasValue(context):
                return
            wanted = self._request.Eval(context)
            if wanted[0] <= answered:
                return
            seen_at = t if np.isnan(seen_at) else seen_at
            scan_time, request, p_WT = seen_at, int(wanted[0]), wanted[1:4]
        x = self._object_state.Eval(context)
        scan, still_since, warning = still_decision(
            t, x[10:13], x[7:10], still_since, scan_time=scan_time, config=self._config)
        if scan:
            self._latch(context, state, [warning] if warning else [], p_WT, request)
            answered, seen_at = float(request), np.nan
        state.get_mutable_discrete_state(self._still_since).set_value(
            [still_since, answered, seen_at])


def check_scan_arguments(system: str, config, p_WT, noise_seed) -> np.ndarray:
    """The arguments both scanners take, each named in a ``TypeError`` (a diagram of one's own
    builds them by hand, without a scenario's checks); ``config`` validated. Returns ``p_WT``
    (3,) m."""
    require(system, "config", config, ScanConfig, "a ScanConfig (a scenario's scan)")
    config.validate()
    if not (is_sequence(p_WT) and len(p_WT) == 3 and all(is_number(v) and np.isfinite(v)
                                                          for v in p_WT)):
        raise TypeError(argument_problem(system, "p_WT", "3 finite coordinates (x, y, z in m; "
                                         "a scenario's scan_target)", p_WT))
    if isinstance(noise_seed, bool):
        raise TypeError(argument_problem(system, "noise_seed", "an integer", noise_seed))
    require(system, "noise_seed", noise_seed, (int, np.integer), "an integer")
    return np.asarray(p_WT, dtype=float).reshape(3)


def is_time(value) -> bool:
    """Whether ``value`` is a finite time >= 0 (s)."""
    return is_number(value) and 0 <= value < np.inf


#: The message of the Scanner's placeholder output until its scan is taken.
NOT_SCANNED_YET = "not scanned yet"


def scan_pending(scan) -> bool:
    """Whether ``scan`` is the Scanner's placeholder: its scan is not taken yet (a PickAndCarry
    waits for it). Any other scan, empty or not, is taken."""
    return (isinstance(scan, ScanResult) and scan.empty and scan.message == NOT_SCANNED_YET
            and np.isnan(scan.taken_at))


def still_decision(t: float, v_W, w_W, still_since: float, *, scan_time: float,
                   config: ScanConfig) -> tuple[bool, float, str]:
    """The stillness rule, at time ``t`` (s), for an object moving at v_W (3,) m/s and w_W (3,)
    rad/s; ``still_since`` (s): when it became still (nan: it was moving). Returns (scan now,
    the new ``still_since``, a warning for the scan or "").

    The object is still when ``|v| < still_speed`` and ``|w| < still_angular_speed_deg``; the
    scan is taken once it has been still for ``still_dwell`` s (stillness before ``scan_time``
    counts) and ``t >= scan_time``; at ``scan_time + still_max_wait`` it is taken anyway, with a
    warning."""
    eps = 1e-9  # periodic event times are sums of floats
    speed, spin = float(np.linalg.norm(v_W)), float(np.linalg.norm(w_W))
    still = speed < config.still_speed and spin < np.deg2rad(config.still_angular_speed_deg)
    if not still:
        still_since = np.nan
    elif np.isnan(still_since):
        still_since = t
    if t < scan_time - eps:
        return False, still_since, ""
    if still and t - still_since >= config.still_dwell - eps:
        return True, still_since, ""
    if t >= scan_time + config.still_max_wait - eps:
        return True, still_since, (
            f"the object was still moving when scanned at t = {t:.2f} s ({speed * 1e3:.1f} mm/s, "
            f"{np.rad2deg(spin):.1f} deg/s; still means under {config.still_speed * 1e3:g} mm/s "
            f"and {config.still_angular_speed_deg:g} deg/s for {config.still_dwell:g} s): the "
            "scan may not be where the object comes to rest")
    return False, still_since, ""


def no_scan(message: str) -> ScanResult:
    """An empty scan result that says why there is no scan."""
    return ScanResult.empty_result(message)
