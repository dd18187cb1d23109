"""What a worker needs to run one trial, and what it sends back: plain data, no pydrake.

Kept free of heavy imports: a worker process (or a Ray worker) unpickles a :class:`TrialTask`
before it runs the first trial, and it must not load OpenMP libraries before it has set its
thread count (see :mod:`gbh_drake.experiment.worker`).
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class TrialTask:
    """One trial: an object at one random resting pose, picked by one method."""

    experiment: str
    """The experiment's name (rows carry it)."""
    object: str
    """Name of the object in the object set."""
    is_control: bool
    """The object has nothing hangable (a control)."""
    method: str
    """The method's name in the experiment (``gbh-10``...)."""
    trial: int
    """0-based trial index of this object."""
    seed: int
    """The scenario's seed, from (experiment seed, object, trial) alone: the same for every
    method, so every method sees the same start pose."""
    scenario_yaml: str
    """The whole scenario of the trial (``yaml_dump_typed``): base, method overrides, object,
    random pose and seed."""
    source_path: str
    """The base scenario file (relative paths in the scenario resolve against it)."""
    digest: str
    """sha256 of ``scenario_yaml``: a finished row counts on resume only if it matches."""
    commit: str
    """The git commit the experiment runs (``-dirty`` when tracked files had changes)."""
    replays: str
    """``failures``: record the trial in Meshcat and send back its replay if it fails;
    ``all``: whatever its outcome; ``none``: do not record."""
    object_tags: tuple[str, ...] = ()
    """The object's tags in its object set (``cup``, ``flat``...): the report groups by them."""
    protocol: str = "stable"
    """How the object was set down (``stable`` or ``natural``: the scenario's
    ``object.random_pose.rest``); rows carry it."""
    object_digest: str = ""
    """Which version of an object set's mesh entry the trial runs (its facts and its mesh
    file's bytes: :func:`gbh_drake.objects.sets.object_digest`; the scenario names only the
    manifest and the entry); "" for a built-in object. Rows carry it when it is not ""."""

    @property
    def key(self) -> tuple[str, str, int, str]:
        """(object, method, trial, protocol), as :func:`gbh_drake.experiment.rows.row_key`."""
        return (self.object, self.method, self.trial, self.protocol)

    def differs(self, row: dict) -> str:
        """What of this trial ``row`` (a row of the same key) was not made with: ``scenario``
        (its ``scenario_digest``), ``object`` (its ``object_digest``: the object set's entry or
        mesh file changed since; a row without one, written before rows carried it, is not
        judged by it), or "" (neither: the row is this trial's)."""
        if row.get("scenario_digest") != self.digest:
            return "scenario"
        if row.get("object_digest", self.object_digest) != self.object_digest:
            return "object"
        return ""


@dataclass
class TrialResult:
    """A worker's answer: the row (JSON-ready) and the replay's HTML (failed trials only)."""

    row: dict
    replay_html: str | None = None
