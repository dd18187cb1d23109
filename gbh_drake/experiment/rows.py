"""The experiment's rows: one JSON object per trial and line in ``trials.jsonl``.

Rows are appended and flushed one by one as trials finish (an interrupted experiment keeps every
finished trial); on start the rows already there are read and their trials skipped. A line cut
short by the interruption is dropped. Reports order rows by :func:`sort_key`, never by when they
finished.

A row (see :func:`gbh_drake.experiment.worker.run_trial_task`): ``experiment``, ``object``,
``is_control``, ``method``, ``trial``, ``seed``, ``grasp_method``, ``viewpoints``, ``pose`` (x, y,
z in m, roll, pitch, yaw in rad), ``outcome``, ``success``, ``reason``, ``held_by`` (``cage`` or
``pinch``), ``grasp_kind``, ``grasp_score``, ``grasp_rank``, ``fallback``, ``refusals``,
``replay`` (path relative to the folder, or empty), ``commit``, ``scenario_digest``,
``stage_times`` (wall seconds: build, scan, plan, simulate, replay, total), ``worker`` and
``record`` (the whole :class:`~gbh_drake.trial.TrialRecord`), and ``protocol`` (``stable`` or
``natural``, set by the runner; a row without it, written before protocols existed, is
``stable``). NaN is written as null.
"""

from __future__ import annotations

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


class RowStore:
    """``trials.jsonl`` of one experiment folder."""

    def __init__(self, folder: Path):
        self.path = Path(folder) / ROWS_FILE

    def load(self, *, repair: bool = False) -> list[dict]:
        """The rows in the file, in file order. A last line cut short (an interrupted write) is
        ignored, and with ``repair`` cut off the file so that new rows start on a line of their
        own. Raises ``ValueError`` on a bad line elsewhere."""
        if not self.path.is_file():
            return []
        data = self.path.read_bytes()
        rows, good_end = [], 0
        lines = data.split(b"\n")
        for i, line in enumerate(lines):
            last = i == len(lines) - 1
            if not line.strip():
                if not last:
                    good_end += len(line) + 1
                continue
            try:
                row = json.loads(line)
                if last:  # no newline after it: the write was cut
                    raise ValueError("unterminated")
            except ValueError as e:
                if last:
                    break
                raise ValueError(f"{self.path}: line {i + 1} is not a row: {e}") from e
            rows.append(row)
            good_end += len(line) + 1
        if repair and good_end < len(data):
            with open(self.path, "r+b") as f:
                f.truncate(good_end)
        return rows

    def append(self, row: dict) -> None:
        """Appends one row and flushes it to the disk."""
        self.path.parent.mkdir(parents=True, exist_ok=True)
        with open(self.path, "a") as f:
            f.write(to_line(row))
            f.flush()
            os.fsync(f.fileno())

    def rewrite(self, rows: Iterable[dict]) -> None:
        """Replaces the file with ``rows`` (atomically: a temporary file renamed into place)."""
        write_atomically(self.path, "".join(to_line(r) for r in rows))
