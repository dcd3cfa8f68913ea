"""Sweeps keep their data and their processes in bounds (issues #16 sections 1 and 3): bounds refused up front,
repeated trials run once, a killed worker costs only time, killing the sweep ends its workers."""

import dataclasses
import multiprocessing
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("pybullet")
psutil = pytest.importorskip("psutil")

import sim.sweep as sweep_mod  # noqa: E402
from sim.store import RobotChangedError, TrialStore  # noqa: E402
from sim.sweep import MAX_TRIALS, SweepAborted, run_sweep, sweep_specs  # noqa: E402
from sim.trial import MAX_DURATION_S, MAX_STEPS, MIN_DT_S, Numerics, TrialInputError, run_trial  # noqa: E402

REPO = Path(__file__).resolve().parents[2]
SHORT = dict(duration_s=0.3, dt_s=1e-3)  # the built-in robot: ~1 s per trial with its model build


def _gone(pid: int) -> bool:
    try:
        return psutil.Process(pid).status() == psutil.STATUS_ZOMBIE
    except psutil.NoSuchProcess:
        return True


@pytest.mark.parametrize(
    ("kw", "match"),
    [
        (dict(duration_s=1e308), "longer than MAX_DURATION_S = 600 s"),
        (dict(duration_s=1e6), r"8e\+09 physics steps, 275 GiB"),
        (dict(dt_s=1e-300), r"dt must be in \[MIN_DT_S, MAX_DT_S\]"),
        (dict(dt_s=1e-9, duration_s=0.1), "MIN_DT_S"),
        (dict(dt_s=1e-6, duration_s=10.0), r"10,500,000 physics steps.*MAX_STEPS = 5,000,000"),
        (
            dict(dt_s=1e-5, duration_s=40.0, numerics=Numerics(control_period_s=None)),
            r"1.1 GiB of command profiles.*MAX_TRIAL_MEMORY",
        ),
    ],
)
def test_run_trial_refuses_oversized_trials_up_front(kw, match):
    t0 = time.perf_counter()
    with pytest.raises(TrialInputError, match=match):
        run_trial(74.0, 30.0, phase=0.7, cv=0.1, rng=1, **kw)
    assert time.perf_counter() - t0 < 10.0  # refused, not attempted
    assert MAX_DURATION_S == 600.0 and MIN_DT_S == 1e-6 and MAX_STEPS == 5_000_000


@pytest.mark.parametrize(("n_wing", "n_leg"), [(4, 1), (2, 1), (4, 3)])
def test_trial_cost_estimates_the_command_profiles_peak_memory(n_wing, n_leg):
    """trial_cost's bytes are within 5 % of tracemalloc's peak while one 10 s trial's commands are built."""
    import tracemalloc

    from sim.model_set import load_model_set
    from sim.trial import _schedule, _servo_commands, trial_cost

    act, starts, dur = _schedule(
        load_model_set(), None, 72.0, 30.0, phase=0.7, cv=0.1, gen=np.random.default_rng(0), duration_s=10.0,
        attempts=None,
    )  # fmt: skip
    tracemalloc.start()
    try:
        _servo_commands(
            act, starts, dt_s=1.25e-4, duration_s=dur, control_period_s=1e-3, n_wing=n_wing, n_leg=n_leg
        )
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    est = trial_cost(dur, 1.25e-4, n_joints=n_wing + n_leg)[1]
    assert abs(est / peak - 1) < 0.05, (est, peak)


def test_sweep_refuses_oversized_sweeps_up_front(tmp_path):
    t0 = time.perf_counter()
    with pytest.raises(TrialInputError, match=r"1,000,000,000 trials, more than MAX_TRIALS = 1,000,000"):
        sweep_specs((74,), (30,), (0.1,), trials=10**9)
    with pytest.raises(TrialInputError, match="MAX_TRIALS"):
        sweep_specs(range(70, 80), range(20, 50), [0.1] * 10, phase=[0.1] * 10, trials=MAX_TRIALS // 3000)
    assert time.perf_counter() - t0 < 10.0
    spec = sweep_specs((74,), (30,), (0.1,), trials=1, **SHORT)[0]
    db = tmp_path / "never.sqlite"
    with pytest.raises(TrialInputError, match="MAX_DURATION_S"):
        run_sweep([dataclasses.replace(spec, duration_s=1e6)], db=db, workers=1, progress=False)
    assert not db.exists()  # refused before the database was opened


def test_repeated_specs_run_once_and_ran_counts_stored_rows(tmp_path, monkeypatch):
    db = tmp_path / "dup.sqlite"
    specs = sweep_specs((70, 70, 70), (30,), (0.1,), trials=1, **SHORT)
    assert len(specs) == 3 and len({s.key() for s in specs}) == 1
    s = run_sweep(specs, db=db, workers=1, progress=False)
    assert (s.total, s.skipped, s.ran, s.duplicates) == (1, 0, 1, 0)
    with TrialStore(db) as store:
        assert store.count() == 1
    # a row another sweep stores while this one simulates it is not counted as run here
    real_add = TrialStore.add

    def add_after_another_sweep(self, row):
        real_add(self, row)  # the other sweep on this database commits the same trial first
        return real_add(self, row)

    monkeypatch.setattr(TrialStore, "add", add_after_another_sweep)
    s2 = run_sweep(sweep_specs((72,), (30,), (0.1,), trials=1, **SHORT), db=db, workers=1, progress=False)
    assert (s2.total, s2.ran, s2.duplicates, s2.skipped) == (1, 0, 1, 1)


def test_robot_changed_since_the_sweep_is_refused_before_running(tmp_path):
    db = tmp_path / "robot.sqlite"
    specs = sweep_specs((74,), (30,), (0.1,), trials=1, **SHORT)
    assert run_sweep(specs, db=db, workers=1, progress=False).ran == 1
    changed = [dataclasses.replace(s, robot_hash="0" * 16, trial=s.trial + 1) for s in specs]
    t0 = time.perf_counter()
    with pytest.raises(RobotChangedError, match="changed.*new --db, or restore the robot"):
        run_sweep(changed, db=db, workers=1, progress=False)
    assert time.perf_counter() - t0 < 5.0
    with TrialStore(db) as store:
        assert store.count() == 1


def test_local_pool_is_waited_for_at_the_end(tmp_path):
    specs = sweep_specs((74,), (30,), (0.1,), trials=2, **SHORT)
    s = run_sweep(specs, db=tmp_path / "w.sqlite", workers=2, progress=False)
    assert s.ran == 2
    assert multiprocessing.active_children() == []  # joined, none left running


def test_killed_worker_costs_only_its_trial(tmp_path):
    db = tmp_path / "kill.sqlite"
    specs = sweep_specs((74, 76), (30,), (0.1,), trials=3, **SHORT)
    killed = []

    def kill_a_worker(row):
        if not killed:
            (worker,) = multiprocessing.active_children()
            os.kill(worker.pid, signal.SIGKILL)
            killed.append(worker.pid)

    s = run_sweep(specs, db=db, workers=1, progress=False, on_result=kill_a_worker)
    assert len(killed) == 1 and s.pool_restarts == 1
    assert (s.total, s.ran, s.skipped) == (6, 6, 0)
    with TrialStore(db) as store:
        assert store.count() == 6 and store.integrity_ok()
    assert multiprocessing.active_children() == []


@pytest.mark.e2e  # worker processes killed until the sweep gives up
def test_workers_dying_every_time_abort_cleanly_with_rows_kept(tmp_path, monkeypatch):
    monkeypatch.setattr(sweep_mod, "MAX_POOL_RESTARTS", 1)
    db = tmp_path / "abort.sqlite"
    specs = sweep_specs((74, 76), (30,), (0.1,), trials=4, **SHORT)
    stored = []

    def kill_every_worker(row):
        stored.append(row["trial"])
        for worker in multiprocessing.active_children():
            os.kill(worker.pid, signal.SIGKILL)

    with pytest.raises(SweepAborted, match=r"died 2 times.*trials in .* are kept: rerun the same sweep"):
        run_sweep(specs, db=db, workers=1, progress=False, on_result=kill_every_worker)
    with TrialStore(db) as store:
        assert store.count() == len(stored) >= 2
    assert multiprocessing.active_children() == []
    s = run_sweep(specs, db=db, workers=1, progress=False)  # resumes
    assert s.skipped == len(stored) and s.ran == 8 - len(stored)


KILL_SCRIPT = """
import multiprocessing, sys
from multiprocessing import resource_tracker
from sim.sweep import run_sweep, sweep_specs


def report(row):
    pids = [p.pid for p in multiprocessing.active_children()] + [resource_tracker._resource_tracker._pid]
    print("pids", *pids, flush=True)


if __name__ == "__main__":
    specs = sweep_specs((74, 76), (30,), (0.1,), trials=20, duration_s=0.3, dt_s=1e-3)
    run_sweep(specs, db=sys.argv[1], workers=2, progress=False, on_result=report)
"""


def test_workers_exit_when_the_sweep_is_killed(tmp_path):
    script = tmp_path / "kill_me.py"
    script.write_text(KILL_SCRIPT)
    env = {**os.environ, "PYTHONPATH": str(REPO)}
    p = subprocess.Popen(
        [sys.executable, str(script), str(tmp_path / "k.sqlite")],
        stdout=subprocess.PIPE,
        stderr=subprocess.DEVNULL,
        text=True,
        env=env,
        start_new_session=True,
    )
    try:
        line = p.stdout.readline()
        assert line.startswith("pids"), line
        pids = [int(x) for x in line.split()[1:]]
        assert len(pids) == 3 and p.pid not in pids  # two workers and the resource tracker
        os.kill(p.pid, signal.SIGKILL)  # the sweep only: no cleanup code runs
        p.wait(timeout=30)
        deadline = time.time() + 10.0
        while time.time() < deadline and not all(_gone(pid) for pid in pids):
            time.sleep(0.2)
        assert [pid for pid in pids if not _gone(pid)] == []
    finally:
        p.stdout.close()
        try:
            os.killpg(p.pid, signal.SIGKILL)  # whatever is left of the session
        except ProcessLookupError:
            pass
        p.wait(timeout=30)
