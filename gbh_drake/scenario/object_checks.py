"""The object to pick: a known name of the object set (with a suggestion for a typo), at a size
that can be simulated, or a mesh file the mesh import accepts. The object set is imported on
demand (its generators are heavy). A random pose with ``rest: natural`` needs a named object
with a declared natural rest."""

import difflib
import os
from pathlib import Path

import numpy as np

from gbh_drake.core.ranges import FieldError

#: Largest extent (m) a scaled named object may have.
NAMED_SIZE = (0.01, 2.0)
#: kg: the object's mass, named or mesh, from ``object.mass`` or its density, is at least 1 g
#: (lighter than a paper clip: not a hand-held object, and its contact at the plant's step was
#: never measured) and at most the Franka's payload
#: (:data:`gbh_drake.objects.plausibility.PAYLOAD`).
MIN_MASS = 0.001


def check_object(scenario) -> None:
    obj = scenario.object
    if obj.set:
        _check_set_object(scenario)
        return
    if obj.mesh:
        if "\0" in obj.mesh:
            raise FieldError(("object", "mesh"), "holds a NUL character")
        path = scenario.resolve(obj.mesh)
        if not path.is_file():
            what = "is a folder" if path.is_dir() else "file not found"
            raise FieldError(("object", "mesh"), f"{what}: {path}")
        from gbh_drake.objects import MeshImportError, load_mesh_object
        from gbh_drake.objects.plausibility import size_refusal

        try:
            loaded = load_mesh_object(path, scale=obj.scale, density=obj.density or None,
                                      mass=obj.mass or None, orientation=obj.orientation)
        except MeshImportError as e:
            raise FieldError(("object", "mesh"), str(e)) from None
        refusal = size_refusal(loaded.mesh, obj.scale)
        if refusal:  # refused before anything is simulated (a mm file read as m: 100 m)
            raise FieldError(("object", "scale"), f"{path}: {refusal}")
        _check_mass(obj, float(loaded.mass_properties.mass), "the mesh", light=False)
        if _natural(obj):
            raise FieldError(("object", "random_pose", "rest"),
                             "natural is the rest declared for each object of the set; a mesh "
                             "file (object.mesh) has none: use rest: stable (its stable "
                             "resting poses), or stable: false (as object.orientation places it)")
        return
    if obj.orientation != "keep":
        raise FieldError(("object", "orientation"), "applies to mesh files (object.mesh); the "
                                                    "named objects stand as designed")
    if not obj.name:
        raise FieldError(("object",), "give a named object (object.name) or a mesh file "
                                      "(object.mesh)")
    from gbh_drake.objects import list_objects  # the object set (its generators) on demand

    known = list_objects()
    if obj.name not in known:
        close = difflib.get_close_matches(obj.name, known, n=1)
        hint = f"did you mean {close[0]!r}? " if close else ""
        raise FieldError(("object", "name"), f"unknown object {obj.name!r} ({hint}known: "
                                             f"{', '.join(known)}; or give object.mesh)")
    if _natural(obj):
        from gbh_drake.objects.catalog import natural_rest

        if natural_rest(obj.name) is None:
            raise FieldError(("object", "random_pose", "rest"),
                             f"natural: {obj.name} has no natural rest declared (register it "
                             "with rest=... in the object set); use rest: stable")
    size = _named_extent(obj.name) * obj.scale
    if not NAMED_SIZE[0] <= size <= NAMED_SIZE[1]:
        raise FieldError(("object", "scale"), f"makes {obj.name} {size * 1000:.3g} mm across; "
                                              f"objects of {NAMED_SIZE[0] * 100:g} cm to "
                                              f"{NAMED_SIZE[1]:g} m can be simulated")
    _check_mass(obj, _named_mass(obj), obj.name)


def _check_set_object(scenario) -> None:
    """``object.set`` is a manifest that loads, ``object.name`` one of its objects, whose mesh
    is found, loads and has a size that can be simulated (as ``object.mesh``'s); ``rest:
    natural`` needs its declared rest. The manifest is named by its path made plain (an
    experiment's trial names it relative to the base scenario: ``../../x/set.yaml``)."""
    from gbh_drake.objects.sets import ObjectSetError, load_object_set

    obj = scenario.object
    path = Path(os.path.normpath(scenario.resolve(obj.set)))
    if not path.is_file():
        raise FieldError(("object", "set"), f"{'is a folder' if path.is_dir() else 'file not found'}"
                                            f": {path}")
    try:
        object_set = load_object_set(path)
        if obj.name not in object_set.names:
            close = difflib.get_close_matches(obj.name, object_set.names, n=1)
            hint = f"did you mean {close[0]!r}? " if close else ""
            raise FieldError(("object", "name"), f"{obj.name!r} is not an object of {path} "
                                                 f"({hint}it has: {', '.join(object_set.names)})")
        found = object_set.object(obj.name)
    except ObjectSetError as e:
        raise FieldError(("object", "set"), str(e)) from None
    entry = found.entry
    if found.builtin:
        if _natural(obj) and _builtin_rest(found.builtin) is None:
            raise FieldError(("object", "random_pose", "rest"), f"natural: {found.builtin} has "
                                                                "no natural rest declared")
        return
    if _natural(obj) and entry.rest is None:
        raise FieldError(("object", "random_pose", "rest"),
                         f"natural: {obj.name} of {path} has no natural rest (give the entry "
                         "rest: {as_given: true, reason: ...} or rpy_deg); use rest: stable")
    from gbh_drake.modeling.object_asset import load_object_asset

    try:  # (a mesh that cannot be imported, a size or a mass that cannot be simulated)
        load_object_asset(obj, scenario.directory)
    except ObjectSetError as e:
        raise FieldError(("object", "set"), str(e)) from None


def _builtin_rest(name: str):
    from gbh_drake.objects.catalog import natural_rest

    return natural_rest(name)


def _natural(obj) -> bool:
    return obj.random_pose is not None and obj.random_pose.rest == "natural"


def _check_mass(obj, mass: float, what: str, *, light: bool = True) -> None:
    """Refuses a mass outside [:data:`MIN_MASS`, the payload] (with ``light`` False, only
    above it: a light mesh is warned about by the mesh import's plausibility checks), on the
    field that gave it."""
    from gbh_drake.objects.plausibility import PAYLOAD

    lo, hi = MIN_MASS, PAYLOAD
    if mass <= hi and (mass >= lo or not light):
        return
    if obj.mass > 0:
        field, how = "mass", ""
    elif obj.density > 0:
        field, how = "density", f" (density {obj.density:g} kg/m^3)"
    else:
        field, how = "scale", f" (scale {obj.scale:g} at its own density)"
    figure = f"{mass:.3g} kg" if mass >= 0.1 else f"{mass * 1000:.3g} g"
    if mass > hi:
        why = (f"above the Franka's payload ({hi:g} kg): give a lighter object.mass or "
               "object.density")
    else:
        why = (f"under {lo * 1000:g} g, not a hand-held object the simulation was measured "
               "with: give a larger object.mass or object.density (0: the object's own)")
    raise FieldError(("object", field), f"makes {what} weigh {figure}{how}, {why}")


def _named_mass(obj) -> float:
    """kg: the named object's mass as the station gives it (``mass``, else its density or
    ``density`` times its volume at ``scale``)."""
    if obj.mass > 0:
        return float(obj.mass)
    _, volume, density = _named_facts(obj.name)
    return float((obj.density or density) * volume * obj.scale ** 3)


def _named_extent(name: str) -> float:
    """Largest extent (m) of the object set's ``name`` at scale 1."""
    return _named_facts(name)[0]


_FACTS: dict[str, tuple[float, float, float]] = {}


def _named_facts(name: str) -> tuple[float, float, float]:
    """(largest extent m, volume m^3, density kg/m^3) of the object set's ``name`` at scale 1,
    from one build of it (cached per process: the set's generators are heavy)."""
    if name not in _FACTS:
        from gbh_drake.objects import make_object

        spec = make_object(name)
        bounds = spec.mesh.bounds
        _FACTS[name] = (float(np.max(bounds[1] - bounds[0])), float(spec.mesh.volume),
                        float(spec.density))
    return _FACTS[name]


def object_model_name(scenario) -> str:
    from gbh_drake.modeling.object_sdf import model_name

    return model_name(Path(scenario.object.mesh).stem if scenario.object.mesh
                      else scenario.object.name)
