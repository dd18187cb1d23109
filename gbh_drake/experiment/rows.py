"""The experiment's rows: one JSON object per trial and line in ``trials.jsonl``.

Rows are appended and flushed one by one as trials finish (an interrupted experiment keeps every
finished trial); on start the rows already there are read and their trials skipped. A last line
cut short by an interrupted write is dropped with a warning (its trial runs again); any other
damaged line (not UTF-8, not JSON, a row without one of :data:`ROW_FIELDS`) is an error naming
the file and line (:class:`FolderError`), and nothing is run or rewritten. Reports order rows by
:func:`sort_key`, never by when they finished.

A row (see :func:`gbh_drake.experiment.worker.run_trial_task`): ``experiment``, ``object``,
``is_control``, ``method``, ``trial``, ``seed``, ``grasp_method``, ``viewpoints``, ``pose`` (x, y,
z in m, roll, pitch, yaw in rad), ``outcome``, ``success``, ``reason``, ``held_by`` (``cage`` or
``pinch``), ``grasp_kind``, ``grasp_score``, ``grasp_rank``, ``fallback``, ``refusals``,
``replay`` (path relative to the folder, or empty), ``commit``, ``scenario_digest``,
``stage_times`` (wall seconds: build, scan, plan, simulate, replay, total), ``worker`` and
``record`` (the whole :class:`~gbh_drake.trial.TrialRecord`), ``protocol`` (``stable`` or
``natural``, set by the runner; a row without it, written before protocols existed, is
``stable``), and for an object set's mesh ``object_digest`` (which version of its entry and
mesh file it ran: :attr:`~gbh_drake.experiment.task.TrialTask.object_digest`). NaN is written
as null.
"""

from __future__ import annotations

import contextlib
import copy
import json
import os
from collections.abc import Iterable, Sequence
from pathlib import Path

from gbh_drake.experiment.worker import TIMING_FIELDS
from gbh_drake.outputs import write_atomically

#: The rows' file in an experiment's folder.
ROWS_FILE = "trials.jsonl"


#: The protocol of a row that does not say (rows written before there were protocols).
DEFAULT_PROTOCOL = "stable"


def protocol_of(row: dict) -> str:
    """The row's protocol (``stable`` when the row has none)."""
    return row.get("protocol") or DEFAULT_PROTOCOL


def row_key(row: dict) -> tuple[str, str, int, str]:
    """(object, method, trial, protocol): a trial of the experiment."""
    return (row["object"], row["method"], int(row["trial"]), protocol_of(row))


def comparable(row: dict) -> dict:
    """``row`` without its timing fields (``stage_times``, ``worker``, the record's
    ``timings``): what must be equal whatever the number of workers or the engine."""
    row = copy.deepcopy(row)
    for name in TIMING_FIELDS:
        row.pop(name, None)
    if isinstance(row.get("record"), dict):
        row["record"].pop("timings", None)
    return row


def sort_key(objects: Sequence[str] = (), methods: Sequence[str] = (),
             protocols: Sequence[str] = ()):
    """Orders rows by protocol (in ``protocols``' order, then by name), object (in
    ``objects``' order, then by name), method (likewise), trial."""
    o = {name: i for i, name in enumerate(objects)}
    m = {name: i for i, name in enumerate(methods)}
    p = {name: i for i, name in enumerate(protocols)}

    def key(row: dict):
        protocol = protocol_of(row)
        return (p.get(protocol, len(p)), protocol, o.get(row["object"], len(o)), row["object"],
                m.get(row["method"], len(m)), row["method"], int(row["trial"]))

    return key


def to_line(row: dict) -> str:
    return json.dumps(row, sort_keys=True, allow_nan=False) + "\n"


class FolderError(ValueError):
    """A file of an experiment folder that cannot be read or is damaged: the message names the
    file and, where there is one, the line."""


#: The fields every row has, with their types (a row without one is damaged): the key of its
#: trial and what the reports count.
ROW_FIELDS = {"object": str, "method": str, "trial": int, "seed": int, "outcome": str,
              "success": bool, "reason": str, "viewpoints": int}


#: Fields a row may leave out (or give as null), with their types when it has them: what the
#: runner and the reports key or sort by besides :data:`ROW_FIELDS`.
OPTIONAL_ROW_FIELDS = {"protocol": str, "scenario_digest": str, "object_digest": str,
                       "replay": str}


def row_problem(row) -> str | None:
    """What makes ``row`` (a parsed line) not a row, or None."""
    if not isinstance(row, dict):
        return f"not a row (a JSON object), got {type(row).__name__}"
    missing = [name for name in ROW_FIELDS if name not in row]
    if missing:
        return f"a row without {', '.join(missing)}"
    present = {name: kind for name, kind in OPTIONAL_ROW_FIELDS.items()
               if row.get(name) is not None}
    for name, kind in {**ROW_FIELDS, **present}.items():
        value = row[name]
        if not isinstance(value, kind) or (kind is int and isinstance(value, bool)):
            return f"{name} is {value!r}, not {'a' if kind is not int else 'an'} " \
                   f"{'integer' if kind is int else {str: 'string', bool: 'boolean'}[kind]}"
    return None


def read_jsonl(path: Path, *, check=None, warn=None, repair: bool = False) -> list[dict]:
    """The JSON objects of ``path``, one a line, in file order ([] without the file). A last
    line without its newline was cut short by an interrupted write: it is dropped (``warn`` is
    told which line) and, with ``repair``, cut off the file so that the next line written
    starts on a line of its own. Any other bad line (not UTF-8, not JSON, ``check(value)``
    returning a problem) raises :class:`FolderError` naming the file and the line: nothing is
    dropped that a run wrote whole."""
    path = Path(path)
    try:
        if not path.exists():
            return []
        data = path.read_bytes()
    except OSError as e:
        raise FolderError(f"{path}: cannot read it ({e.strerror or e})") from None
    *lines, cut = data.split(b"\n")
    rows = []
    for i, line in enumerate(lines):
        if not line.strip():
            continue
        try:
            value = json.loads(line.decode("utf-8"))
        except UnicodeDecodeError as e:
            raise FolderError(f"{path}: line {i + 1}: not UTF-8 text (byte 0x{line[e.start]:02x}"
                              f"); the file is damaged: fix or remove that line") from None
        except ValueError as e:
            raise FolderError(f"{path}: line {i + 1}: not a JSON line ({e}); the file is "
                              "damaged: fix or remove that line") from None
        problem = check(value) if check else None
        if problem:
            raise FolderError(f"{path}: line {i + 1}: {problem}; the file is damaged: fix or "
                              "remove that line")
        rows.append(value)
    if cut.strip():
        line = data.count(b"\n") + 1
        if warn is not None:
            warn(f"{path}: line {line} was cut short (an interrupted write): "
                 + ("dropped" if repair else "left out"))
        if repair:
            try:
                with open(path, "r+b") as f:
                    f.truncate(len(data) - len(cut))
            except OSError as e:
                raise FolderError(f"{path}: cannot cut off its damaged last line "
                                  f"({e.strerror or e})") from None
    return rows


class RowStore:
    """``trials.jsonl`` of one experiment folder."""

    def __init__(self, folder: Path):
        self.path = Path(folder) / ROWS_FILE

    def load(self, *, repair: bool = False, warn=None) -> list[dict]:
        """The rows in the file, in file order (:func:`read_jsonl`, each line checked by
        :func:`row_problem`): a last line cut short is dropped and ``warn`` told (its trial runs
        again), with ``repair`` cut off the file. Raises :class:`FolderError` on a bad line
        elsewhere."""
        return read_jsonl(self.path, check=row_problem, warn=warn, repair=repair)

    def append(self, row: dict) -> None:
        """Appends one row and flushes it to the disk. A row that cannot be written whole (a
        full disk) is cut off again, so that the file keeps only whole rows; the OSError is
        raised."""
        self.path.parent.mkdir(parents=True, exist_ok=True)
        line = to_line(row).encode()
        fd = os.open(self.path, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o644)
        try:
            size = os.fstat(fd).st_size
            try:
                done = 0
                while done < len(line):  # (a write may take part of it: the rest follows)
                    done += os.write(fd, line[done:])
                os.fsync(fd)
            except OSError:
                with contextlib.suppress(OSError):
                    os.ftruncate(fd, size)  # (what part of the line reached the file goes)
                raise
        finally:
            os.close(fd)

    def rewrite(self, rows: Iterable[dict]) -> None:
        """Replaces the file with ``rows`` (atomically: a temporary file renamed into place)."""
        write_atomically(self.path, "".join(to_line(r) for r in rows))
