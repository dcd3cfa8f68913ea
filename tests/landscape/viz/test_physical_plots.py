"""The physical robot's printed tables (landscape/viz/physical_plots.py): captions come from the analyses'
constants, so they cannot drift from what was computed."""

import math

from landscape.analysis.physical import lean, response, resting
from landscape.analysis.physical.cells import Lateralisation
from landscape.analysis.physical.kinematics import Kinematics
from landscape.viz.physical_plots import kinematics_text


def _kinematics():
    lat = Lateralisation(3, 1, 0.75, 0.3, 0.95)
    return Kinematics([], None, [], [(15.0, 0.25)], {15.0: 0.125}, None, [], lat)


def test_the_captions_state_the_windows_the_analyses_use():
    text = "\n".join(kinematics_text(_kinematics()))
    assert "pitch 0.5-0.95 s after each opening starts minus the rest in the 0.3 s before" in text
    assert "(0.95-1.05 s), the openings that rolled past a tilt of 45 deg within 1.4 s" in text
    assert "(0.2 s after it gets there, 0.4-1.0 s after the opening starts;" in text
    assert (
        "leg 15° 0.250 (the leg command's lead" in text
        and "0.125 s (vib_pulse_v2.mat), over its 0.8 s" in text
    )
    assert "roll-overs to + roll: 3 of 4 (Wilson 95 % [30, 95] %)" in text


def test_a_changed_window_changes_its_caption(monkeypatch):
    monkeypatch.setattr(resting, "HOLD_WINDOW_S", (0.4, 0.9))
    monkeypatch.setattr(response, "ROLLED_TILT_DEG", 50.0)
    monkeypatch.setattr(lean, "LEAN_WINDOW_S", (0.3, 1.1))
    text = "\n".join(kinematics_text(_kinematics()))
    assert "pitch 0.4-0.9 s after each opening starts" in text
    assert "rolled past a tilt of 50 deg" in text and "before passing 50 deg" in text
    assert "0.3-1.1 s after the opening starts" in text


def test_without_the_legs_recording_the_phase_says_why():
    k = Kinematics(
        [], None, [], None, None, "no vib_pulse_v2.mat", [], Lateralisation(0, 0, math.nan, 0.0, 1.0)
    )
    assert (
        "the first attempt's leg phase under the protocol: not measured (no vib_pulse_v2.mat)"
        in kinematics_text(k)
    )
