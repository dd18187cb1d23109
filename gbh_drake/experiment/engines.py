"""Where the trials run: local worker processes, or Ray tasks. Both yield results as trials finish.

* :func:`local_results`: ``workers`` local processes, each a one-process ``ProcessPoolExecutor``
  (``spawn``: fresh interpreters, nothing inherited from this process's state). Each process runs
  one trial at a time and keeps its imported modules and its Meshcat across trials, until it has
  run ``trials_per_worker`` trials: then a fresh process takes its place (pydrake never frees a
  trial's Python systems, so a worker grows with every trial it runs).
* :func:`ray_results`: the same function as Ray tasks (one CPU each) on a cluster: ``auto`` (the
  cluster this machine belongs to), ``ray://host:port`` or ``host:port`` (a cluster's address),
  or ``local`` (a one-machine Ray started here, listening on the loopback only, dashboard and
  usage reporting off). Nothing but the environment variables :data:`WORKER_ENV` is shipped to
  a cluster (no ``runtime_env`` working directory or packages): each node's Ray workers import
  ``gbh_drake`` from the Python that ran ``ray start`` there, so every node needs this package
  installed, at the same version (docs/ray.md). Ray is optional (``pip install
  'gbh_drake[ray]'``): only this engine imports it. An experiment file chooses it with ``engine:
  ray`` and ``ray_address``; ``gbh experiment --ray ADDRESS`` overrides the file.

Workers run single-threaded (see :mod:`gbh_drake.experiment.worker`), so rows are identical,
timing fields aside, whatever the number of workers or the engine.
"""

from __future__ import annotations

import collections
import contextlib
import importlib.util
import multiprocessing
import os
import socket
import threading
import time
from collections.abc import Iterator, Sequence
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait

from gbh_drake.experiment.task import TrialResult, TrialTask
from gbh_drake.experiment.worker import run_trial_task, run_worker_task, set_single_threaded

#: Environment of the worker processes (inherited when they start).
WORKER_ENV = {"OMP_NUM_THREADS": "1"}

#: A loopback port where nothing listens: the HTTP proxy of a local Ray's processes.
_DEAD_PROXY = "http://127.0.0.1:9"

#: Environment of a Ray started here (its processes inherit it):
#:
#: * no usage reporting;
#: * ``ray.init`` takes the loopback address as the node's, so Ray's servers listen on the
#:   loopback only (it otherwise takes the machine's outward address);
#: * HTTP to anything but the loopback goes to a dead proxy: Ray's dashboard process asks the
#:   cloud metadata addresses (169.254.169.254, metadata.google.internal) which cloud it runs on
#:   even with the dashboard and usage reporting off (ray 2.60, ``get_cluster_config_to_report``);
#:   through the proxy those requests fail at once, on this machine, and resolve no name.
#:   (Ray's gRPC ignores these variables.)
LOCAL_RAY_ENV = {
    "RAY_USAGE_STATS_ENABLED": "0",
    "RAY_ENABLE_WINDOWS_OR_OSX_CLUSTER": "0",
    **{name: _DEAD_PROXY for name in ("http_proxy", "https_proxy", "HTTP_PROXY",
                                      "HTTPS_PROXY")},
    **{name: "localhost,127.0.0.1,::1" for name in ("no_proxy", "NO_PROXY")},
}


def ray_missing(instead: str = "leave out --ray") -> str:
    """Why the Ray engine cannot run here, and ``instead`` (what runs local worker processes)."""
    return ("needs Ray, which is not installed in this environment: pip install "
            f"'gbh_drake[ray]' (or {instead} to run local worker processes)")


#: Why the Ray engine cannot run here (``gbh experiment --ray`` without Ray installed).
RAY_MISSING = f"--ray {ray_missing()}"


class RayMissing(RuntimeError):
    """The Ray engine was asked for, but ``ray`` cannot be imported (message: :data:`RAY_MISSING`)."""

    def __init__(self):
        super().__init__(RAY_MISSING)


class RayError(RuntimeError):
    """Ray could not be started or reached (the message names the address and says why)."""


def ray_installed() -> bool:
    """Whether ``ray`` can be found, without importing it (a local Ray's environment must be set
    before the import: :func:`init_ray` does that)."""
    try:
        return importlib.util.find_spec("ray") is not None
    except (ImportError, ValueError):
        return False


@contextlib.contextmanager
def environment(values: dict[str, str]):
    """Sets environment variables for the duration (processes started meanwhile inherit them)."""
    saved = {k: os.environ.get(k) for k in values}
    os.environ.update(values)
    try:
        yield
    finally:
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v


def local_results(tasks: Sequence[TrialTask], workers: int, *,
                  trials_per_worker: int | None = None) -> Iterator[TrialResult]:
    """Runs ``tasks`` on ``workers`` local processes, each replaced by a fresh one after
    ``trials_per_worker`` trials (None: never); yields each result as it finishes.

    Each worker is a one-process ``ProcessPoolExecutor`` (a dead worker still raises
    ``BrokenProcessPool``); a worker due for replacement is shut down and a new executor takes
    its place. (``ProcessPoolExecutor(max_tasks_per_child=...)`` is not used: on Python 3.11 it
    stops replacing exited workers once one counts as idle, and the experiment hangs.)"""
    if not tasks:
        return
    context = multiprocessing.get_context("spawn")
    queue = collections.deque(tasks)

    def fresh() -> ProcessPoolExecutor:
        return ProcessPoolExecutor(max_workers=1, mp_context=context,
                                   initializer=set_single_threaded)

    with environment(WORKER_ENV):
        slots = [fresh() for _ in range(min(max(1, workers), len(tasks)))]
        ran = [0] * len(slots)
        running = {}
        finished = False
        try:
            for i, slot in enumerate(slots):
                running[slot.submit(run_trial_task, queue.popleft())] = i
            while running:
                done, _ = wait(running, return_when=FIRST_COMPLETED)
                for future in done:
                    i = running.pop(future)
                    result = future.result()
                    ran[i] += 1
                    if queue:
                        if trials_per_worker and ran[i] >= trials_per_worker:
                            slots[i].shutdown(wait=True)
                            slots[i], ran[i] = fresh(), 0
                        running[slots[i].submit(run_trial_task, queue.popleft())] = i
                    yield result
            finished = True
        finally:
            for slot in slots:
                if not finished:  # Ctrl-C, SIGTERM, an error, or the caller stopped early
                    _stop_workers(slot)
                slot.shutdown(wait=True, cancel_futures=True)


def _stop_workers(pool: ProcessPoolExecutor) -> None:
    """Ends the workers' running trials now (their rows were not written: they are redone when
    the experiment resumes). ``ProcessPoolExecutor.terminate_workers`` from Python 3.14."""
    terminate = getattr(pool, "terminate_workers", None)
    if terminate is not None:
        terminate()
        return
    for process in list((getattr(pool, "_processes", None) or {}).values()):
        if process.is_alive():
            process.terminate()


#: Seconds ``--ray ADDRESS`` waits for a cluster to answer (``auto`` or an address), and for a
#: ``local`` Ray to start; then the experiment stops with one line (exit 2).
RAY_CONNECT_TIMEOUT = 30.0
RAY_START_TIMEOUT = 120.0
#: Seconds between two progress lines while Ray starts or connects.
RAY_PROGRESS_EVERY = 5.0


def ray_results(tasks: Sequence[TrialTask], address: str, *, workers: int = 0,
                trials_per_worker: int | None = None, log=print) -> Iterator[TrialResult]:
    """Runs ``tasks`` as Ray tasks (see the module docstring for ``address``); ``workers`` is the
    number of CPUs of a ``local`` Ray (0: this machine's); a Ray worker process runs at most
    ``trials_per_worker`` of them (Ray's ``max_calls``; None: no limit). Ray is started or
    reached now (a :class:`RayError` before any trial runs); the results are yielded as they
    finish."""
    if not tasks:
        return iter(())
    started_here = address == "local"
    start = time.perf_counter()
    ray = init_ray(address, workers=workers, log=log)
    try:
        log(f"ray: {'started a local Ray' if started_here else 'connected to ' + address} in "
            f"{time.perf_counter() - start:.1f} s; "
            f"{ray.cluster_resources().get('CPU', 0):g} CPUs")
    except BaseException:
        ray.shutdown()
        raise
    return _ray_results(ray, tasks, trials_per_worker)


def _ray_results(ray, tasks: Sequence[TrialTask],
                 trials_per_worker: int | None) -> Iterator[TrialResult]:
    try:
        remote = ray.remote(num_cpus=1, max_retries=1,
                            max_calls=trials_per_worker or 0)(run_worker_task)
        pending = [remote.remote(task) for task in tasks]
        try:
            while pending:
                done, pending = ray.wait(pending, num_returns=1)
                for ref in done:
                    yield ray.get(ref)
        finally:
            for ref in pending:
                ray.cancel(ref, force=True)
    finally:
        ray.shutdown()


def init_ray(address: str, *, workers: int = 0, log=None):
    """``ray.init`` for ``address`` (``local``: a Ray on this machine only); returns ``ray``.
    ``log`` is told what happens while Ray starts (every :data:`RAY_PROGRESS_EVERY` s). Raises
    :class:`RayMissing` when Ray is not installed, :class:`RayError` when no cluster answers at
    ``address`` (nothing listening, no cluster for ``auto``); a start or connection that takes
    longer than :data:`RAY_START_TIMEOUT` / :data:`RAY_CONNECT_TIMEOUT` ends the process with one
    line and exit code 2 (``ray.init`` cannot be stopped from Python while it waits)."""
    if not ray_installed():
        raise RayMissing
    log = log or (lambda message: None)
    if address == "local":
        log(f"ray: starting a local Ray (at most {RAY_START_TIMEOUT:.0f} s) ...")
        with environment({**LOCAL_RAY_ENV, **WORKER_ENV}), \
                _deadline("local", "starting a local Ray", RAY_START_TIMEOUT, log,
                          "a local Ray did not start"):
            import ray

            ray.init(num_cpus=workers or os.cpu_count(), include_dashboard=False,
                     _node_ip_address="127.0.0.1", log_to_driver=False,
                     configure_logging=False, namespace="gbh_drake")
        node_ip = ray.util.get_node_ip_address()
        if node_ip != "127.0.0.1":  # ray was imported before the environment was set
            ray.shutdown()
            raise RuntimeError(f"a local Ray would listen on {node_ip}, not the loopback: "
                               "start gbh before anything imports ray")
        return ray
    os.environ.setdefault("RAY_USAGE_STATS_ENABLED", "0")
    log(f"ray: connecting to {address} (at most {RAY_CONNECT_TIMEOUT:.0f} s) ...")
    import ray

    _probe(address, _bootstrap_address(address))
    with _deadline(address, f"connecting to {address}", RAY_CONNECT_TIMEOUT, log,
                   "something listens there but no Ray cluster answered"):
        try:
            ray.init(address=address, log_to_driver=False, configure_logging=False,
                     namespace="gbh_drake", runtime_env={"env_vars": dict(WORKER_ENV)})
        except (ConnectionError, getattr(ray.exceptions, "AuthenticationError",
                                         ConnectionError)) as e:
            raise RayError(f"{address}: {' '.join(str(e).split())}{_auth_hint()}") from None
    return ray


def _auth_hint() -> str:
    """Why a cluster that answers may refuse this process: Ray's token authentication (a head
    started by ``ray start --head`` where ``~/.ray/auth_token`` exists enables it, ray 2.60), which
    a process connecting to an address uses only with ``RAY_AUTH_MODE=token``."""
    if os.environ.get("RAY_AUTH_MODE", "").lower() == "token":
        return ""
    return ("; if the cluster uses token authentication, set RAY_AUTH_MODE=token here, with the "
            "cluster's token in ~/.ray/auth_token or RAY_AUTH_TOKEN (docs/ray.md)")


def _bootstrap_address(address: str) -> str:
    """``host:port`` where the cluster of ``address`` should answer (``auto``: the cluster this
    machine belongs to, as Ray finds it). :class:`RayError` for ``auto`` without a cluster."""
    if address.startswith("ray://"):
        return address[len("ray://"):]
    if address != "auto" and not os.environ.get("RAY_ADDRESS"):
        return address
    from ray._private import services

    try:
        return services.canonicalize_bootstrap_address_or_die(address)
    except ConnectionError:
        raise RayError("auto: no Ray cluster is running on this machine (start one with 'ray "
                       "start --head', give a cluster's address, or --ray local for a Ray of "
                       "this experiment only)") from None
    except ValueError as e:
        raise RayError(f"{address}: {e}") from None


#: What a Ray address may be (:func:`address_problem`).
ADDRESS_FORMS = ("'local', 'auto' or a cluster's address host:port (e.g. 10.0.0.5:6379 or "
                 "ray://10.0.0.5:10001)")


def _host_port(host_port: str) -> tuple[str, int] | None:
    """(host, port) of ``host:port`` (``[v6]:port`` too), or None when it is not one."""
    host, sep, port = host_port.rpartition(":")
    host = host.strip("[]")
    if not sep or not host or not port.isdigit() or not 0 < int(port) < 65536:
        return None
    return host, int(port)


def address_problem(address: str) -> str | None:
    """What is wrong with ``address`` as the Ray engine's (``--ray``, an experiment's
    ``ray_address``), or None: ``local``, ``auto``, ``host:port`` or ``ray://host:port``."""
    if address in ("local", "auto") or _host_port(address.removeprefix("ray://")):
        return None
    return f"not {ADDRESS_FORMS}, got {address!r}"


def _probe(address: str, host_port: str, timeout: float = 10.0) -> None:
    """:class:`RayError` unless something accepts a TCP connection at ``host_port``."""
    parsed = _host_port(host_port)
    if parsed is None:
        raise RayError(f"{address}: not {ADDRESS_FORMS}")
    host, port = parsed
    where = address if host_port == address else f"{address} ({host_port})"
    try:
        socket.create_connection((host, port), timeout=timeout).close()
    except socket.gaierror as e:
        raise RayError(f"{where}: cannot resolve the host {host!r} ({e.strerror})") from None
    except ConnectionRefusedError:
        raise RayError(f"{where}: nothing listens there (connection refused): is the cluster's "
                       "head running (ray start --head)?") from None
    except TimeoutError:
        raise RayError(f"{where}: no answer within {timeout:.0f} s") from None
    except OSError as e:
        raise RayError(f"{where}: cannot connect ({e.strerror or e})") from None


@contextlib.contextmanager
def _deadline(address: str, doing: str, timeout: float, log, failure: str):
    """Says every :data:`RAY_PROGRESS_EVERY` s that ``doing`` goes on; after ``timeout`` s says
    ``failure`` in one line and ends the process (exit 2): ``ray.init`` waits inside C++ and retries
    on its own for minutes."""
    done = threading.Event()
    start = time.monotonic()

    def watch():
        while not done.wait(max(0.0, min(RAY_PROGRESS_EVERY,
                                         timeout - (time.monotonic() - start)))):
            waited = time.monotonic() - start
            if waited >= timeout:
                line = f"gbh: cannot use Ray: {address}: {failure} within {timeout:.0f} s\n"
                os.write(2, line.encode())
                os._exit(2)
            log(f"ray: still {doing} ({waited:.0f} s) ...")

    watcher = threading.Thread(target=watch, name="gbh-ray-deadline", daemon=True)
    watcher.start()
    try:
        yield
    finally:
        done.set()
