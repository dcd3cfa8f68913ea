"""Long benchmarks show their progress (#17): benchmarks/sim_convergence.py plans its trials and reports them done
with elapsed time and ETA on stderr. Runs the benchmark's own main with a fast stand-in for the simulator, so the
planned total is checked against the trials the benchmark really runs."""

from __future__ import annotations

import io
import sys
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from tests.conftest import load_script


@pytest.fixture()
def convergence(monkeypatch):
    mod = load_script("benchmarks/sim_convergence.py")
    calls = []

    def fake_trial(theta_w_deg, theta_l_deg, **kw):
        calls.append((theta_w_deg, theta_l_deg, kw.get("dt_s")))
        t = np.arange(0.0, 2.0 + 1e-9, 0.01)
        trace = SimpleNamespace(t_s=t, pitch_deg=0.5 * t, roll_deg=np.zeros_like(t))
        return SimpleNamespace(
            trace=trace, success=True, attempt=1, time_to_right_s=1.0, cpu_s=1.0, sim_s=2.0
        )

    monkeypatch.setattr(mod, "_run_trial", fake_trial)
    return mod, calls


@pytest.mark.parametrize("argv", [["--quick"], ["--rate-seeds", "2"], ["--only-rates", "--rate-seeds", "3"]])
def test_sim_convergence_reports_every_planned_trial(monkeypatch, convergence, argv):
    mod, calls = convergence
    err, out = io.StringIO(), io.StringIO()
    monkeypatch.setattr(sys, "argv", ["sim_convergence.py", *argv])
    monkeypatch.setattr(sys, "stderr", err)
    monkeypatch.setattr(sys, "stdout", out)
    mod.main()
    lines = err.getvalue().splitlines()
    assert calls and lines, "the benchmark ran no trial or printed no progress"
    n = len(calls)
    assert lines[-1].startswith(f"progress: {n}/{n} trials, ") and "ETA 0 s" in lines[-1], lines
    assert "\r" not in err.getvalue()  # a log, not a terminal: lines, no bar frames
    assert "|" in out.getvalue()  # the tables still go to stdout


def test_sim_convergence_progress_lines_carry_an_eta(convergence):
    mod, _ = convergence
    stream = io.StringIO()
    prog = mod.Progress(4, stream=stream)
    prog.t0 -= 10.0  # 10 s in, one trial of four done
    prog.last = -1e9
    prog.step()
    assert stream.getvalue().startswith("progress: 1/4 trials, 10 s elapsed, ETA 30 s")
    assert Path(mod.__file__).name == "sim_convergence.py"
