"""The project's Meshcat server: listening on the loopback only.

Drake's ``Meshcat()`` listens on all interfaces by default; a simulation has no business being
reachable from other machines, so every Meshcat of gbh_drake comes from :func:`local_meshcat`.
"""

from pydrake.geometry import Meshcat, MeshcatParams


def local_meshcat(port: int | None = None) -> Meshcat:
    """A Meshcat server on ``localhost`` (the first free port from 7000, or ``port``)."""
    params = MeshcatParams(host="localhost")
    if port is not None:
        params.port = port
    return Meshcat(params)


def keep_open(url: str, seconds: float | None = None, *, stdin=None, out=None) -> str:
    """Keeps this process, and so its Meshcat server at ``url``, alive after a run: for
    ``seconds`` when given (Ctrl-C ends it sooner), else until Enter (a line on stdin, a
    terminal or a pipe) or Ctrl-C (SIGINT) or SIGTERM, whatever runs the process (a script, a
    pipeline, no terminal at all: stdin at its end waits for the signal). Says how to leave on
    ``out`` (default stdout) first. Returns what ended it: ``"time"``, ``"enter"`` or
    ``"signal"``; the signal is then not an interruption (:func:`gbh_drake.interrupts.forget`):
    the run was complete."""
    import sys
    import threading
    import time

    from gbh_drake import interrupts

    stdin = sys.stdin if stdin is None else stdin
    out = sys.stdout if out is None else out
    if seconds is not None:
        how = f"for {seconds:g} s (Ctrl-C ends it sooner)"
    elif stdin is not None and not stdin.closed and stdin.isatty():
        how = "until you press Enter (or Ctrl-C)"
    else:
        how = "until Enter on stdin, Ctrl-C (SIGINT) or SIGTERM"
    print(f"Meshcat stays open at {url} {how}", file=out, flush=True)
    entered = threading.Event()
    if seconds is None and stdin is not None and not stdin.closed:
        def read() -> None:
            try:
                if stdin.readline():  # "" is the end of stdin: wait for a signal instead
                    entered.set()
            except (OSError, ValueError):
                pass

        threading.Thread(target=read, name="gbh-keep-open", daemon=True).start()
    deadline = None if seconds is None else time.monotonic() + seconds
    try:
        while not entered.wait(0.1):
            if deadline is not None and time.monotonic() >= deadline:
                return "time"
        return "enter"
    except KeyboardInterrupt:  # SIGINT, SIGTERM, SIGHUP (gbh_drake.interrupts)
        interrupts.forget()
        print(file=out)
        return "signal"
