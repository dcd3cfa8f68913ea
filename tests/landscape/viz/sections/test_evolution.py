"""The phase-evolution section (landscape/viz/sections/evolution.py) on synthetic trial rows."""

import numpy as np
import pytest

from landscape.viz.sections.evolution import section_evolution
from tests.conftest import csv_rows as _csv
from tests.landscape.viz.sections.synthetic import _map_rows, _row, _won


def test_evolution_without_a_phase_map_says_what_to_run(tmp_path):
    rows = [_won(seed=1), _row(seed=2)]
    sec = section_evolution(rows, tmp_path, tmp_path / "t.sqlite")
    assert (
        sec.missing
        and "no single-attempt phase map at Tl 0.8 s" in sec.missing
        and "landscape sweep" in sec.missing
    )


def test_evolution_takes_the_trials_phase_when_every_start_meets_a_good_phase(tmp_path):
    """Tw/Tl = 2.5 alternates phi and phi + 0.5: with good phases 0.0-0.45 every start meets one, so the section
    takes phi_1 from the multi-attempt trials at that setting (0.35, their most common) and the study setting
    from the map (74, 30), not from fixed defaults."""
    good = set(np.round(np.arange(0, 0.5, 0.05), 2))
    rows = _map_rows(good) + [_row(cv=0.0, phase=0.35, seed=s) for s in (1, 2, 3)] + [_row(cv=0.0, phase=0.6)]
    sec = section_evolution(rows, tmp_path, tmp_path / "t.sqlite", attempts=4)
    assert not sec.missing
    recs = _csv(tmp_path / "evolution.csv")
    first = [r for r in recs if r["attempt"] == "1"]
    assert [float(r["phase"]) for r in first] == pytest.approx([0.35, 0.35])
    assert float(first[0]["start_s"]) == pytest.approx(0.35 * 0.8)


def test_evolution_draws_every_requested_attempt_under_heavy_noise(tmp_path):
    rows = _map_rows({0.2})
    sec = section_evolution(rows, tmp_path, tmp_path / "t.sqlite", cv=3.0, seed=7, attempts=12)
    assert not sec.missing
    recs = _csv(tmp_path / "evolution.csv")
    assert sorted({float(r["noise_cv"]) for r in recs}) == [0.0, 3.0]
    for cv in (0.0, 3.0):
        assert [int(r["attempt"]) for r in recs if float(r["noise_cv"]) == cv] == list(range(1, 13))
