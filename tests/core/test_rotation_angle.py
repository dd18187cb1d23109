"""``core.geometry.rotation_angle``: the angle between two orientations."""

import numpy as np
from hypothesis import given
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from gbh_drake.core.geometry import rotation_angle

unit_axes = st.tuples(*[st.floats(-1, 1)] * 3).map(np.array).filter(
    lambda v: np.linalg.norm(v) > 0.1)


@given(axis=unit_axes, deg=st.floats(0.0, 180.0), base=st.integers(0, 2**31 - 1))
def test_a_turn_by_deg_about_any_axis_from_any_orientation_measures_deg(axis, deg, base):
    R_a = Rotation.random(random_state=base).as_matrix()
    turn = Rotation.from_rotvec(np.radians(deg) * axis / np.linalg.norm(axis)).as_matrix()
    assert abs(rotation_angle(R_a, R_a @ turn) - deg) < 1e-4
    assert abs(rotation_angle(R_a @ turn, R_a) - deg) < 1e-4  # symmetric
