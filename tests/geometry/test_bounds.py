"""Stated ranges: a value is returned only inside its range, anything else is one UsageError line naming it; a
percentage is exactly the fraction it writes; unit slips are said only where plausible."""

from __future__ import annotations

import math

import pytest
from hypothesis import example, given
from hypothesis import strategies as st

from geometry.bounds import Bounds, mass_slip, percent_to_fraction, radians_slip
from geometry.errors import UsageError
from landscape.params import parse_bounded

CV = Bounds(0.0, 1.0, meaning="Cv is sigma / Tl as a fraction", percent=True)
PHASE = Bounds(0.0, 1.0, hi_open=True)
COUNT = Bounds(1, math.inf, integer=True)


@given(st.floats(allow_nan=True, allow_infinity=True), st.sampled_from([CV, PHASE, COUNT]))
@example(1.0, PHASE)
@example(0.0, COUNT)
@example(2.5, COUNT)
def test_a_value_is_returned_inside_its_range_or_refused_in_one_line(v, b):
    try:
        got = b.check(v, "--x")
    except UsageError as exc:
        text = str(exc)
        assert text.startswith("--x ") and "\n" not in text
        assert not b.contains(v)
        return
    assert b.contains(got) and got == v
    assert isinstance(got, int) == b.integer


@pytest.mark.parametrize(
    "b, text",
    [
        (CV, "in [0, 1], or a percentage written as '10%'"),
        (PHASE, "in [0, 1)"),
        (COUNT, ">= 1, a whole number"),
        (Bounds(0.0, 600.0, unit="s", lo_open=True), "in (0, 600] s"),
        (Bounds(0.0, math.inf, unit="kg", lo_open=True), "> 0 kg"),
    ],
)
def test_the_range_in_words(b, text):
    assert b.text == text


@given(st.integers(0, 10_000), st.integers(0, 4))
def test_a_percentage_is_exactly_the_fraction_it_writes(n, decimals):
    """'12.5%' reads as the float '0.125' reads as: the same trial seeds as the fraction."""
    written = f"{n / 10**decimals:.{decimals}f}"
    frac = percent_to_fraction(written + "%", "--cv")
    from decimal import Decimal

    assert frac == float(Decimal(written) / 100)
    if n <= 100 * 10**decimals:
        assert parse_bounded(f"0%,{written}%", CV, "--cv") == [0.0, frac]


def test_percent_ranges_read_as_their_fractions():
    assert parse_bounded("0%:25%:5%", CV, "--cv") == parse_bounded("0:0.25:0.05", CV, "--cv")
    with pytest.raises(UsageError, match="mixes percentages and fractions"):
        parse_bounded("0:25%:5%", CV, "--cv")
    with pytest.raises(UsageError, match=r"--cv 150 is outside \[0, 1\]"):
        parse_bounded("150", CV, "--cv")
    with pytest.raises(UsageError, match=r"--cv 1\.5 is outside"):
        parse_bounded("150%", CV, "--cv")


@pytest.mark.parametrize(
    "value, limits, said",
    [
        (1.3, (-10.0, 95.0), True),  # 74.5 deg in radians: inside the wing's limits
        (-0.5, (-90.0, 90.0), True),
        (0.0, (-10.0, 95.0), False),  # 0 is 0 in any unit
        (30.0, (-10.0, 95.0), False),  # more than 2 pi: degrees
        (2.0, (-10.0, 95.0), False),  # 114.6 deg: past the limit, so meant in degrees
        (1.0, (-5.0, 5.0), False),  # a joint of a few degrees: 1 deg is plausible
        ([0.0, 0.5, 1.0], (-90.0, 90.0), True),
        ([0.5, 20.0], (-90.0, 90.0), False),
    ],
)
def test_radians_are_suspected_only_where_plausible(value, limits, said):
    text = radians_slip(value, limits, "--theta-l")
    assert (text is not None) == said
    if said and not isinstance(value, list):
        assert text.endswith(f"give --theta-l {math.degrees(value):.4g}")


def test_a_mass_over_a_tonne_is_suspected_to_be_grams():
    assert mass_slip(1000.0, "--mass") is None and mass_slip(None, "--mass") is None
    assert mass_slip(260_000.0, "--mass") == (
        "--mass 260000 kg is more than 1000 kg; if you meant grams, give --mass 260"
    )
