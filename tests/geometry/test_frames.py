import numpy as np
from hypothesis import given
from hypothesis import strategies as st

from geometry.frames import body_to_world, canonical_pitch_roll_deg, pitch_roll_from_up, up_vector

angles = st.floats(-180, 180, allow_nan=False)


def test_up_vector_convention():
    assert np.allclose(up_vector(0.0, 0.0), [0, 0, 1])
    # pitch 90: head down, u = -x; roll 90: u = +y
    assert np.array_equal(up_vector(np.pi / 2, 0.7), [-1.0, 0.0, 0.0])
    assert np.allclose(up_vector(0.0, np.pi / 2), [0, 1, 0])


@given(angles, angles)
def test_double_cover(p, r):
    """(p, r) and (180 - p, r + 180) are the same orientation."""
    a = up_vector(np.deg2rad(p), np.deg2rad(r))
    b = up_vector(np.deg2rad(180 - p), np.deg2rad(r + 180))
    assert np.allclose(a, b, atol=1e-12)
    cp, cr = canonical_pitch_roll_deg(180 - p, r + 180)
    assert np.allclose(up_vector(np.deg2rad(cp), np.deg2rad(cr)), a, atol=1e-12)
    assert -90 <= cp <= 90


@given(st.floats(-89, 89), angles)
def test_pitch_roll_round_trip(p, r):
    pr, rr = pitch_roll_from_up(up_vector(np.deg2rad(p), np.deg2rad(r)))
    assert np.allclose(up_vector(pr, rr), up_vector(np.deg2rad(p), np.deg2rad(r)), atol=1e-12)


def test_rotation_matches_up_vector():
    R = body_to_world(0.3, -2.0)
    assert np.allclose(R @ R.T, np.eye(3))
    assert np.allclose(R.T @ [0, 0, 1], up_vector(0.3, -2.0))
