"""Output folders: checked before a run starts, held by one run at a time, written atomically.

A run's folder holds one complete run: the new one, or, when the new one fails or is
interrupted, the previous one as it was (or nothing, if there was none):

* :class:`RunOutputs` (a context manager) first checks the folder: it is made if missing; a path
  that is a file, a folder that cannot be written and a disk with less than
  :data:`MIN_FREE_BYTES` free are refused (:class:`OutputError`) before anything is simulated.
* It locks the folder (``flock`` on ``<folder>/.gbh.lock``): a second run given the same folder
  while the first is running is refused with a message naming the first's process id. The lock
  dies with its process (even a killed one), so it is never stale.
* It removes the temporary files an earlier killed run left; the previous run's outputs stay
  until this run's replace them.
* :meth:`RunOutputs.stage` writes each output at once to a hidden temporary file beside its
  final name (a full disk fails here, with the file named); :meth:`RunOutputs.commit` moves the
  previous run's outputs aside and renames the new ones into place, ``summary.yaml`` last, then
  drops what it moved aside (and any previous output the new run does not make). An exception,
  Ctrl-C or SIGTERM before the commit has finished removes the temporary files and whatever this
  run had already renamed, and puts the previous run's outputs back.

:func:`replace_contents` does the same for ``gbh objects build --out``: the models are built in a
hidden staging folder, then each object's folder replaces the old one.
"""

from __future__ import annotations

import contextlib
import enum
import errno
import fcntl
import math
import os
import shutil
from collections.abc import Callable
from pathlib import Path

from gbh_drake import interrupts

#: A run needs this much free space in its output folder (the replay is 5-30 MB).
MIN_FREE_BYTES = 64 * 2**20
#: The lock file in every output folder (hidden; it stays, empty of meaning once unlocked).
LOCK_NAME = ".gbh.lock"
#: What ``gbh run`` writes into its folder (a pick also its scan and grasps, and with
#: ``--save-views`` the views' depth images: ``gbh_drake.scan_grasps.run_export``).
RUN_OUTPUTS = ("replay.html", "scenario.yaml", "summary.yaml", "scan.ply", "grasps.json", "views")
_TMP_PREFIX = ".gbh-tmp-"


class OutputError(OSError):
    """An output folder or file that cannot be used; the message names it and says why."""

    def __init__(self, path: Path | str, problem: str):
        super().__init__(f"{path}: {problem}")
        self.path = str(path)
        self.problem = problem

    def __reduce__(self):  # picklable with its parts
        return type(self), (self.path, self.problem)


def reason(e: OSError) -> str:
    """Why ``e`` happened, in words (``no space left on the disk``)."""
    reasons = {errno.ENOSPC: "no space left on the disk", errno.EDQUOT: "disk quota exceeded",
               errno.EROFS: "read-only file system", errno.EACCES: "permission denied",
               errno.EPERM: "permission denied", errno.ENOTDIR: "a part of the path is a file",
               errno.EEXIST: "exists and is not a folder",
               errno.ENAMETOOLONG: "a name in the path is too long: at most 255 bytes",
               errno.EISDIR: "is a folder", errno.EIO: "input/output error",
               errno.EFBIG: "file too large"}
    return reasons.get(e.errno, e.strerror or str(e))


def prepare_folder(folder: Path, *, min_free: int = MIN_FREE_BYTES) -> Path:
    """Makes ``folder`` if needed; raises :class:`OutputError` if it is a file, cannot be
    made, or its disk has less than ``min_free`` bytes free. Returns it resolved."""
    folder = Path(folder)
    if "\0" in str(folder):
        raise OutputError(repr(str(folder)), "holds a NUL character")
    try:
        is_file = folder.exists() and not folder.is_dir()
    except OSError as e:  # a name too long, a folder that cannot be looked into
        raise OutputError(folder, f"cannot be used as a folder ({reason(e)})") from None
    if is_file:
        raise OutputError(folder, "is a file, not a folder")
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        raise OutputError(folder, f"cannot create the folder ({reason(e)})") from None
    if not os.access(folder, os.W_OK | os.X_OK):
        raise OutputError(folder, "the folder is not writable")
    try:
        free = shutil.disk_usage(folder).free
    except OSError as e:
        raise OutputError(folder, f"cannot be used as a folder ({reason(e)})") from None
    if free < min_free:
        raise OutputError(folder, f"only {free / 2**20:.1f} MB free on its disk; a run needs "
                                  f"{min_free / 2**20:.0f} MB")
    return folder.resolve()


class FolderLock:
    """An exclusive ``flock`` on ``<folder>/.gbh.lock``; :class:`OutputError` if held. Also a
    context manager (acquired on entry, released on exit). ``holder``: what holds such locks,
    for the message (``gbh run``, ``gbh experiment``); ``hint``: what to do instead."""

    def __init__(self, folder: Path, *, holder: str = "gbh run",
                 hint: str = "give another output folder (output_dir)"):
        self.path = Path(folder) / LOCK_NAME
        self.holder = holder
        self.hint = hint
        self._fd: int | None = None

    def __enter__(self) -> FolderLock:
        self.acquire()
        return self

    def __exit__(self, *exc) -> None:
        self.release()

    def acquire(self) -> None:
        try:
            fd = os.open(self.path, os.O_RDWR | os.O_CREAT, 0o644)
        except IsADirectoryError:
            raise OutputError(self.path, "is a folder, not gbh's lock file; remove it") from None
        except OSError as e:
            raise OutputError(self.path.parent, f"cannot write in the folder ({reason(e)})") \
                from None
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            holder = os.pread(fd, 64, 0).decode(errors="replace").strip() or "?"
            os.close(fd)
            raise OutputError(self.path.parent, f"another {self.holder} (process {holder}) is "
                                                "writing into this folder; wait for it to finish "
                                                f"or {self.hint}") from None
        try:
            os.ftruncate(fd, 0)
            os.pwrite(fd, f"{os.getpid()}\n".encode(), 0)
        except OSError as e:
            os.close(fd)
            raise OutputError(self.path.parent, f"cannot write in the folder ({reason(e)})") \
                from None
        self._fd = fd

    def release(self) -> None:
        if self._fd is not None:
            with contextlib.suppress(OSError):
                os.ftruncate(self._fd, 0)
            os.close(self._fd)  # releases the flock
            self._fd = None


def write_file(path: Path, data: str | bytes) -> Path:
    """Writes ``data`` to a hidden temporary file beside ``path`` (flushed to disk) and returns
    that file; raises :class:`OutputError` naming ``path`` (the temporary file removed)."""
    path = Path(path)
    tmp = path.with_name(f"{_TMP_PREFIX}{os.getpid()}-{path.name}")
    raw = data.encode() if isinstance(data, str) else data
    try:
        with open(tmp, "wb") as f:
            f.write(raw)
            f.flush()
            os.fsync(f.fileno())
    except OSError as e:
        remove(tmp)
        raise OutputError(path, f"could not write it ({reason(e)})") from None
    except BaseException:
        remove(tmp)
        raise
    return tmp


def write_atomically(path: Path, data: str | bytes) -> None:
    """Writes ``path`` whole or not at all (a temporary file renamed into place; a device or a
    pipe is written into: :func:`special_file`)."""
    if special_file(path):
        write_into(path, data)
        return
    tmp = write_file(path, data)
    try:
        os.replace(tmp, path)
    except OSError as e:
        remove(tmp)
        raise OutputError(path, f"could not write it ({reason(e)})") from None


def special_file(path: Path) -> bool:
    """Whether ``path`` is a device, a pipe or a socket (``/dev/null``, ``/dev/stdout``): an
    output written into, never staged beside it and renamed over it (as root a rename would
    replace the device node with a file)."""
    path = Path(path)
    try:
        return path.exists() and not path.is_file() and not path.is_dir()
    except OSError:
        return False


def write_into(path: Path, data: str | bytes) -> None:
    """Writes ``data`` into the existing ``path`` as it is (no temporary file); raises
    :class:`OutputError` naming ``path``."""
    try:
        with open(path, "wb") as f:
            f.write(data.encode() if isinstance(data, str) else data)
    except OSError as e:
        raise OutputError(path, f"could not write it ({reason(e)})") from None


def remove(path: Path) -> None:
    """Removes a file or folder if it is there (errors ignored)."""
    with contextlib.suppress(OSError):
        if path.is_dir() and not path.is_symlink():
            shutil.rmtree(path)
        else:
            path.unlink()


class RunOutputs:
    """One run's output folder (see the module docstring)::

        with RunOutputs(folder) as outputs:   # checked, locked; the previous outputs stay
            ...                               # the run
            outputs.stage("replay.html", html)
            outputs.stage("summary.yaml", text)
            outputs.commit()                  # all renamed into place, or the previous kept
    """

    def __init__(self, folder: Path, names: tuple[str, ...] = RUN_OUTPUTS, *,
                 min_free: int = MIN_FREE_BYTES):
        self.folder = Path(folder)
        self.names = names
        self.min_free = min_free
        self._lock: FolderLock | None = None
        self._staged: dict[str, Path] = {}
        self._committed: list[Path] = []
        self._aside: dict[Path, Path] = {}
        """The previous run's outputs moved aside during the commit: final path -> where."""
        self.committed = False

    def __enter__(self) -> RunOutputs:
        self.folder = prepare_folder(self.folder, min_free=self.min_free)
        self._lock = FolderLock(self.folder)
        self._lock.acquire()
        try:
            self._clear_stale()
        except BaseException:
            self._lock.release()
            raise
        return self

    def _clear_stale(self) -> None:
        """Removes the temporary files left by killed runs (we hold the lock: no other run is
        writing here); the previous run's outputs stay."""
        for stale in self.folder.glob(f"{_TMP_PREFIX}*"):
            remove(stale)

    def path(self, name: str) -> Path:
        """Where output ``name`` will be once committed."""
        return self.folder / name

    def stage(self, name: str, data: str | bytes) -> Path:
        """Writes output ``name`` to its temporary file now; returns its final path."""
        if name in self._staged:
            remove(self._staged.pop(name))
        self._staged[name] = write_file(self.folder / name, data)
        return self.folder / name

    def stage_folder(self, name: str, write: Callable[[Path], object]) -> Path:
        """Writes output folder ``name`` now (``write(folder)`` fills a temporary folder beside
        it); returns its final path. A failure to write raises :class:`OutputError` naming it."""
        if name in self._staged:
            remove(self._staged.pop(name))
        tmp = self.folder / f"{_TMP_PREFIX}{os.getpid()}-{name}"
        remove(tmp)
        self._staged[name] = tmp
        try:
            tmp.mkdir()
            write(tmp)
        except OSError as e:
            raise OutputError(self.folder / name, f"could not write it ({reason(e)})") from None
        return self.folder / name

    def commit(self) -> None:
        """Moves the previous run's outputs aside, renames every staged output into place
        (``summary.yaml`` last), then drops what was moved aside. A signal received before (and
        its exception dropped by some library) stops it here: the previous run is kept."""
        interrupts.check()
        for name in self.names:  # aside, all of them: the new run replaces the whole set
            target = self.folder / name
            if target.exists() or target.is_symlink():
                aside = target.with_name(f"{_TMP_PREFIX}{os.getpid()}-previous-{name}")
                try:
                    os.replace(target, aside)
                except OSError as e:
                    raise OutputError(target, f"could not replace it ({reason(e)})") from None
                self._aside[target] = aside
        order = sorted(self._staged, key=lambda n: n == "summary.yaml")
        for name in order:
            target = self.folder / name
            try:
                os.replace(self._staged[name], target)
            except OSError as e:
                raise OutputError(target, f"could not write it ({reason(e)})") from None
            self._committed.append(target)
        self._staged.clear()
        self.committed = True
        for aside in self._aside.values():
            remove(aside)
        self._aside.clear()

    def __exit__(self, exc_type, exc, tb) -> None:
        try:
            if exc_type is not None or not self.committed:
                for tmp in self._staged.values():
                    remove(tmp)
                for done in self._committed:
                    remove(done)
                for target, aside in self._aside.items():  # the previous run, back in place
                    with contextlib.suppress(OSError):
                        os.replace(aside, target)
                self._staged.clear()
                self._committed.clear()
                self._aside.clear()
        finally:
            if self._lock is not None:
                self._lock.release()


def replace_contents(out: Path, build: Callable[[Path], list], *,
                     min_free: int = MIN_FREE_BYTES) -> list:
    """Runs ``build(staging)`` in a hidden staging folder inside ``out``, then moves each entry
    it made into ``out``, replacing the old one; on any failure or interrupt ``out`` keeps its
    old contents and the staging folder is removed. Returns what ``build`` returned."""
    out = prepare_folder(Path(out), min_free=min_free)
    lock = FolderLock(out)
    lock.acquire()
    staging = out / f"{_TMP_PREFIX}{os.getpid()}-staging"
    try:
        for stale in out.glob(f"{_TMP_PREFIX}*"):
            remove(stale)
        staging.mkdir()
        try:
            result = build(staging)
        except OSError as e:
            where = e.filename or out
            raise OutputError(where, f"could not write it ({reason(e)})") from None
        for entry in sorted(staging.iterdir()):
            target = out / entry.name
            old = out / f"{_TMP_PREFIX}{os.getpid()}-old-{entry.name}"
            if target.exists() or target.is_symlink():
                os.replace(target, old)
            os.replace(entry, target)
            remove(old)
        return result
    finally:
        remove(staging)
        lock.release()


def plain(value):
    """``value`` made ready for JSON and YAML: numpy scalars as Python numbers, enums as their
    values, tuples as lists, keys as strings, NaN and infinities as None."""
    if isinstance(value, dict):
        return {str(k): plain(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [plain(v) for v in value]
    if isinstance(value, enum.Enum):
        return plain(value.value)
    if hasattr(value, "item") and not isinstance(value, str | bytes):  # numpy scalar
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value
