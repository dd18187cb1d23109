"""Shared builders: sweeps, vessels and hole measurement on shapes of known answer."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gbh_drake.objects import primitives as P
from gbh_drake.objects.catalog import make_object
from gbh_drake.objects.holes import fit_hole


def test_closed_sweep_is_a_torus():
    path = np.column_stack([P.arc((0, 0), 0.05, 0, 2 * np.pi, 65)[:-1], np.zeros(64)])
    ring = P.sweep(path, P.circle_section(0.01), (0, 0, 1), closed=True)
    mesh = P.to_trimesh(ring)
    assert mesh.is_watertight and (2 - mesh.euler_number) // 2 == 1
    assert mesh.volume == pytest.approx(2 * np.pi**2 * 0.05 * 0.01**2, rel=0.03)
    centre, clear = fit_hole(mesh, np.zeros(3), (0, 0, 1), search_radius=0.01)
    assert clear == pytest.approx(0.08, rel=0.01)
    np.testing.assert_allclose(centre, 0.0, atol=1e-3)


def test_vessel_shell_and_cavity():
    shell, cavity = P.vessel(np.array([(0, 0), (0.04, 0), (0.04, 0.1)]), 0.004)
    mesh = P.to_trimesh(shell)
    assert mesh.is_watertight and mesh.euler_number == 2
    inner = np.pi * 0.036**2 * 0.096
    assert mesh.volume == pytest.approx(np.pi * 0.04**2 * 0.1 - inner, rel=0.03)
    lo, hi = np.reshape(cavity.bounding_box(), (2, 3))
    assert lo[2] == pytest.approx(0.004, abs=1e-6) and hi[2] < 0.102


@settings(max_examples=6, deadline=None)
@given(radius=st.floats(0.035, 0.05), reach=st.floats(0.042, 0.055),
       height=st.floats(0.08, 0.11))
def test_mug_family_stays_valid(radius, reach, height):
    spec = make_object("mug_classic", radius=radius, reach=reach, height=height)
    assert spec.mesh.is_watertight and spec.mesh.body_count == 1
    assert (2 - spec.mesh.euler_number) // 2 == 1
    assert spec.hangable_parts[0].clear_diameter >= 0.025
