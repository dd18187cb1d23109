"""One handler for SIGINT, SIGTERM and SIGHUP for the whole ``gbh`` process.

The first signal is recorded (:func:`received`) and turned into an exception in the main thread
(``KeyboardInterrupt`` for SIGINT; :class:`Terminated` and :class:`HungUp`, both subclasses of
``KeyboardInterrupt``, for SIGTERM and SIGHUP), so that outputs are cleaned up on the way out:

* not while a module is being imported: an exception raised inside an import (pydrake's,
  open3d's and trimesh's take seconds) is turned by extension modules into ``ImportError:
  initialization failed``, by scipy's lazy loader into an ``AttributeError``, or swallowed by
  trimesh's import guards (which catch ``BaseException``). The handler then only records the
  signal and looks again every :data:`RETRY` seconds (a SIGALRM timer): the exception is raised
  as soon as no import is running;
* nor inside a :func:`deferred` block (raised when the block ends);
* :func:`check` raises it again at the program's checkpoints (after the imports, at every step
  of Drake's simulator, before a run's outputs are committed, between an experiment's rows), in
  case some code caught and dropped it;
* :func:`exit_code` decides the exit status from the record (128 + the signal: 130, 143, 129),
  whatever became of the exception.

A second signal ends the process at once, without a traceback: the handler is removed when the
first one arrives (the default action), and a watcher thread (woken through
``signal.set_wakeup_fd``) exits with the signal's code when the second arrives before Python
could run the handler, or when the first is not handled within :data:`GRACE` seconds, as while
the main thread waits inside C++ (``ray.init``). A forked child that inherited the handler takes
the default action.
"""

from __future__ import annotations

import contextlib
import os
import select
import signal
import threading
import time

#: The signals handled, with the words of the one line that says what happened.
SIGNALS = {signal.SIGINT: "interrupted (SIGINT)", signal.SIGTERM: "terminated (SIGTERM)",
           signal.SIGHUP: "hung up (SIGHUP)"}
#: Seconds between two looks, while a signal waits for an import to finish.
RETRY = 0.02
#: Seconds the main thread has to run the handler before the watcher ends the process.
GRACE = 5.0


class Terminated(KeyboardInterrupt):
    """SIGTERM arrived (raised in the main thread, like KeyboardInterrupt for SIGINT)."""


class HungUp(KeyboardInterrupt):
    """SIGHUP arrived (the terminal went away)."""


_EXCEPTIONS = {signal.SIGINT: KeyboardInterrupt, signal.SIGTERM: Terminated,
               signal.SIGHUP: HungUp}

_pending: int | None = None
_pid: int | None = None
_previous: dict = {}
_said = False
_deferring = 0


def received() -> int | None:
    """The signal received since :func:`install` (None: none)."""
    return _pending


def exit_code(default: int = 130) -> int:
    """128 + the signal received (``default`` if none was: a ``KeyboardInterrupt`` raised by
    hand, as tests do)."""
    return 128 + _pending if _pending is not None else default


def describe(default: int = signal.SIGINT) -> str:
    """``interrupted (SIGINT)``, ``terminated (SIGTERM)`` or ``hung up (SIGHUP)``."""
    return SIGNALS[_pending if _pending is not None else default]


def check() -> None:
    """Raises the signal's exception if a signal was received (a checkpoint)."""
    if _pending is not None:
        _stop_timer()
        raise _EXCEPTIONS[_pending]


def mark_said() -> None:
    """The command has said in its own words what the signal ended (:func:`said`)."""
    global _said
    _said = True


def said() -> bool:
    """Whether :func:`mark_said` was called since :func:`install`."""
    return _said


def forget() -> None:
    """Forgets a received signal (it was dealt with: leaving a finished run's live view)."""
    global _pending
    _pending = None


def install() -> bool:
    """Installs the handler for the signals not ignored (``nohup`` keeps SIGHUP ignored); in the
    main thread only (returns False elsewhere, doing nothing). Forgets an earlier signal."""
    global _pid, _pending, _said
    if threading.current_thread() is not threading.main_thread():
        return False
    _pid, _pending, _said = os.getpid(), None, False
    for signum in SIGNALS:
        current = signal.getsignal(signum)
        if current is signal.SIG_IGN:
            continue
        _previous[signum] = signal.signal(signum, _on_signal)
    _start_watcher()
    return True


def uninstall() -> None:
    """Puts back the handlers :func:`install` replaced and stops the retry timer."""
    _stop_timer()
    _stop_watcher()
    while _previous:
        signum, handler = _previous.popitem()
        signal.signal(signum, handler if handler is not None else signal.SIG_DFL)


@contextlib.contextmanager
def handled():
    """:func:`install` for the duration (then :func:`uninstall`)."""
    installed = install()
    try:
        yield
    finally:
        if installed:
            uninstall()


@contextlib.contextmanager
def deferred():
    """A block a signal does not cut short (a row and its replay written together): the
    signal's exception is raised when the block ends."""
    global _deferring
    _deferring += 1
    try:
        yield
    finally:
        _deferring -= 1
    if not _deferring:
        check()


def _must_wait(frame) -> bool:
    return bool(_deferring) or _in_import(frame)


def _in_import(frame) -> bool:
    while frame is not None:
        if frame.f_code.co_filename.startswith("<frozen importlib._bootstrap"):
            return True
        frame = frame.f_back
    return False


def _on_signal(signum, frame):
    global _pending
    for s in SIGNALS:  # a second signal: the default action, at once
        if s in _previous:
            signal.signal(s, signal.SIG_DFL)
    if os.getpid() != _pid:  # a forked child that inherited the handler
        os.kill(os.getpid(), signum)
        return
    _pending = signum
    if _must_wait(frame):
        _start_timer()
        return
    raise _EXCEPTIONS[signum]


def _on_timer(signum, frame):
    if _pending is None:
        return
    if _must_wait(frame):
        signal.setitimer(signal.ITIMER_REAL, RETRY)
        return
    _stop_timer()
    raise _EXCEPTIONS[_pending]


_timer_previous = None


def _start_timer() -> None:
    global _timer_previous
    if _timer_previous is None:
        _timer_previous = signal.signal(signal.SIGALRM, _on_timer) or signal.SIG_DFL
    signal.setitimer(signal.ITIMER_REAL, RETRY)


def _stop_timer() -> None:
    global _timer_previous
    if _timer_previous is not None:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, _timer_previous)
        _timer_previous = None


_watcher: tuple | None = None  # (read fd, write fd, the previous wakeup fd, thread)


def _start_watcher() -> None:
    global _watcher
    if _watcher is not None:
        return
    r, w = os.pipe()
    os.set_blocking(w, False)
    try:
        previous = signal.set_wakeup_fd(w, warn_on_full_buffer=False)
    except ValueError:
        os.close(r)
        os.close(w)
        return
    thread = threading.Thread(target=_watch, args=(r,), name="gbh-signals", daemon=True)
    thread.start()
    _watcher = (r, w, previous, thread)


def _stop_watcher() -> None:
    global _watcher
    if _watcher is None:
        return
    r, w, previous, thread = _watcher
    _watcher = None
    signal.set_wakeup_fd(previous)
    os.close(w)  # the watcher reads the end of the pipe and returns
    thread.join(timeout=1.0)
    os.close(r)


def _watch(r: int) -> None:
    first, since = None, 0.0
    while True:
        timeout = None if first is None else max(0.0, since + GRACE - time.monotonic())
        ready, _, _ = select.select([r], [], [], timeout)
        if not ready:  # GRACE passed: the main thread is inside a call that does not return
            if _pending is None:
                _exit_now(first, f"{SIGNALS[first]}; stopped at once (a call into C++ did not "
                                 f"return within {GRACE:.0f} s)")
            first = None
            continue
        data = os.read(r, 64)
        if not data:
            return
        for signum in data:
            if signum not in SIGNALS or os.getpid() != _pid:
                continue
            if first is not None:  # the second before the first was handled
                _exit_now(signum, f"{SIGNALS[signum]} again; stopped at once")
            first, since = signum, time.monotonic()


def _exit_now(signum: int, message: str) -> None:
    with contextlib.suppress(OSError):
        os.write(2, f"gbh: {message}\n".encode())
    os._exit(128 + signum)


def _after_fork_in_child() -> None:  # a forked child must not wake this process's watcher
    global _watcher
    _watcher = None
    with contextlib.suppress(ValueError, OSError):
        signal.set_wakeup_fd(-1)


os.register_at_fork(after_in_child=_after_fork_in_child)
