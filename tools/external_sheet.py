"""The contact sheet of an external object set: every object in its natural rest, ground truth drawn.

    python tools/external_sheet.py [scenarios/object_sets/external.yaml]
        [--out docs/objects/external_sheet.png]

Reads the manifest with PyYAML, takes each mesh from the fetch cache
(``python -m gbh_drake.objects.fetch_sets MANIFEST`` first), turns the file's frame F by the declared
rest, puts it on z = 0 (:func:`~gbh_drake.objects.placement.rest_on_table`, "keep") and moves
the hangable parts with it; rendering is :func:`gbh_drake.objects.contact_sheet.contact_sheet`
(red: closed loops, blue: open hooks, rod = hole axis). A stand-in for the object-set loader.
"""

from __future__ import annotations

import argparse
import logging
from pathlib import Path

import numpy as np
import yaml

from gbh_drake import REPO_ROOT
from gbh_drake.objects.contact_sheet import contact_sheet
from gbh_drake.objects.fetch import resolve
from gbh_drake.objects.mass import mass_properties_detailed
from gbh_drake.objects.mesh_io import load_mesh_file
from gbh_drake.objects.placement import rest_on_table
from gbh_drake.objects.spec import HangablePart, NaturalRest, ObjectSpec

COLOURS = {"cup": (0.85, 0.55, 0.35, 1.0), "ring": (0.55, 0.6, 0.85, 1.0),
           "flat": (0.5, 0.75, 0.55, 1.0), "container": (0.8, 0.75, 0.45, 1.0)}
CONTROL = (0.6, 0.6, 0.62, 1.0)
OTHER = (0.7, 0.55, 0.75, 1.0)


def spec_in_rest(obj: dict, cache_dir=None) -> ObjectSpec:
    """One manifest entry as an ObjectSpec in frame O: the declared rest, on z = 0."""
    mesh_F = load_mesh_file(resolve(obj["mesh"], obj["source"], cache_dir), scale=obj["scale"])
    rest = obj["rest"]
    rpy = (0.0, 0.0, 0.0) if rest.get("as_given") is True else tuple(rest["rpy_deg"])
    X_RF = np.eye(4)
    X_RF[:3, :3] = NaturalRest(rpy, rest["reason"]).R
    placed = rest_on_table(mesh_F.copy().apply_transform(X_RF))
    X_OF = placed.X_OF @ X_RF
    parts = [HangablePart(p["name"], X_OF[:3, :3] @ np.asarray(p["center"], float) + X_OF[:3, 3],
                          X_OF[:3, :3] @ np.asarray(p["axis"], float), p["kind"],
                          p["clear_diameter"])
             for p in obj["hangable_parts"]]
    colour = CONTROL if obj["control"] else next(
        (COLOURS[t] for t in obj["tags"] if t in COLOURS), OTHER)
    density = obj["mass"] / mass_properties_detailed(placed.mesh, 1.0).mass
    return ObjectSpec(obj["name"], placed.mesh, density, parts, obj["control"], colour,
                      obj["description"])


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("manifest", nargs="?",
                        default=REPO_ROOT / "scenarios" / "object_sets" / "external.yaml")
    parser.add_argument("--out", default=REPO_ROOT / "docs" / "objects" / "external_sheet.png")
    parser.add_argument("--columns", type=int, default=6)
    parser.add_argument("--dpi", type=int, default=60)
    args = parser.parse_args(argv)
    logging.disable(logging.WARNING)  # the import's warnings are listed in the set's doc page
    data = yaml.safe_load(Path(args.manifest).read_text())
    specs = [spec_in_rest(obj) for obj in data["objects"]]
    title = (f"{data['name']} object set in its natural rests (red: closed loops, blue: open "
             f"hooks; rod = hole axis)")
    print(contact_sheet(args.out, columns=args.columns, specs=specs, title=title, dpi=args.dpi))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
