"""Barrier intervals (landscape/uncertainty.py): the first-order band against the Monte-Carlo range."""

from __future__ import annotations

import math

import numpy as np
import pytest
import trimesh

from geometry import Robot
from geometry.errors import UsageError
from geometry.robots import load_robot
from landscape.computation import compute
from landscape.uncertainty import DEFAULT_SAMPLES, Uncertainty, barrier_intervals, com_offsets_m

AGREE = 0.03
"""On a smooth case each end of the Monte-Carlo range lies within this fraction of the first-order band's
half-width of the band's end: N directions miss the extreme one by an angle of order N^(-1/2) (1 - cos of it,
about 1 / N, is 0.25 % at N = 400) and the second-order term is (r / distance to the edge) of the half-width
(1 cm / 1 m here)."""


def _box(com, extents=(4.0, 2.0, 1.0)):
    return Robot.from_trimesh(trimesh.creation.box(extents=extents), mass_kg=1.0, com=com)


def _righting(com, u):
    c = compute(_box(com), g_m_s2=1.0, landscape_grid=False)
    return c, barrier_intervals(c, u).exits["righting"]


def test_monte_carlo_contains_the_first_order_band_on_a_smooth_case():
    """CoM 0.1 m towards +y, 1 cm uncertainty: the +y edge's saddle stays the lowest (the -y edge is 0.2 m of CoM
    away from taking over), so the recomputed barriers span the first-order band."""
    c, i = _righting((0.0, 0.1, 0.0), Uncertainty(com_m=0.01, samples=400))
    lo, hi = i.first_order_j
    half = (hi - lo) / 2
    assert half == pytest.approx(0.01 * np.linalg.norm(c.gradient["righting"].com_j_per_m), rel=1e-12)
    assert i.note is None
    mc_lo, mc_hi = i.monte_carlo_j
    assert mc_lo <= lo + AGREE * half and mc_hi >= hi - AGREE * half
    assert abs(mc_lo - lo) <= AGREE * half and abs(mc_hi - hi) <= AGREE * half


def test_monte_carlo_shows_a_switch_of_saddle_inside_the_uncertainty():
    """CoM 1 mm towards +y, 1 cm uncertainty: the -y edge's saddle, 2 mm of CoM away, takes over inside the
    uncertainty. The barrier is the lower of the two, so it cannot rise as far as the +y saddle's gradient
    says: the recomputed range stops well short of the first-order band's top, and the band says it reaches
    beyond the gradient's reach."""
    c, i = _righting((0.0, 0.001, 0.0), Uncertainty(com_m=0.01, samples=400))
    lo, hi = i.first_order_j
    half = (hi - lo) / 2
    assert c.gradient["righting"].differentiable
    assert "first order holds only within" in i.note
    assert i.monte_carlo_j[1] < hi - 0.3 * half


def test_where_there_is_no_gradient_the_band_is_the_monte_carlo_range():
    """Centred CoM: two equal saddles, no first-order band; the Monte-Carlo range stands in unasked. The barrier is
    the lower of two saddles whose gradients g = (0, +-a, b) are mirror images, so to first order it spans
    [B - r |g|, B + r |b|] (the highest of min(g1 . d, g2 . d) over |d| <= r is r |b|, at d along z): the range
    lies within it, below the single saddle's B + r |g|."""
    c = compute(_box((0.0, 0.0, 0.0)), g_m_s2=1.0, landscape_grid=False)
    iv = barrier_intervals(c, Uncertainty(com_m=0.01))
    i = iv.exits["righting"]
    assert i.first_order_j is None and "2 saddles" in i.note
    assert iv.samples == DEFAULT_SAMPLES and iv.seconds_per_sample > 0
    g = c.gradient["righting"].one_sided_com_j_per_m
    assert g.shape == (2, 3) and g[0, 1] == pytest.approx(-g[1, 1])
    b, r = i.barrier_j, 0.01
    assert b - r * np.linalg.norm(g[0]) * (1 + AGREE) <= i.monte_carlo_j[0] < b
    assert b < i.monte_carlo_j[1] <= b + r * abs(g[0, 2]) * (1 + AGREE)


def test_a_mass_uncertainty_alone_scales_the_barrier():
    """At a fixed CoM the barrier is proportional to the mass: first order is exact."""
    c = compute(_box((0.0, 0.1, 0.0)), g_m_s2=1.0, landscape_grid=False)
    i = barrier_intervals(c, Uncertainty(mass_kg=0.05, samples=3)).exits["righting"]
    b = c.barrier.righting.barrier_j
    assert i.first_order_j == pytest.approx((0.95 * b, 1.05 * b), rel=1e-12)
    assert i.monte_carlo_j == pytest.approx((0.95 * b, 1.05 * b), rel=1e-12)


def test_the_monte_carlo_range_is_seeded():
    c = compute(load_robot(), theta_w_deg=74.0, theta_l_deg=30.0, landscape_grid=False)
    a = barrier_intervals(c, Uncertainty(com_m=0.001, samples=8, seed=3)).exits["righting"]
    b = barrier_intervals(c, Uncertainty(com_m=0.001, samples=8, seed=3)).exits["righting"]
    other = barrier_intervals(c, Uncertainty(com_m=0.001, samples=8, seed=4)).exits["righting"]
    assert a.monte_carlo_j == b.monte_carlo_j != other.monte_carlo_j
    assert np.allclose(np.linalg.norm(com_offsets_m(50, 0.002, 1), axis=1), 0.002)


@pytest.mark.parametrize(
    "u, needle",
    [
        (Uncertainty(com_m=-0.001), "must be a finite number >= 0"),
        (Uncertainty(com_m=math.nan), "must be a finite number >= 0"),
        (Uncertainty(mass_kg=math.inf), "must be a finite number >= 0"),
        (Uncertainty(com_m=0.001, samples=0), "samples must be a whole number in [1, 100000]"),
        (Uncertainty(com_m=0.5), "larger than the body"),
        (Uncertainty(mass_kg=2.0), "is not below the mass"),
    ],
)
def test_bad_uncertainties_are_refused(u, needle):
    c = compute(_box((0.0, 0.1, 0.0)), g_m_s2=1.0, landscape_grid=False)
    with pytest.raises(UsageError) as e:
        barrier_intervals(c, u)
    assert needle in str(e.value) and "\n" not in str(e.value)
