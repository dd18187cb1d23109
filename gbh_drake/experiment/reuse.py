"""Trials of another experiment's folder taken as this experiment's (``gbh experiment --reuse``).

Two experiment files often share methods: ``scenarios/experiment_robust.yaml`` runs the
``gbh-10`` of ``scenarios/experiment.yaml`` beside ``gbh-10r``, ``experiment_oneview.yaml`` its
``gbh-1`` and ``antipodal``. A trial is the same trial when its key (object, method, trial,
protocol) and its whole scenario (``scenario_digest``: base, method overrides, object, pose,
seed) are the same, and for an object set's mesh the same version of its entry
(``object_digest``); such a row of another folder is copied into this one (with its replay, if
it has one) instead of being simulated again. The row keeps the commit it ran at: the report's
list of commits says when the rows of one folder come from several (a resumed experiment can
mix commits in the same way), so reuse rows made by the code you mean to measure.
"""

from __future__ import annotations

import shutil
from collections import Counter
from collections.abc import Iterable
from pathlib import Path

from gbh_drake.experiment.rows import ROWS_FILE, FolderError, RowStore, row_key


def reuse_rows(folder: Path, store: RowStore, tasks: Iterable, done: dict, sources: Iterable,
               *, log=print) -> int:
    """Appends to ``store`` (the rows of ``folder``) every row of the ``sources`` folders that
    is a trial of ``tasks`` not yet ``done`` and was made with that task's scenario, and adds it
    to ``done``; copies its replay into ``folder/replays`` (a replay that is not there any more
    leaves the row's ``replay`` empty). A row that ended in an error is not taken. Says per
    source how many rows it took, at which commits, and how many trials it holds with another
    scenario. Returns the number of rows taken. Raises :class:`FolderError` naming a source
    that is this folder or holds no ``trials.jsonl``, or a damaged line of one."""
    by_key = {t.key: t for t in tasks}
    taken = 0
    for source in sources:
        source = Path(source)
        if source.resolve() == Path(folder).resolve():
            raise FolderError(f"{source}: --reuse names the experiment's own folder")
        if not (source / ROWS_FILE).is_file():
            raise FolderError(f"{source}: no {ROWS_FILE} here: --reuse takes an experiment's "
                              "folder")
        commits, other = Counter(), 0
        for row in RowStore(source).load():
            key = row_key(row)
            task = by_key.get(key)
            if task is None or key in done or row.get("outcome") == "error":
                continue
            if task.differs(row):
                other += 1
                continue
            row = dict(row, replay=_copy_replay(source, folder, row.get("replay") or ""))
            store.append(row)
            done[key] = row
            commits[row.get("commit") or "?"] += 1
        n = sum(commits.values())
        taken += n
        at = ", ".join(f"{k} at {c[:12]}" for c, k in sorted(commits.items()))
        log(f"reused {n} trials from {source}" + (f" ({at})" if at else "")
            + (f"; {other} trials there ran other scenarios: not reused" if other else ""))
    return taken


def _copy_replay(source: Path, folder: Path, replay: str) -> str:
    """The replay's path in ``folder`` after copying it from ``source``, or '' without one."""
    parts = Path(replay).parts
    if len(parts) != 2 or parts[0] != "replays" or not (source / replay).is_file():
        return ""
    target = Path(folder) / replay
    target.parent.mkdir(parents=True, exist_ok=True)
    shutil.copyfile(source / replay, target)
    return replay
