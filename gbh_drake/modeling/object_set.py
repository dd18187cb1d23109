"""Drake models of the whole object set: ``models/objects/<name>/<name>.{sdf,obj}`` + ground truth."""

from __future__ import annotations

from pathlib import Path

import yaml

from gbh_drake import IN_CHECKOUT, MODELS_DIR
from gbh_drake.modeling.object_sdf import ObjectModelFiles, write_object_model
from gbh_drake.objects import list_objects, make_object
from gbh_drake.objects.export import ground_truth

#: ``gbh objects build``'s folder: the repository's models/objects/ (Drake's package ``gbh_drake``),
#: or ./models/objects outside a checkout (never into an installed package).
OBJECT_MODELS_DIR = MODELS_DIR / "objects" if IN_CHECKOUT else Path("models") / "objects"


def build_object_models(out_dir: Path = OBJECT_MODELS_DIR,
                        names: list[str] | None = None) -> list[ObjectModelFiles]:
    """Writes a Drake model (SDF + OBJ) and ``ground_truth.yaml`` for each object (or ``names``)."""
    models = []
    for name in names or list_objects():
        spec = make_object(name)
        folder = Path(out_dir) / spec.name
        model = write_object_model(spec.mesh, spec.name, folder, density=spec.density, rgba=spec.rgba)
        with open(folder / "ground_truth.yaml", "w") as f:
            yaml.safe_dump(ground_truth(spec), f, sort_keys=False)
        models.append(model)
    return models


#: The columns of ``gbh objects list`` (and its --csv/--json), in order.
COLUMNS = ("name", "size_cm", "mass_g", "watertight", "control", "tags", "hangable_parts",
           "natural_rest", "source", "warnings", "error")
#: The header of ``gbh objects list``'s text (:func:`describe_lines`).
HEADER = f"{'object':24s} {'size x, y, z':>24s} {'mass':>9s}   hangable parts (ground truth)"


def describe_set(manifest: Path | None = None) -> list[dict]:
    """One row per object of the set at ``manifest`` (None: the built-in set), as the station
    would load it: name, size (cm: x, y, z in its frame O), mass (g), watertight, control,
    tags, ground-truth parts ("name (kind, clear diameter mm)"; "unknown" when a mesh entry
    declares none), natural rest, where it comes from and the import's warnings; ``error``:
    why the object cannot be used (the one-line message of its
    :class:`~gbh_drake.objects.sets.ObjectSetError`: a mesh not found or not a mesh, a size
    that cannot be simulated), its other facts then None, or ""."""
    from gbh_drake import SCENARIOS_DIR
    from gbh_drake.modeling.object_asset import load_object_asset
    from gbh_drake.modeling.object_config import ObjectConfig
    from gbh_drake.objects.sets import ObjectSetError, load_object_set

    path = (Path(manifest) if manifest else SCENARIOS_DIR / "object_sets" / "own.yaml").resolve()
    object_set = load_object_set(path)
    rows = []
    for name in object_set.names:
        try:
            obj = object_set.object(name)
            asset = load_object_asset(ObjectConfig(set=str(path), name=name), path.parent)
        except ObjectSetError as e:
            entry = object_set.entry(name)
            rows.append({"name": name, "size_cm": None, "mass_g": None, "watertight": None,
                         "control": bool(entry.control), "tags": list(entry.tags),
                         "hangable_parts": None, "natural_rest": None, "source": None,
                         "warnings": [], "error": str(e)})
            continue
        size = (asset.mesh.bounds[1] - asset.mesh.bounds[0]) * 100
        if asset.hangable_parts:
            parts = ", ".join(f"{p.name} ({p.kind}, {p.clear_diameter * 1000:.1f} mm)"
                              for p in asset.hangable_parts)
        else:
            parts = "none (control)" if obj.is_control else ("none" if obj.builtin else "unknown")
        rows.append({
            "name": name, "size_cm": [round(float(v), 1) for v in size],
            "mass_g": round(asset.mass * 1000.0, 1), "watertight": bool(asset.mesh.is_watertight),
            "control": bool(obj.is_control), "tags": list(obj.tags), "hangable_parts": parts,
            "natural_rest": asset.natural_rest.reason if asset.natural_rest else "",
            "source": asset.source, "warnings": list(asset.warnings), "error": ""})
    return rows


def describe_lines(rows: list[dict]) -> list[str]:
    """``gbh objects list``'s text: the :data:`HEADER`, then one line per object (name, size,
    mass, parts; ``refused:`` and why for an object that cannot be used), each object's
    warnings indented below it."""
    lines = [HEADER]
    for r in rows:
        if r["error"]:
            lines.append(f"{r['name']:24s} refused: {r['error']}")
            continue
        x, y, z = r["size_cm"]
        flag = "" if r["watertight"] else "  (not watertight)"
        lines.append(f"{r['name']:24s} {x:5.1f} x {y:5.1f} x {z:5.1f} cm {r['mass_g']:7.0f} g   "
                     f"{r['hangable_parts']}{flag}")
        lines += [f"    warning: {w}" for w in r["warnings"]]
    return lines


def describe_object_set() -> list[str]:
    """One line per object of the built-in set: name, size (cm), mass (g), hangable parts."""
    return describe_lines(describe_set())
