"""Property-based tests of the parsers people type into (#16): value ranges, joint maps, --com and angles.

Whatever the text, a parser either returns a value that satisfies its contract or raises the project's
UsageError with one line; it never returns something silently wrong, raises anything else, or hangs."""

from __future__ import annotations

import math

from hypothesis import example, given, settings
from hypothesis import strategies as st

from geometry.errors import UsageError
from geometry.joint_map import JointMap
from landscape.cli.options import finite
from landscape.params import MAX_VALUES, parse_values

numbers = st.floats(allow_nan=True, allow_infinity=True) | st.integers(-(10**6), 10**6).map(float)
text = st.text(alphabet="0123456789.,:-+eEinfa ", max_size=30)


@settings(max_examples=300, deadline=None)
@given(text)
@example("0:90:1e-7")
@example("0:1e308:1e-308")
@example("1e308:-1e308:1")
@example(",,,")
@example("nan,1")
def test_parse_values_returns_finite_bounded_lists_or_one_clear_error(s):
    try:
        vals = parse_values(s, "theta-w")
    except UsageError as exc:
        assert str(exc).startswith("--theta-w") and "\n" not in str(exc)
        return
    assert 1 <= len(vals) <= MAX_VALUES
    assert all(isinstance(v, float) and math.isfinite(v) for v in vals)


@settings(max_examples=200, deadline=None)
@given(st.floats(-1e3, 1e3, allow_nan=False), st.floats(-1e3, 1e3, allow_nan=False), st.floats(1e-3, 1e3))
def test_a_range_is_inclusive_and_evenly_spaced(start, stop, step):
    s = f"{start!r}:{stop!r}:{step!r}"
    try:
        vals = parse_values(s, "theta-l")
    except UsageError as exc:
        assert "is empty (STOP < START)" in str(exc) or "more than the" in str(exc)
        assert stop < start or (stop - start) / step + 1 > MAX_VALUES
        return
    assert vals[0] == round(start, 10) and vals[-1] <= stop + 1e-6 * step + 1e-9
    assert vals[-1] + step > stop - 1e-6 * max(1.0, abs(stop))  # the last value is the last one before STOP
    assert len(vals) == math.floor((stop - start) / step + 1e-9) + 1


names = st.text(alphabet="abcxyz_019", min_size=0, max_size=6)


@settings(max_examples=300, deadline=None)
@given(st.lists(names, max_size=5), st.lists(names, max_size=3), st.sampled_from([";", "; ", ";;"]))
@example(["", ""], [""], ";")  # wing=,;leg=
@example([], [], ";")  # no joint at all
@example(["a"], [], ";")  # a body without a leg
@example(["leg"], ["leg"], ";")  # the same joint twice
def test_joint_maps_round_trip_or_refuse(wing, leg, sep):
    s = f"wing={','.join(wing)}{sep}leg={','.join(leg)}"
    # an empty group ('wing=' or 'leg=') is left out: nothing drives that angle
    wing_g, leg_g = (() if g in ([], [""]) else tuple(g) for g in (wing, leg))
    valid = (wing_g or leg_g) and "" not in wing_g + leg_g and len(set(wing_g + leg_g)) == len(wing_g + leg_g)
    try:
        jm = JointMap.parse(s)
    except UsageError as exc:
        assert "\n" not in str(exc)
        assert not valid
        return
    assert valid
    assert jm.wing == wing_g and jm.leg == leg_g
    assert JointMap.parse(jm.text()) == jm


@settings(max_examples=200, deadline=None)
@given(st.text(alphabet="0123456789.,-eEnaif ", max_size=25))
@example("0,0")
@example("1,2,3,4")
@example("nan,0,0")
def test_com_option_is_three_finite_numbers_or_one_clear_error(s):
    from landscape.cli.options import load_robot

    try:
        load_robot(None, "/nonexistent.stl", com=s)
    except UsageError as exc:
        msg = str(exc)
        assert "\n" not in msg
        parts = s.split(",")
        ok_com = len(parts) == 3 and all(_is_finite_number(x) for x in parts)
        # a well-formed CoM gets past its own check and fails on the missing mesh instead
        assert ("--com" in msg) if not ok_com else ("nonexistent" in msg)


def _is_finite_number(x: str) -> bool:
    try:
        return math.isfinite(float(x))
    except ValueError:
        return False


@settings(max_examples=200, deadline=None)
@given(numbers)
def test_angles_are_finite_or_refused(value):
    try:
        out = finite(value, "theta-w")
    except UsageError as exc:
        assert not math.isfinite(value) and "--theta-w must be a finite number" in str(exc)
        return
    assert out == value and math.isfinite(out)
