"""benchmarks/studies/prediction_states.py: counts the attempts after a failed one that start still, the map's misses
among them, and pairs of attempts that open from the same state and end differently."""

import json

import pytest

from tests.conftest import load_script

pytest.importorskip("pybullet")


def _state(attempt, phase, *, ke=0.0, omega_y=-0.3, success=False):
    return dict(
        key="k", wing_period_s=0.0, leg_period_s=0.0, attempt=attempt, phase=phase, roll_deg=0.03, pitch_deg=-1.1,
        omega_x=0.0, omega_y=omega_y, omega_z=0.0, ke_rot_mj=ke, success=success,
    )  # fmt: skip


def test_counts_still_starts_map_misses_and_same_state_pairs(tmp_path, capsys):
    from sim.sweep import run_sweep, sweep_specs

    db = tmp_path / "t.sqlite"
    specs = sweep_specs(
        (74.0,), (30.0,), (0.0,), phase=(0.0, 0.5), attempts=1, duration_s=4.0, dt_s=1e-3, trials=1
    )
    run_sweep(specs, db=db, workers=1, progress=False)
    from landscape.analysis.trials import phase_maps
    from sim.store import read_rows

    pm = phase_maps(read_rows(db))[(74.0, 0.8)]
    good0 = pm.lookup(30.0, 0.0)[0]
    key = "h/paper/74/30/Tw2/Tl0.8/phi0/cv0/10s/dt0.001/seed1"
    trial = {
        "key": key,
        "reproduced": True,
        "states": [
            _state(1, 0.0, success=False),
            _state(2, 0.5, ke=0.5, omega_y=2.0),  # moving
            _state(3, 0.0, success=True),  # attempt 1's phase and state, another outcome
            _state(4, 0.5, success=True),
        ],
    }
    states = tmp_path / "s.jsonl"
    states.write_text(json.dumps(trial) + "\n")
    bench = load_script("benchmarks/studies/prediction_states.py")
    assert bench.main(["--db", str(db), "--states", str(states)]) == 0
    out = capsys.readouterr().out
    good5 = pm.lookup(30.0, 0.5)[0]
    assert "1 trials, 3 attempts after a failed one" in out
    still_wrong = int(not good0) + int(not good5)  # attempts 3 and 4 righted
    assert f"below 0.1 mJ: 2; the map from rest gets {still_wrong} of them wrong" in out
    assert f"0.1 mJ or more: 1; the map gets {int(good5)} wrong" in out  # attempt 2 failed
    assert "ending differently: 1\n" in out and "attempts 1 and 3" in out
    assert "headings" not in out  # states without a heading (older files) say nothing of it
    trial["states"] = [
        {**st, "heading_deg": 10.0 * st["attempt"] + 90.0 * (st["attempt"] == 3)} for st in trial["states"]
    ]
    states.write_text(json.dumps(trial) + "\n")
    assert bench.main(["--db", str(db), "--states", str(states)]) == 0
    out = capsys.readouterr().out
    assert "more than 1 deg apart: 1 of 1" in out and "attempts 1 and 3 (headings 20.0 deg apart)" in out
    assert bench.main(["--db", str(db), "--states", str(tmp_path / "absent.jsonl")]) == 2
