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


def describe_object_set() -> list[str]:
    """One line per object: name, size (cm), mass (g), hangable parts."""
    lines = []
    for name in list_objects():
        spec = make_object(name)
        size = (spec.mesh.bounds[1] - spec.mesh.bounds[0]) * 100
        gt = ground_truth(spec)
        parts = ", ".join(f"{p.name} ({p.kind})" for p in spec.hangable_parts) or "none (control)"
        lines.append(f"{name:20s} {size[0]:5.1f} x {size[1]:5.1f} x {size[2]:5.1f} cm "
                     f"{gt['mass_kg'] * 1000:6.0f} g   {parts}")
    return lines
