"""What the report knows besides the rows: the paper's figures, the protocols in words, which
grasp methods go beyond the paper (their :class:`~gbh_drake.method_spec.MethodSpec`), and the
objects' tags (:func:`object_tags`, the one lookup the sections use)."""

from __future__ import annotations

from pathlib import Path

import pandas as pd

#: The paper's Table 1 (real robot, 15 objects x 5 trials): name -> (viewpoints, total, success).
PAPER_TABLE1 = {
    "GraspNet 1 view": (1, 75, 23),
    "GbH 1 view": (1, 75, 54),
    "GbH 10 views": (10, 75, 68),
}

#: Where the built-in objects' natural rests are declared.
BUILTIN_RESTS = "gbh_drake/objects/catalog.py"
#: What each protocol means, under its Table 1 (:func:`protocol_text`; ``{rests}``: where the
#: objects' natural rests are declared).
PROTOCOL_TEXT = {
    "stable": "Protocol `stable`: each object in one of its stable resting poses, drawn by its "
              "probability, with a random yaw and position.",
    "natural": "Protocol `natural`: each object in the rest a person would set it down in "
               "(declared per object, with its reason, in {rests}), with a random yaw and "
               "position; the paper's objects were set down by a person.",
}


#: Tags of the built-in objects, for rows that carry no ``object_tags`` (written before the
#: object sets had tags): the objects that lie flat (every resting pose: the bar cannot pass
#: under their material) and the cups that rest on their handle when lying on their side (the
#: trials issue 19 names, fixed before any number of its methods was seen).
FLAT_OBJECTS = ("clothes_hanger", "key_ring", "scissors", "tape_roll")
CUPS = ("mug_classic", "mug_large", "mug_square_handle", "pybullet_mug", "teacup")
#: The tag of an object the report has no facts about.
UNKNOWN = "unknown"


def beyond_paper(grasp_methods) -> list[bool]:
    """For each grasp method name: whether it goes beyond the paper's grasps (its spec's
    ``beyond_paper``; a name no spec has is not)."""
    from gbh_drake.method_spec import method_names, method_spec

    known = set(method_names())
    return [g in known and method_spec(g).beyond_paper for g in grasp_methods]


def protocol_text(protocol: str, object_set: str = "") -> str:
    """What ``protocol`` means, in a sentence (one the report does not know: said so).
    ``object_set``: the experiment's manifest, relative to the report's folder (its objects'
    rests are declared there), or "" (built-in objects alone: :data:`BUILTIN_RESTS`)."""
    rests = BUILTIN_RESTS if not object_set else \
        f"its object set, [{Path(object_set).name}]({object_set}) (a built-in object's in " \
        f"{BUILTIN_RESTS})"
    return PROTOCOL_TEXT.get(protocol, f"Protocol `{protocol}`: the report has no description "
                                       "of this protocol.").format(rests=rests)


def object_tags(frame_or_rows) -> dict[str, frozenset[str]]:
    """Each object's tags (``cup``, ``flat``, ``control``, ...), from the frame (or rows) of a
    report: the rows' ``object_tags`` where they carry them (the last row's), else the built-in
    lists (:data:`FLAT_OBJECTS`, :data:`CUPS`); ``control`` also where a row says
    ``is_control``. An object with neither (no tags in its rows, not built in, not a control,
    and no true hangable part in its records: ``true_parts`` 0 or missing) is
    :data:`UNKNOWN`."""
    from gbh_drake.experiment.report.columns import frame_of

    frame = frame_or_rows if isinstance(frame_or_rows, pd.DataFrame) else \
        frame_of(list(frame_or_rows))
    by_object = frame[["object", "object_tags", "is_control", "true_parts"]].groupby(
        "object", sort=False)
    carried = by_object.object_tags.last()  # (the last row's that has them)
    control = by_object.is_control.any()
    parts = by_object.true_parts.max()
    out = {}
    for obj in carried.index:
        tags = set(carried[obj]) if carried[obj] is not None else \
            {"flat"} if obj in FLAT_OBJECTS else {"cup"} if obj in CUPS else set()
        if control[obj]:
            tags.add("control")
        if carried[obj] is None and not tags and not (pd.notna(parts[obj]) and parts[obj] > 0):
            tags.add(UNKNOWN)
        out[obj] = frozenset(tags)
    return out


def tagged(frame: pd.DataFrame, tag: str) -> pd.Series:
    """Per row of ``frame``: whether its object has ``tag`` (:func:`object_tags`)."""
    tags = object_tags(frame)
    return frame.object.map(lambda o: tag in tags[o]).astype(bool)
