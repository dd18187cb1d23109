"""Where the trials run: local worker processes, or Ray tasks. Both yield results as trials finish.

* :func:`local_results`: a ``concurrent.futures.ProcessPoolExecutor`` of ``workers`` processes
  (``spawn``: fresh interpreters, nothing inherited from this process's state). Each process runs
  one trial at a time and keeps its imported modules and its Meshcat across trials.
* :func:`ray_results`: the same function as Ray tasks (one CPU each) on a cluster: ``auto`` (the
  cluster this machine belongs to), ``ray://host:port`` or ``host:port`` (a cluster's address; its
  nodes need this package installed at the same path), or ``local`` (a one-machine Ray started
  here, listening on the loopback only, dashboard and usage reporting off). Ray is optional
  (``pip install 'gbh_drake[ray]'``): only this engine imports it.

Workers run single-threaded (see :mod:`gbh_drake.experiment.worker`), so rows are identical,
timing fields aside, whatever the number of workers or the engine.
"""

from __future__ import annotations

import contextlib
import importlib.util
import multiprocessing
import os
import time
from collections.abc import Iterator, Sequence
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait

from gbh_drake.experiment.task import TrialResult, TrialTask
from gbh_drake.experiment.worker import run_trial_task, set_single_threaded

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


#: Why the Ray engine cannot run here (``gbh experiment --ray`` without Ray installed).
RAY_MISSING = ("--ray needs Ray, which is not installed in this environment: pip install "
               "'gbh_drake[ray]' (or leave out --ray to run local worker processes)")


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


def local_results(tasks: Sequence[TrialTask], workers: int) -> Iterator[TrialResult]:
    """Runs ``tasks`` on ``workers`` local processes; yields each result as it finishes."""
    if not tasks:
        return
    context = multiprocessing.get_context("spawn")
    with environment(WORKER_ENV):
        pool = ProcessPoolExecutor(max_workers=max(1, workers), mp_context=context,
                                   initializer=set_single_threaded)
        finished = False
        try:
            pending = {pool.submit(run_trial_task, task) for task in tasks}
            while pending:
                done, pending = wait(pending, return_when=FIRST_COMPLETED)
                for future in done:
                    yield future.result()
            finished = True
        finally:
            if not finished:  # Ctrl-C, SIGTERM, an error, or the caller stopped early
                _stop_workers(pool)
            pool.shutdown(wait=True, cancel_futures=True)


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


def ray_results(tasks: Sequence[TrialTask], address: str, *, workers: int = 0,
                log=print) -> Iterator[TrialResult]:
    """Runs ``tasks`` as Ray tasks (see the module docstring for ``address``); ``workers`` is the
    number of CPUs of a ``local`` Ray (0: this machine's). Yields results as they finish."""
    if not tasks:
        return
    started_here = address == "local"
    start = time.perf_counter()
    ray = init_ray(address, workers=workers)
    try:
        log(f"ray: {'started a local Ray' if started_here else 'connected to ' + address} in "
            f"{time.perf_counter() - start:.1f} s; "
            f"{ray.cluster_resources().get('CPU', 0):g} CPUs")
        remote = ray.remote(num_cpus=1, max_retries=1)(run_trial_task)
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


def init_ray(address: str, *, workers: int = 0):
    """``ray.init`` for ``address`` (``local``: a Ray on this machine only); returns ``ray``.
    Raises :class:`RayMissing` when Ray is not installed."""
    if not ray_installed():
        raise RayMissing
    if address == "local":
        with environment({**LOCAL_RAY_ENV, **WORKER_ENV}):
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
    import ray

    ray.init(address=address, log_to_driver=False, configure_logging=False,
             namespace="gbh_drake", runtime_env={"env_vars": dict(WORKER_ENV)})
    return ray
