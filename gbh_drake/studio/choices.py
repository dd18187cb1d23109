"""What the studio's controls choose, and the scenario it makes of them.

The studio's scenario is the file's (or the default) with one override on top, the very text
``gbh run --set`` takes (:func:`overrides`): the object, its pose, the number of views, the
grasp method, GbH's preset and the seed. The studio builds its trial from
``apply_overrides(base, overrides(...))``, so what it shows is what ``gbh run --set '<that
text>'`` runs, and it says the text.

The object's pose: x, y (m), the yaw (deg) and the rest: one of the object's stable resting
orientations by index (most probable first, :func:`gbh_drake.objects.stable_poses`; x, y are
where its frame O's origin goes, as in ``object.pose``), or ``drop`` (:data:`DROP`): a stable
orientation drawn by its probability from the seed, as a random drop would leave it (the
experiment's ``stable`` protocol: ``object.random_pose`` with x, y and the yaw fixed; x, y are
its footprint's centre then).
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from gbh_drake.modeling.object_config import ObjectConfig

#: The rest index that means "drawn by probability from the seed".
DROP = -1
#: GbH's presets as the studio offers them (``GbhParams.preset``): gbh_drake's defaults, the
#: paper's rules alone.
PRESETS = ("", "paper")


@dataclass(frozen=True)
class ObjectChoice:
    """One object the studio offers: how it is named on the page and its configuration (a
    built-in object's name, an object set's manifest and name, or a mesh file; paths
    absolute)."""

    label: str
    config: ObjectConfig


@dataclass
class Choices:
    """The controls' values."""

    object: int = 0
    """Index into the studio's objects."""
    x: float = 0.55
    y: float = 0.0
    """m: where O's origin goes on the table (W; for :data:`DROP`, the footprint's centre)."""
    yaw_deg: float = 0.0
    rest: int = DROP
    """The stable resting orientation's index (most probable first), or :data:`DROP`."""
    views: int = 10
    method: str = "gbh"
    preset: str = ""
    seed: int = 0


def object_choices(scenario, sets: list[str | Path] = (), meshes: list[str | Path] = ()
                   ) -> list[ObjectChoice]:
    """The objects the studio offers: the scenario's own first, then the built-in set, each
    object of the manifests ``sets``, then the mesh files ``meshes`` (in metres, their z up)."""
    from gbh_drake.objects.catalog import list_objects
    from gbh_drake.objects.sets import load_object_set

    own = _absolute(scenario.object, scenario)
    choices = [ObjectChoice(_label(own), own)]
    choices += [ObjectChoice(name, ObjectConfig(name=name)) for name in list_objects()
                if _label(own) != name]
    for path in sets:
        object_set = load_object_set(path)
        for name in object_set.names:
            config = ObjectConfig(set=str(Path(object_set.path).resolve()), name=name)
            choices.append(ObjectChoice(f"{object_set.name}/{name}", config))
    for path in meshes:
        path = Path(path).resolve()
        choices.append(ObjectChoice(f"{path.name}", ObjectConfig(name="", mesh=str(path))))
    return choices


def _absolute(config: ObjectConfig, scenario) -> ObjectConfig:
    """``config`` with its set or mesh path made absolute (as the scenario resolves it)."""
    import copy

    config = copy.deepcopy(config)
    if config.set:
        config.set = str(scenario.resolve(config.set))
    if config.mesh:
        config.mesh = str(scenario.resolve(config.mesh))
        config.name = ""
    return config


def _label(config: ObjectConfig) -> str:
    if config.mesh:
        return Path(config.mesh).name
    if config.set:
        return f"{Path(config.set).stem}/{config.name}"
    return config.name


def overrides(choice: ObjectChoice, choices: Choices, R_rest: np.ndarray | None = None) -> str:
    """The ``gbh run --set`` text of ``choices`` for the object ``choice`` (one line of YAML).
    ``R_rest`` (3, 3): the chosen stable orientation (None: :data:`DROP`)."""
    o = choice.config
    fields = {"name": o.name, "set": o.set, "mesh": o.mesh, "scale": o.scale,
              "orientation": o.orientation, "density": o.density, "mass": o.mass}
    text = ", ".join(f"{k}: {_yaml(v)}" for k, v in fields.items())
    if R_rest is None:
        pose = (f"random_pose: {{x: {_yaml([choices.x, choices.x])}, "
                f"y: {_yaml([choices.y, choices.y])}, "
                f"yaw_deg: {_yaml([choices.yaw_deg, choices.yaw_deg])}, rest: stable}}")
    else:
        from pydrake.math import RollPitchYaw, RotationMatrix

        R = _rz(np.radians(choices.yaw_deg)) @ np.asarray(R_rest, dtype=float)
        rpy = np.degrees(RollPitchYaw(RotationMatrix(R)).vector())
        pose = (f"pose: {{translation: {_yaml([choices.x, choices.y, 0.0])}, "
                f"rotation: !Rpy {{deg: {_yaml(rpy.tolist())}}}}}")
    return (f"{{seed: {int(choices.seed)}, grasp_method: {choices.method}, "
            f"scan: {{num_views: {int(choices.views)}}}, gbh: {{preset: {_yaml(choices.preset)}}}, "
            f"object: {{{text}, {pose}}}}}")


def scenario_for(base, choice: ObjectChoice, choices: Choices, R_rest=None):
    """The studio's scenario: ``base`` with :func:`overrides` on top, checked as ``gbh run
    --set`` checks it (a :class:`~gbh_drake.scenario.ScenarioError` says what is wrong)."""
    from gbh_drake.scenario.loader import apply_overrides

    return apply_overrides(base, overrides(choice, choices, R_rest), "gbh studio")


def _rz(yaw: float) -> np.ndarray:
    c, s = np.cos(yaw), np.sin(yaw)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _yaml(value) -> str:
    """``value`` as YAML flow text (JSON is YAML; floats to 12 significant digits, below
    1e-12 as 0: a yaw of 30 deg is ``30.0``, not its rotation matrix's
    ``29.999999999999993``, a pitch ``0.0``, not ``-0.0``)."""
    if isinstance(value, float | np.floating):
        value = float(f"{float(value):.12g}")
        return repr(value if abs(value) >= 1e-12 else 0.0)
    if isinstance(value, list | tuple):
        return "[" + ", ".join(_yaml(v) for v in value) + "]"
    return json.dumps(value)
