"""The grasps document: a :class:`~gbh_drake.scan_grasps.result.GraspsResult` as JSON or YAML,
versioned (``schema_version``) and described by a JSON Schema (:data:`JSON_SCHEMA`) whose field
descriptions are the reference (``docs/grasps_schema.md`` is generated from them:
:func:`schema_markdown`).

Frames: every pose is X_BF, frame F in the robot's base frame B (Franka's ``panda_link0``),
written as ``{matrix (4 rows), translation (m), quaternion_wxyz}``; every point and direction
is in B. Lengths are metres; angles are degrees where a field's name ends in ``_deg``.
Numbers that are not defined (a closed loop's beta) are ``null``.
"""

from __future__ import annotations

import json

import numpy as np

from gbh_drake.core.gripper import HOOK_GRIPPER, X_link8_G, p_G_hook
from gbh_drake.scan_grasps.poses import pose_entry
from gbh_drake.scan_grasps.result import Grasp, GraspsResult

SCHEMA_NAME = "gbh_drake/grasps"
#: Raised when a field changes meaning or goes away; new optional fields keep the number.
SCHEMA_VERSION = 1
#: The frame every pose is in.
FRAME_B = ("B: the robot's base frame, Franka's panda_link0 (in the simulation the world W: "
           "the default directives weld panda_link0 at W's origin); z up")


def document(result: GraspsResult) -> dict:
    """The document of ``result`` (plain JSON types)."""
    from gbh_drake import __version__
    from gbh_drake.outputs import plain

    params = result.params
    t = result.table
    g = HOOK_GRIPPER
    X_G_T = np.eye(4)
    X_G_T[:3, 3] = p_G_hook(g)
    doc = {
        "schema": SCHEMA_NAME,
        "schema_version": SCHEMA_VERSION,
        "gbh_drake_version": __version__,
        "frame": FRAME_B,
        "units": {"length": "m", "angle": "deg (fields ending in _deg)",
                  "pose": "X_BF: frame F in B; matrix rows, translation m, quaternion w x y z"},
        "input": {"kind": result.input_kind, "path": result.input_path,
                  "free_space": result.free_space, **result.extra,
                  "table": {"normal": list(t.normal_W), "height": t.height,
                            "source": result.table_source},
                  "notes": result.notes, "warnings": result.warnings},
        "gripper": {"X_link8_G": pose_entry(X_link8_G(g)), "X_G_T": pose_entry(X_G_T),
                    "q_open": g.q_open, "q_closed": g.q_closed,
                    "width_open": 2 * g.q_open, "width_closed": 2 * g.q_closed,
                    "finger_length": g.finger_length, "bar_length": g.bar_length,
                    "rod_width": g.rod_width},
        "gbh": {"preset": params.preset, "seed": result.seed,
                "params": _params(params)},
        "n_candidates": result.n_candidates,
        "structures": [{"index": i, "c": s.c, "v": s.v, "a": s.a, "m": s.m,
                        "clearance": s.clearance, "n_rays": s.n_rays}
                       for i, s in enumerate(result.structures)],
        "grasps": [_grasp(x) for x in result.grasps],
        "refused": [_grasp(x) for x in result.refused],
        "none": None if result.none is None else {
            "outcome": result.none.outcome, "message": result.none.message,
            "rejected_by": result.none.rejected_by, "closest": result.none.closest},
        "hangability": _hangability(result.hangability),
        "timings": result.timings,
    }
    return plain(_lists(doc))


def _params(params) -> dict:
    import dataclasses

    return {f.name: getattr(params, f.name) for f in dataclasses.fields(params)}


def _grasp(x: Grasp) -> dict:
    w = x.waypoints
    return {"rank": x.rank, "kind": x.kind, "score": x.score, "terms": x.terms,
            "structure": x.structure, "turn_deg": x.turn_deg,
            "X_BG": pose_entry(w.grasp), "X_B_link8": _flange(w.grasp),
            "jaw": {"q_open": w.q_open, "q_closed": w.q_closed, "width_open": 2 * w.q_open,
                    "width_closed": 2 * w.q_closed},
            "pre_grasp": {"X_BG": pose_entry(w.pre_grasp), "X_B_link8": _flange(w.pre_grasp)},
            "closed": {"X_BG": pose_entry(w.closed), "X_B_link8": _flange(w.closed)},
            "lift": {"height": w.lift_height, "X_BG": pose_entry(w.lift),
                     "X_B_link8": _flange(w.lift)},
            "checks": x.checks}


def _flange(X_BG: np.ndarray) -> dict:
    from gbh_drake.core.gripper import X_B_link8

    return pose_entry(X_B_link8(X_BG))


def _hangability(report) -> dict | None:
    if report is None:
        return None
    return {"samples": report.samples, "contact_candidates": report.contact_candidates,
            "contact_angle_deg": report.contact_angle_deg,
            "best_contact_angle_deg": report.best_contact_angle_deg,
            "clusters": report.clusters, "merged": report.merged, "positions": report.positions,
            "exit_proof": report.exit_proof, "structures": report.structures,
            "refused_by": report.refused_by(), "summary": report.summary(),
            "refused": [{"c": r.c, "clearance": r.clearance, "rule": r.rule, "v": r.v, "m": r.m}
                        for r in report.refused]}


def _lists(value):
    """numpy arrays as lists, recursively."""
    if isinstance(value, dict):
        return {k: _lists(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_lists(v) for v in value]
    if isinstance(value, np.ndarray):
        return value.tolist()
    return value


def to_json(doc: dict) -> str:
    return json.dumps(doc, indent=1, allow_nan=False) + "\n"


def to_yaml(doc: dict) -> str:
    import yaml

    return yaml.safe_dump(doc, sort_keys=False, default_flow_style=None, width=100)


# ---- the JSON Schema ------------------------------------------------------------------------


def _num(description: str) -> dict:
    return {"type": "number", "description": description}


def _maybe_num(description: str) -> dict:
    return {"type": ["number", "null"], "description": description}


def _vec(n: int, description: str) -> dict:
    return {"type": "array", "items": {"type": "number"}, "minItems": n, "maxItems": n,
            "description": description}


def _obj(description: str, properties: dict, required: list[str] | None = None,
         extra: bool = False) -> dict:
    return {"type": "object", "description": description, "properties": properties,
            "required": list(properties) if required is None else required,
            "additionalProperties": extra}


POSE = _obj("a pose X_PF: frame F in its parent P (B, unless the name says: X_link8_G is in "
            "panda_link8, X_G_T in G)", {
    "matrix": {"type": "array", "minItems": 4, "maxItems": 4,
               "items": _vec(4, "a row"), "description": "4x4 homogeneous matrix, by rows"},
    "translation": _vec(3, "m: the origin of F in P"),
    "quaternion_wxyz": _vec(4, "the rotation R_PF as a unit quaternion w, x, y, z (w >= 0)"),
})


def _pose(description: str) -> dict:
    return {**POSE, "description": description}


def _pair(description: str) -> dict:
    return _obj(description, {"X_BG": _pose("the gripper frame G"),
                              "X_B_link8": _pose("the flange panda_link8")})


GRASP = _obj("one grasp of the hook gripper", {
    "rank": {"type": "integer", "minimum": 0,
             "description": "1 for the best, in the order to try them; 0 in `refused`"},
    "kind": {"enum": ["parallel", "vertical"],
             "description": "parallel: the bar along the hole's axis, closes in place; "
                            "vertical: the straight rod in the hole, closes about it (the "
                            "hand moves along +y_G as the fingers close)"},
    "score": _num("S_total = m S_beta S_alpha, in [0, 1]"),
    "terms": _obj("the score's terms", {
        "m": _num("fraction of rays round the hole that hit: 1 a closed loop"),
        "s_alpha": _num("exp(-alpha^2 / gamma_alpha)"),
        "s_beta": _num("exp(-beta^2 / gamma_beta); 1 for a closed loop"),
        "alpha_deg": _num("deg: the approach +z_G from straight down"),
        "beta_deg": _maybe_num("deg: the opening's direction from the held material's side; "
                               "null for a closed loop")}),
    "structure": {"type": "integer", "description": "index in `structures` of the hole it "
                                                     "hooks"},
    "turn_deg": _num("deg: the approach turned from the paper's pose"),
    "X_BG": _pose("the open gripper's frame G at the grasp (origin: the palm's centre; +z_G "
                  "the approach toward the fingertips; +y_G the closing axis, from the L rod "
                  "to the straight rod)"),
    "X_B_link8": _pose("the flange panda_link8 at the grasp: X_BG X_link8_G^-1"),
    "jaw": _obj("the fingers", {
        "q_open": _num("m: each finger's joint position at the grasp"),
        "q_closed": _num("m: ... closed (the bar's tip on the straight rod: the loop closed)"),
        "width_open": _num("m: Franka's gripper width open (2 q_open)"),
        "width_closed": _num("m: ... closed (2 q_closed); command it as the stop, with a "
                             "grasp force")}),
    "pre_grasp": _pair("the open gripper approach_distance (0.10 m) back along -z_G: go there "
                       "first, then straight along +z_G to the grasp"),
    "closed": _pair("where G is once closed (a vertical grasp moves by the fingers' travel "
                    "along +y_G)"),
    "lift": _obj("the closed gripper lifted along the table's normal", {
        "height": _num("m: how far it rises (the object, hanging from the loop and turned any "
                       "way, clears the table by lift_clearance 0.05 m; 0.10-0.40 m)"),
        "X_BG": _pose("G lifted"), "X_B_link8": _pose("the flange lifted")}),
    "checks": _obj("the collision rules' counts", {
        "n_collisions": {"type": "integer", "description": "N_c: object points inside the open "
                                                           "gripper (< p_c)"},
        "n_sweep_collisions": {"type": "integer", "description": "object points (or unseen "
                                                                 "space) the closing sweeps"},
        "ground_distance": _maybe_num("m: the gripper's lowest point above the table, open, "
                                      "closing and closed")}),
})

STRUCTURE = _obj("a hanging structure (paper Sec. 2.2)", {
    "index": {"type": "integer", "minimum": 0, "description": "its index"},
    "c": _vec(3, "m: the hanging position (the hole's centre)"),
    "v": _vec(3, "the hole's axis (unit; sign arbitrary)"),
    "a": _vec(3, "the opening's mean direction (unit); zeros for a closed loop"),
    "m": _num("fraction of the ray plane's rays that hit (1: closed)"),
    "clearance": _num("m: from c to the surface"),
    "n_rays": {"type": "integer", "description": "rays cast round c"},
})

HANGABILITY = _obj("what the hangability detector saw (core.results.HangabilityReport)", {
    "samples": {"type": "integer", "description": "surface samples"},
    "contact_candidates": {"type": "integer", "description": "samples whose normal points to "
                                                             "the centre of mass within "
                                                             "contact_angle_deg"},
    "contact_angle_deg": _num("deg: that angle"),
    "best_contact_angle_deg": _maybe_num("deg: the nearest any sample came"),
    "clusters": {"type": "integer", "description": "clusters of contact candidates"},
    "merged": {"type": "integer", "description": "hanging positions merged into another"},
    "positions": {"type": "integer", "description": "hanging positions whose hole was tested"},
    "exit_proof": {"type": "boolean", "description": "whether the exit proof ran (free space)"},
    "structures": {"type": "integer", "description": "structures kept"},
    "refused_by": {"type": "object", "description": "positions each rule refused: too small, "
                                                    "not a through-hole, exit proof",
                   "additionalProperties": {"type": "integer"}},
    "summary": {"type": "string", "description": "the same in words"},
    "refused": {"type": "array", "description": "each refused position", "items": _obj(
        "a refused hanging position", {
            "c": _vec(3, "m"), "clearance": _num("m"),
            "rule": {"enum": ["too small", "not a through-hole", "exit proof"],
                     "description": "the rule that refused it"},
            "v": {"type": ["array", "null"], "items": {"type": "number"},
                  "description": "the hole's axis (null if refused before it was searched)"},
            "m": _maybe_num("fraction of rays that hit (null before the axis was searched)")})},
})

JSON_SCHEMA = _obj(f"{SCHEMA_NAME}, version {SCHEMA_VERSION}: ranked grasps of the hook "
                   "gripper for one scanned object, in the robot's base frame B", {
    "schema": {"const": SCHEMA_NAME, "description": "what this document is"},
    "schema_version": {"const": SCHEMA_VERSION, "description": "the version of this schema"},
    "gbh_drake_version": {"type": "string", "description": "the gbh_drake that wrote it"},
    "frame": {"type": "string", "description": "the frame of every pose, point and direction"},
    "units": {"type": "object", "description": "units, in words"},
    "input": _obj("what was scanned", {
        "kind": {"enum": ["mesh", "point_cloud", "depth_images", "simulation"],
                 "description": "the input's kind (`simulation`: written by gbh run)"},
        "path": {"type": "string", "description": "the input file or views.yaml"},
        "free_space": {"type": "boolean", "description": "whether the scan came with what the "
                                                         "cameras saw free (the exit proof "
                                                         "needs it: `hangability.exit_proof` "
                                                         "says whether it ran)"},
        "table": _obj("GbH's supporting surface: normal . p = height", {
            "normal": _vec(3, "unit, up"), "height": _num("m"),
            "source": {"enum": ["given", "fitted", "verified", "assumed", "lowest point"],
                       "description": "where it came from"}}),
        "notes": {"type": "array", "items": {"type": "string"},
                  "description": "what the input lacks and what that means"},
        "warnings": {"type": "array", "items": {"type": "string"},
                     "description": "what may be wrong with the scan"},
        "scenario": {"type": "string", "description": "gbh run: the scenario file"},
        "seed": {"type": "integer", "description": "gbh run: the scenario's seed"},
        "method": {"type": "string", "description": "gbh run: the grasp method"},
        "executed_rank": {"type": "integer", "description": "gbh run: the rank of the grasp "
                                                            "executed (0: none)"},
    }, required=["kind", "path", "free_space", "table", "notes", "warnings"]),
    "gripper": _obj("the hook gripper on a Franka's flange, as the station mounts it", {
        "X_link8_G": _pose("G in the flange frame panda_link8 (a -45 deg turn about z, then "
                           "0.0584 m along z)"),
        "X_G_T": _pose("the hook point T (the TCP: the bar's middle, between the rods) in G"),
        "q_open": _num("m"), "q_closed": _num("m"), "width_open": _num("m"),
        "width_closed": _num("m"), "finger_length": _num("m: l_f"),
        "bar_length": _num("m: l_h"), "rod_width": _num("m")}),
    "gbh": _obj("how GbH ran", {
        "preset": {"type": "string", "description": "\"\" (gbh_drake's) or \"paper\""},
        "seed": {"type": "integer", "description": "the surface sampler's seed"},
        "params": {"type": "object", "description": "every GbhParams field"}}),
    "n_candidates": {"type": "integer", "description": "grasps synthesised and checked"},
    "structures": {"type": "array", "items": STRUCTURE, "description": "hanging structures, "
                                                                        "best first"},
    "grasps": {"type": "array", "items": GRASP, "description": "the ranked grasps, best first "
                                                              "(at most top_k, distinct)"},
    "refused": {"type": "array", "items": GRASP, "description": "the refused candidates that "
                                                               "came closest to passing"},
    "none": {"description": "null when there are grasps; else why not", "oneOf": [
        {"type": "null"},
        _obj("why there is no grasp", {
            "outcome": {"enum": ["empty_scan", "no_hangable_structure", "no_grasp_found"],
                        "description": "as the trial's verdict names it"},
            "message": {"type": "string", "description": "the same in words"},
            "rejected_by": {"type": "object", "additionalProperties": {"type": "integer"},
                            "description": "no_grasp_found: candidates each collision rule "
                                           "removed, in order"},
            "closest": {"type": "string", "description": "how near the closest came"}})]},
    "hangability": {"description": "what the detector saw (null when it did not run)",
                    "oneOf": [{"type": "null"}, HANGABILITY]},
    "timings": {"type": "object", "additionalProperties": {"type": "number"},
                "description": "wall seconds by step"},
})


def schema_markdown() -> str:
    """The fields of :data:`JSON_SCHEMA` as a Markdown table (``docs/grasps_schema.md``): a
    pose's three fields are given once (``pose``), a list of grasps once (``grasps[]``)."""
    rows = ["| field | type | meaning |", "|---|---|---|"]
    seen: dict[int, str] = {id(POSE["properties"]): "pose"}

    def kind_of(sub: dict) -> str:
        if "enum" in sub:
            return " \\| ".join(f"`{v}`" for v in sub["enum"])
        if "const" in sub:
            return f"`{sub['const']}`"
        if "oneOf" in sub:
            return "null \\| object"
        if sub.get("properties") is POSE["properties"]:
            return "pose"
        kind = sub.get("type", "")
        return " \\| ".join(kind) if isinstance(kind, list) else kind

    def walk(schema: dict, path: str) -> None:
        for name, sub in schema.get("properties", {}).items():
            here = f"{path}.{name}" if path else name
            items = sub.get("items") if sub.get("type") == "array" else None
            also = ""
            if isinstance(items, dict) and id(items) in seen:
                also = f" (each as `{seen[id(items)]}`)"
            rows.append(f"| `{here}` | {kind_of(sub)} | {sub.get('description', '')}{also} |")
            for option in sub.get("oneOf", []):
                walk(option, here)
            if id(sub.get("properties")) not in seen:
                walk(sub, here)
            if isinstance(items, dict) and id(items) not in seen:
                seen[id(items)] = f"{here}[]"
                walk(items, f"{here}[]")

    walk(JSON_SCHEMA, "")
    walk(POSE, "pose")
    return "\n".join(rows) + "\n"
