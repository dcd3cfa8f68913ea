"""The held body's lean with the leg on each side, and when a roll-over leaves the level
(landscape/analysis/physical/lean.py): synthetic series with known leans and departures, the mirror symmetry
of the built-in robot's simulated leans, and the robot's pattern on the lab's recordings (skipped without
../shared)."""

import math

import numpy as np
import pytest

from landscape.analysis.physical.lean import (
    LEAN_SETTLE_S,
    LEAN_WINDOW_S,
    LEG_HALF_PERIOD_S,
    LEG_LAG_S,
    HoldLeans,
    cell_lean,
    departure_s,
    hold_leans_deg,
    recorded_leans,
    simulated_leans,
)
from landscape.analysis.physical.response import lateral_tilt_deg
from tests.landscape.analysis.physical.lab import DATA, needs_data

DT_S = 0.01


def _roll_for_tilt_deg(pitch_deg, tilt_deg):
    """The roll that gives this lateral tilt at this pitch: sin(tilt) = cos p sin r."""
    return np.degrees(np.arcsin(np.sin(np.radians(tilt_deg)) / np.cos(np.radians(pitch_deg))))


def _leg_series(changes_s, sides, *, lag_s=0.0, t_end_s=2.0):
    """Times, and the leg's side at each (0 before the first change), the leg reaching a side ``lag_s`` after
    its change."""
    t = np.arange(-0.5, t_end_s, DT_S).round(2)
    k = np.searchsorted(np.asarray(changes_s) + lag_s, t + 1e-9, side="right") - 1
    return t, np.where(k >= 0, np.asarray(sides)[np.clip(k, 0, None)], 0)


def test_each_settled_window_gives_its_median_tilt_with_the_leg_on_its_side():
    """Pitch 60; the leg command changes side every 0.4 s and the leg follows 0.1 s later; the body leans +4 deg
    with the leg on + and -1.5 deg on - once settled, with a 10 deg swing in the 0.2 s after each change that the
    settling skips. Windows 0.4-1.0 s after the opening: - from 0.5 to 0.7 s and + from 0.9 to 1.0 s."""
    changes, sides = np.array([-0.6, -0.2, 0.2, 0.6, 1.0]), np.array([-1, 1, -1, 1, -1])
    t, side = _leg_series(changes, sides, lag_s=LEG_LAG_S)
    tilt = np.where(side > 0, 4.0, -1.5)
    since = t - (changes[np.clip(np.searchsorted(changes + LEG_LAG_S, t + 1e-9) - 1, 0, None)] + 0.1)
    tilt = tilt + np.where((since >= 0) & (since < LEAN_SETTLE_S - 0.005), 10.0 * side, 0.0)
    pitch = np.full_like(t, 60.0)
    roll = _roll_for_tilt_deg(pitch, tilt)
    leans = hold_leans_deg(t, pitch, roll, 0.0, changes, sides, lag_s=LEG_LAG_S)
    assert [s for s, _ in leans] == [-1, 1]
    assert [v for _, v in leans] == pytest.approx([-1.5, 4.0], abs=1e-9)
    # the same series on another clock, the opening 3 s in: the same windows
    shifted = hold_leans_deg(t + 3.0, pitch, roll, 3.0, changes + 3.0, sides, lag_s=LEG_LAG_S)
    assert [s for s, _ in shifted] == [-1, 1]
    assert [v for _, v in shifted] == pytest.approx([-1.5, 4.0], abs=1e-9)
    # a lean that grows within the window: its median, from the window's samples only
    growing = np.where(side > 0, 4.0, -1.5) + 0.5 * t
    got = hold_leans_deg(t, np.zeros_like(t), growing, 0.0, changes, sides, lag_s=LEG_LAG_S)
    in_minus = (t >= 0.5 - 1e-9) & (t <= 0.7 + 1e-9)
    assert got[0] == (-1, pytest.approx(float(np.median(growing[in_minus])), abs=1e-12))
    assert got[0][1] == pytest.approx(-1.5 + 0.5 * 0.6, abs=1e-9)


def test_windows_too_short_or_outside_the_hold_are_dropped():
    """Changes at -0.1 (+), 0.13 (-), 0.4 (+), 0.7 (-) s, no lag: the + window from -0.1 ends before the hold
    window, the - one would run 0.4-0.4 s, the + one 0.6-0.7 s (0.1 s, kept) and the last - one 0.9-1.0 s; with
    the + change at 0.47 instead, the - window is 0.07 s long and dropped, at 0.48 it is 0.08 s and kept."""
    t = np.arange(-0.5, 2.0, DT_S).round(2)
    level = np.zeros_like(t)
    roll = np.where(t < 0.8, 2.0, -3.0)
    sides = np.array([1, -1, 1, -1])
    leans = hold_leans_deg(t, level, roll, 0.0, [-0.1, 0.13, 0.4, 0.7], sides)
    assert leans == [(1, pytest.approx(2.0)), (-1, pytest.approx(-3.0))]
    short = hold_leans_deg(t, level, roll, 0.0, [-0.1, 0.2, 0.47, 0.9], sides)
    assert short == [(1, pytest.approx(2.0))]  # the + window is 0.67-0.9 s; - 0.4-0.47 s is dropped
    edge = hold_leans_deg(t, level, roll, 0.0, [-0.1, 0.2, 0.48, 0.9], sides)
    assert [s for s, _ in edge] == [-1, 1]
    # a leg still (no change) or a series without samples: nothing
    assert hold_leans_deg(t, level, roll, 0.0, [], []) == []
    # the series ends inside a window: the window ends with it
    cut = t <= 0.75
    assert hold_leans_deg(t[cut], level[cut], roll[cut], 0.0, [-0.1, 0.13, 0.4, 0.7], sides) == [
        (1, pytest.approx(2.0))
    ]


def test_windows_end_before_the_body_departs_or_rights():
    """The leg on + from 0.0 s (window 0.4-1.0 s) while the tilt grows at 100 deg/s from 0.65 s: it passes
    40 deg at 1.05 s, so the window ends at 0.75 s. A roll that passes 40 deg before 0.78 s leaves no window
    (it would last less than 0.08 s); a body upright from before the opening (roll 170 deg: a tilt of 10 deg) leaves none either."""
    t = np.arange(-0.5, 2.0, DT_S).round(2)
    level = np.zeros_like(t)
    rolling = np.where(t < 0.65, 0.5, 0.5 + 100.0 * (t - 0.65))
    leans = hold_leans_deg(t, level, rolling, 0.0, [0.0], [1])
    sel = (t >= 0.4) & (t <= 0.75 + 1e-9)
    assert leans == [(1, pytest.approx(float(np.median(rolling[sel]))))]
    assert float(t[sel][-1]) == pytest.approx(0.75)
    early = np.where(t < 0.37, 0.5, 0.5 + 100.0 * (t - 0.37))  # past 40 deg at 0.77 s: ends at 0.47 s
    assert hold_leans_deg(t, level, early, 0.0, [0.0], [1]) == []
    upright = np.full_like(t, 170.0)
    assert hold_leans_deg(t, level, upright, 0.0, [0.0], [1]) == []
    # righted 2 s earlier and back on its back since: the upright stretch is over and does not count
    fell_back = np.where((t > -0.45) & (t < -0.05), 170.0, 1.0)
    assert hold_leans_deg(t, level, fell_back, 0.0, [0.0], [1]) == [(1, pytest.approx(1.0))]


def test_hold_leans_refuses_mismatched_input():
    t = np.arange(0.0, 1.0, DT_S)
    with pytest.raises(ValueError, match="one length"):
        hold_leans_deg(t, t[:-1], t, 0.0, [0.0], [1])
    with pytest.raises(ValueError, match="one length"):
        hold_leans_deg(t, t, t, 0.0, [0.0, 0.4], [1])
    with pytest.raises(ValueError, match=r"\+1 or -1; got 0.0"):
        hold_leans_deg(t, t, t, 0.0, [0.0, 0.4], [1, 0])
    with pytest.raises(ValueError, match="increasing"):
        hold_leans_deg(t, t, t, 0.0, [0.4, 0.0], [1, -1])


def test_departure_is_the_last_rise_through_five_degrees_on_the_side_it_rolls_to():
    """Level (pitch 0: the tilt is the roll), a rock to +8 deg (the other side) and one to -7 deg and back, then a
    roll to - at 100 deg/s from 0.7 s: the tilt last rose through 5 deg on the - side at 0.75 s. A roll past
    45 deg only after 1.4 s, or none, is no roll-over; a body already beyond 5 deg from the start departed at 0."""
    t = np.arange(-0.5, 2.0, DT_S).round(2)
    level = np.zeros_like(t)
    roll = np.where(t < 0.7, 0.0, -100.0 * (t - 0.7))
    roll = np.clip(roll + 8.0 * ((t > 0.2) & (t < 0.3)) - 7.0 * ((t > 0.4) & (t < 0.5)), -80.0, 80.0)
    assert departure_s(t, level, roll, 0.0) == pytest.approx(0.75, abs=1e-9)
    # the same tilt at pitch 30: sin(tilt) = cos 30 sin r
    pitch = np.full_like(t, 30.0)
    tilted_30 = _roll_for_tilt_deg(
        pitch, np.clip(roll, -55.0, 55.0)
    )  # at pitch 30 the tilt is at most 60 deg
    assert departure_s(t, pitch, tilted_30, 0.0) == pytest.approx(0.75, abs=1e-9)
    late = np.where(t < 1.0, 0.0, -100.0 * (t - 1.0))  # past 45 deg at 1.45 s
    assert math.isnan(departure_s(t, level, late, 0.0))
    assert departure_s(t, level, late, 0.5) == pytest.approx(0.55, abs=1e-9)  # an opening 0.5 s later
    tilted = np.where(t < 0.3, 6.0, 6.0 + 100.0 * (t - 0.3))
    assert departure_s(t, level, tilted, 0.0) == 0.0
    assert math.isnan(departure_s(t, level, level, 0.0))


def test_cell_lean_without_windows_or_rolls_is_nan():
    c = cell_lean(90.0, 45.0, HoldLeans((), (), (math.nan,)))
    assert math.isnan(c.plus_deg) and math.isnan(c.minus_deg) and math.isnan(c.departure_s)
    assert (c.n_plus, c.n_minus, c.n_rolled, c.n_openings) == (0, 0, 0, 1)


def test_the_mirror_symmetric_robot_leans_to_its_legs_side_alike_on_both_sides():
    """The built-in robot is mirror-symmetric: with the leg 45 deg at 60 deg, a first opening half a leg period
    later (phase 0.67) swings the leg to the other side at the same times, so its leans mirror the first's (the
    leg's earlier swings differ, so not exactly); the held body leans towards the leg's side by about 1 deg in the
    first window. Every side and window is there: neither opening rolls over. With the leg still, no side."""
    a = simulated_leans(60.0, 45.0, model_set="paper", robot=None, seed=0, attempts=1, phase=0.17)
    b = simulated_leans(60.0, 45.0, model_set="paper", robot=None, seed=0, attempts=1, phase=0.67)
    assert len(a.minus_deg) == len(a.plus_deg) == len(b.minus_deg) == len(b.plus_deg) == 1
    assert a.minus_deg[0] == pytest.approx(-b.plus_deg[0], abs=0.1)
    assert a.plus_deg[0] == pytest.approx(-b.minus_deg[0], abs=0.1)
    assert a.minus_deg[0] < -0.5 and b.plus_deg[0] > 0.5
    assert math.isnan(a.departures_s[0]) and math.isnan(b.departures_s[0])
    still = simulated_leans(60.0, 0.0, model_set="paper", robot=None, seed=0, attempts=1)
    assert still.plus_deg == still.minus_deg == () and len(still.departures_s) == 1


@pytest.mark.shared
@needs_data
def test_the_robot_leans_with_its_leg_at_60_degrees():
    """The robot on its back at the 60 deg command leans to + tilt with the leg on + and stays about level with
    it on -: by 1.5 deg at leg 15 deg (24 and 25 windows), by 8.8 deg at leg 30 deg. At 75/15 it does not: the
    + lean of +10 deg an ad-hoc count found there came from two openings of the robot upright after righting (a
    roll near 170 deg reads as a tilt of +12 to +15 deg); on its back the three + windows have a median of -2 deg.
    Roll-overs leave the level 0.8-0.9 s into the opening at 60/30-75/30, about 0.3 s at 75/45 and 90/30-45."""
    cells = {c: cell_lean(*c, h) for c, h in recorded_leans(DATA).items()}
    assert len(cells) == 9 and all(leg > 0 for _, leg in cells)
    assert cells[(60.0, 30.0)].difference_deg > 5.0 and cells[(60.0, 30.0)].n_plus == 3
    assert cells[(60.0, 15.0)].difference_deg > 0.5 and cells[(60.0, 15.0)].n_plus >= 20
    assert abs(cells[(60.0, 15.0)].minus_deg) < 0.5 and cells[(60.0, 45.0)].minus_deg < 0.0
    c75 = cells[(75.0, 15.0)]
    assert c75.n_plus == 3 and c75.difference_deg < 0.0
    for c in ((60.0, 30.0), (60.0, 45.0), (75.0, 15.0), (75.0, 30.0)):
        assert 0.75 < cells[c].departure_s < 0.9
    for c in ((75.0, 45.0), (90.0, 30.0), (90.0, 45.0)):
        assert 0.25 < cells[c].departure_s < 0.35 and cells[c].n_rolled == cells[c].n_openings == 5


@pytest.mark.shared
@needs_data
def test_an_upright_robot_reads_as_a_tilt_but_gives_no_lean():
    """At 75/15 the robot keeps opening its wings after it has righted: upright (u_z < -0.9) with a roll near
    170 deg, its lateral tilt reads +10 to +16 deg, what made an ad-hoc count of every opening find a + lean of
    +10 deg there. hold_leans_deg reads no lean from those openings."""
    from landscape.analysis.physical.recording import read_recording, trial_files

    upright_tilts = []
    for f in trial_files(DATA):
        rec = read_recording(f)
        if (rec.theta_w_cmd_deg, rec.theta_l_deg) != (75.0, 15.0):
            continue
        changes = np.sort(np.concatenate([rec.leg_up_s, rec.leg_up_s + LEG_HALF_PERIOD_S]))
        sides = np.where(np.isin(changes, rec.leg_up_s), 1, -1)
        tilt = lateral_tilt_deg(rec.pitch_deg, rec.roll_deg)
        for start in rec.openings_s:
            held = (rec.t_s >= start + LEAN_WINDOW_S[0]) & (rec.t_s <= start + LEAN_WINDOW_S[1])
            if held.any() and np.median(rec.up_z[held]) < -0.9:
                upright_tilts.append(float(np.median(tilt[held])))
                leans = hold_leans_deg(
                    rec.t_s, rec.pitch_deg, rec.roll_deg, start, changes, sides, lag_s=LEG_LAG_S
                )
                assert leans == []
    assert len(upright_tilts) >= 2 and all(x > 10.0 for x in upright_tilts)


def test_leg_sides_from_the_log_and_from_an_angle():
    from landscape.analysis.physical.lean import LEG_LAG_S, leg_command_changes, leg_sides

    t, side = leg_command_changes([0.2, 1.0])
    assert np.allclose(t + LEG_LAG_S, [0.3, 0.7, 1.1, 1.5]) and side.tolist() == [1, -1, 1, -1]
    ts = np.arange(0.0, 1.0, 0.01).round(2)
    tc, s = leg_sides(ts, 30.0 * np.sin(2 * np.pi * (ts - 0.105) / 0.8), band_deg=15.0)
    # the first side from the start, then the first sample past each zero crossing
    assert np.allclose(tc, [0.0, 0.11, 0.51, 0.91]) and s.tolist() == [-1, 1, -1, 1]
    # a leg held still, wobbling about zero, never changes side
    assert leg_sides(ts, 0.1 * np.sin(40 * ts), band_deg=5.0)[0].size == 0
