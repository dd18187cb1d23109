"""Plausibility warnings: size (with the unit hint), mass, solid-filled meshes."""

import numpy as np
import pytest
import trimesh
from mesh_shapes import filled_mug

from gbh_drake.objects import mass_properties_for, plausibility_warnings
from gbh_drake.objects import plausibility as P

MUG = filled_mug()  # 13 cm, solid-filled


def _scaled(mesh, s):
    m = mesh.copy()
    m.apply_scale(s)
    return m


def test_mesh_in_centimetres_warns_with_the_scale_hint():
    mug_cm = _scaled(MUG, 100.0)
    mass = mass_properties_for(mug_cm, density=600.0).mass
    warnings = plausibility_warnings(mug_cm, mass, "cup.obj", density=600.0)
    assert warnings[0] == ("cup.obj: largest extent 13.3 m is implausible for a hand-held object "
                           "(1 cm - 1 m): looks like centimetres: give scale: 0.01 (then 13.3 cm)")
    assert warnings[1].startswith("cup.obj: mass 3.07e+05 kg = density 600 kg/m^3 x volume ")
    assert warnings[1].endswith("is implausibly heavy for a hand-held object (5 g - 5 kg): fix "
                                "scale first, then give mass (kg) directly")
    assert len(warnings) == 2  # no solid-filled warning before the size is right


@pytest.mark.parametrize("factor, scale, hint", [  # the mug is 13.25 cm
    (1000.0, 1.0, "looks like millimetres: give scale: 0.001 (then 13.3 cm)"),
    (100.0, 1.0, "looks like centimetres: give scale: 0.01 (then 13.3 cm)"),
    (1000.0, 0.1, "looks like millimetres: give scale: 0.0001 (then 13.3 cm)"),
    (39.37, 1.0, "looks like inches: give scale: 0.0254 (then 13.2 cm)"),
    (0.01, 1.0, "looks 100x too small: give scale: 100 (then 13.3 cm)"),
    (0.001, 0.001, "looks 1000x too small: give scale: 1 (then 13.3 cm)"),
    (1e-4, 1.0, "looks 1000x too small: give scale: 1000 (then 1.3"),
    (1e-6, 1.0, "check the file's unit and give scale (now 1)"),
    (1e5, 1.0, "check the file's unit and give scale (now 1)"),
])
def test_unit_hints(factor, scale, hint):
    mesh = _scaled(MUG, factor)
    (warning,) = P.extent_warnings(mesh, scale=scale)
    assert hint in warning, warning


def test_plausible_sizes_say_nothing():
    for s in (0.1, 1.0, 5.0):  # 1.3 cm, 13 cm, 66 cm
        assert P.extent_warnings(_scaled(MUG, s)) == []


def test_solid_filled_mug_at_density_600_warns():
    mass = mass_properties_for(MUG, density=600.0).mass
    (warning,) = plausibility_warnings(MUG, mass, "scan.ply", density=600.0)
    assert warning.startswith("scan.ply: the mesh is solid-filled (volume 82% of its convex hull, "
                              "mean thickness 2V/A 26 mm), so density 600 kg/m^3 gives the mass "
                              "of a solid block, 307 g; a hollow object of this shape with 4 mm "
                              "walls would weigh ~")
    assert warning.endswith("if the real object is hollow (a mug, a box, a bottle), give mass "
                            "(kg) directly")
    shell = float(warning.split("would weigh ~")[1].split(" g")[0])
    assert 60 < shell < 120  # several times lighter than the solid block


def test_mass_given_directly_silences_the_solid_filled_warning():
    assert plausibility_warnings(MUG, 0.33, "scan.ply") == []


def test_the_object_set_is_plausible(specs):
    """Modelled walls: no warning at the objects' own densities; the solid controls (ball,
    bottle, box, can) are flagged as solid-filled, as the rule says, since only a density is
    given for them."""
    for name, spec in specs.items():
        props = mass_properties_for(spec.mesh, density=spec.density)
        warnings = plausibility_warnings(spec.mesh, props.mass, name, density=spec.density)
        solid = name in ("ball", "bottle", "box", "can", "spray_bottle")
        assert len(warnings) == int(solid), (name, warnings)
        assert plausibility_warnings(spec.mesh, props.mass, name) == []


@pytest.mark.parametrize("mass, density, message", [
    (0.002, 600.0, "mass 2 g = density 600 kg/m^3 x volume 3.333 cm^3 is implausibly light for a "
                   "hand-held object (5 g - 5 kg): give mass (kg) directly or another density"),
    (12.0, None, "mass 12 kg is implausibly heavy for a hand-held object (5 g - 5 kg): check mass"),
    (0.001, None, "mass 1 g is implausibly light"),
])
def test_mass_range(mass, density, message):
    box = trimesh.creation.box((0.05, 0.05, 0.05))
    warnings = plausibility_warnings(box, mass, "x.stl", density=density)
    assert any(w.startswith(f"x.stl: {message}") for w in warnings), warnings


def test_solid_fill_rule():
    cube = trimesh.creation.box((0.1, 0.1, 0.1))
    fill, thickness = P.solid_fill(cube)
    assert fill == pytest.approx(1.0) and thickness == pytest.approx(0.1 / 3)
    thin = trimesh.creation.box((0.1, 0.1, 0.015))  # 2V/A = 1.15 cm: still solid
    assert P.solid_fill(thin) is not None
    plate = trimesh.creation.box((0.1, 0.1, 0.008))  # 2V/A = 7.4 mm: a wall, not a block
    assert P.solid_fill(plate) is None
    ring = trimesh.creation.annulus(0.04, 0.05, 0.1)  # a tube: fill 36 %
    assert P.solid_fill(ring) is None
    assert np.isfinite(P.SOLID_MIN_FILL) and P.SOLID_MIN_THICKNESS == 0.01


@pytest.mark.parametrize("factor, refused", [
    (1000.0, "largest extent 133 m is larger than the workspace (> 1.2 m): looks like "
             "millimetres: give scale: 0.001 (then 13.3 cm)"),
    (10.0, "largest extent 1.33 m is larger than the workspace (> 1.2 m): looks like "
           "inches: give scale: 0.0254 (then 3.37 cm)"),
    (8.0, None),  # 1.06 m: implausible (a warning), not impossible
    (0.05, None),  # 6.6 mm: a warning
    (0.03, "largest extent 3.98 mm is smaller than the scan and the gripper can sense "
           "(< 5 mm): looks 100x too small: give scale: 100 (then 39.8 cm)"),
])
def test_absurd_sizes_are_refused_with_the_scale_hint(factor, refused):
    assert P.size_refusal(_scaled(MUG, factor)) == refused
