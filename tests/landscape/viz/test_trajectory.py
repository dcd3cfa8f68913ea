"""Trajectories on the landscape: paths laid on the torus, trace files read and checked, the figures drawn."""

import contextlib
import io
import re
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

pytest.importorskip("pybullet")

import landscape  # noqa: E402
from geometry.robots import load_robot  # noqa: E402
from landscape.cli import main  # noqa: E402
from landscape.cli.sim import write_trace_csv  # noqa: E402
from landscape.viz import render as rd  # noqa: E402
from landscape.viz import trajectory as tj  # noqa: E402
from sim.trial import run_trial  # noqa: E402

SHARED = Path(__file__).resolve().parents[3].parent / "shared"
LAB_URDF = SHARED / "ref" / "lab_robot" / "lab_robot.urdf"


def invoke(*args):
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main([str(a) for a in args])
    return SimpleNamespace(exit_code=code, stdout=out.getvalue(), stderr=err.getvalue())


@pytest.fixture(scope="module")
def trials():
    """Two short built-in trials at (74, 30): one that rights, one that does not."""
    ok = run_trial(74.0, 30.0, phase=0.1, cv=0.1, rng=1, duration_s=2.0, trace=True)
    no = run_trial(74.0, 30.0, phase=0.9, cv=0.0, rng=4, duration_s=1.5, trace=True)
    assert ok.success and not no.success
    return ok, no


def _write(r, path, notes=True):
    meta = (
        tj.trace_meta_lines(
            robot_hash=r.robot_hash, theta_w_deg=r.theta_w_deg, theta_l_deg=r.theta_l_deg, righted=r.success
        )
        if notes
        else ()
    )
    return write_trace_csv(r.trace, path, tuple(meta))


# ------------------------------------------------------------------------------------------------ paths
def test_path_across_the_roll_seam_is_broken_not_drawn_across():
    roll = np.array([150.0, 170.0, 179.0, -172.0, -160.0])
    path = tj.attempt_path_deg(np.zeros(5), roll)
    assert np.isnan(path[3]).all() and len(path) == 6
    finite = path[np.isfinite(path[:, 0])]
    # the drawn pieces never jump further than the data did (11 deg across the seam)
    assert np.abs(np.diff(path, axis=0)[np.isfinite(np.diff(path, axis=0)[:, 1]), 1]).max() <= 20.0
    np.testing.assert_allclose(finite[:, 1], [150.0, 170.0, 179.0, -172.0, -160.0])


def test_path_through_pitch_90_stays_on_one_copy_and_starts_near_the_start():
    # a trace reports |pitch| <= 90: going over pitch 90 it turns round and its roll jumps by 180
    path = tj.attempt_path_deg(
        [60.0, 85.0, 85.0, 60.0], [10.0, 10.0, -170.0, -170.0], start_near_deg=(70.0, 0.0)
    )
    np.testing.assert_allclose(path, [[60.0, 10.0], [85.0, 10.0], [95.0, 10.0], [120.0, 10.0]])
    # started near the twin (120, -170) of (60, 10), the same motion is drawn on the other copy
    other = tj.attempt_path_deg([60.0, 85.0], [10.0, 10.0], start_near_deg=(115.0, -175.0))
    np.testing.assert_allclose(other, [[120.0, -170.0], [95.0, -170.0]])


def test_contour_svg_draws_a_seam_crossing_path_in_two_pieces(tmp_path):
    p = np.linspace(-180, 180, 37)
    energy = 1e-3 * (2 + np.cos(np.deg2rad(p))[:, None] + np.cos(np.deg2rad(p))[None, :])
    path = tj.attempt_path_deg(np.full(20, 30.0), np.linspace(120.0, 230.0, 20))
    svg = tj.render_trajectories_contour(energy, p, p, tmp_path / "t.svg", paths_deg=[path], righted=[True])
    text = svg.read_text()
    group = re.search(r'<g id="attempt-1-righted">(.*?)</g>', text, re.S).group(1)
    d = re.search(r' d="([^"]+)"', group).group(1)
    pieces = [
        np.array([float(v) for v in re.findall(r"[-\d.]+", piece)]).reshape(-1, 2)
        for piece in d.split("M")[1:]
    ]
    assert len(pieces) == 2  # one on each side of the seam
    steps = [np.hypot(*np.diff(q, axis=0).T) for q in pieces]
    typical = float(np.median(np.concatenate(steps)))
    # every stroke is one data step long; the 306-pixel move across the plot is a move, not a line
    assert all(st.max() < 1.5 * typical for st in steps)
    assert abs(pieces[1][0, 1] - pieces[0][-1, 1]) > 40 * typical


# ------------------------------------------------------------------------------------------------ trace files
def test_trace_file_round_trip_and_rule_without_notes(trials, tmp_path):
    for r in trials:
        t = tj.read_trace_csv(_write(r, tmp_path / "n.csv"))
        assert (t.robot_hash, t.theta_w_deg, t.theta_l_deg, t.righted) == (
            r.robot_hash,
            74.0,
            30.0,
            r.success,
        )
        np.testing.assert_allclose(t.pitch_deg, r.trace.pitch_deg, rtol=1e-8)
        bare = tj.read_trace_csv(_write(r, tmp_path / "b.csv", notes=False))
        # without notes: the pose from the largest commands, the outcome from the trial's own rule
        assert (bare.robot_hash, bare.theta_w_deg, bare.theta_l_deg, bare.righted) == (
            None,
            74.0,
            30.0,
            r.success,
        )
    robot = load_robot()
    mass = sum(p.mass.mass_kg for p in robot.parts)
    assert t.mass_kg == pytest.approx(mass, rel=1e-6)


def test_trace_of_another_robot_is_refused(trials, tmp_path):
    r = trials[0]
    t = tj.read_trace_csv(_write(r, tmp_path / "t.csv"))
    with pytest.raises(tj.TraceFileError, match="another robot"):
        tj.check_trace_robot(t, robot_hash="0" * 16, mass_kg=t.mass_kg, robot_name="x")
    a = np.loadtxt(_write(r, tmp_path / "heavy.csv", notes=False), delimiter=",", skiprows=1)
    a[:, 5] *= 1.5  # a 390 g robot's energies at the same heights
    np.savetxt(tmp_path / "heavy.csv", a, delimiter=",", header=",".join(r.trace.COLUMNS), comments="")
    heavy = tj.read_trace_csv(tmp_path / "heavy.csv")
    with pytest.raises(tj.TraceFileError, match="mass of 39"):
        tj.check_trace_robot(heavy, robot_hash=r.robot_hash, mass_kg=t.mass_kg, robot_name="x")


@pytest.mark.parametrize(
    "text, match", [("a,b\n1,2\n", "not a trial trace"), ("", "not a trial trace"), (None, "not found")]
)
def test_bad_trace_files(tmp_path, text, match):
    f = tmp_path / "x.csv"
    if text is not None:
        f.write_text(text)
    with pytest.raises(tj.TraceFileError, match=match):
        tj.read_trace_csv(f)


# ------------------------------------------------------------------------------------------------ figures
def _colour_pixels(img, hex_colour, tol=30):
    rgb = np.array([int(hex_colour[i : i + 2], 16) for i in (1, 3, 5)])
    return int((np.abs(img[:, :, :3].astype(int) - rgb).max(axis=2) <= tol).sum())


def test_figures_exist_with_their_size_and_show_both_outcomes(trials, tmp_path):
    import matplotlib.image as mpimg

    c = landscape.compute(load_robot(), theta_w_deg=74.0, theta_l_deg=30.0, step_deg=3.0)
    paths = [np.column_stack([r.trace.pitch_deg, r.trace.roll_deg]) for r in trials]
    problem = rd.off_screen_problem()
    try:
        written = tj.render_trajectories(
            c, paths, [r.success for r in trials], tmp_path, robot_name="builtin"
        )
    except tj.UsageError:
        if problem is None:
            raise
        written = [tmp_path / "trajectories_contour.png"]
    img = mpimg.imread(written[0])
    assert img.shape[:2] == (780, 960)
    img8 = (img * 255).astype(np.uint8)
    assert img8[:, :, :3].std() > 30
    assert _colour_pixels(img8, tj.RIGHTED_COLOUR) > 100
    assert _colour_pixels(img8, tj.NOT_RIGHTED_COLOUR, tol=8) > 100
    if problem is not None:
        pytest.skip(problem)
    img3 = mpimg.imread(tmp_path / "trajectories.png")
    assert img3.shape[:2] == (960, 1280)
    img3 = (img3 * 255).astype(np.uint8)
    assert img3[:, :, :3].std() > 30 and _colour_pixels(img3, tj.RIGHTED_COLOUR) > 100


# ------------------------------------------------------------------------------------------------ command line
@pytest.mark.e2e  # simulates and renders a traced trial
def test_render_trace_command_and_its_bad_input(trials, tmp_path):
    ok = _write(trials[0], tmp_path / "ok.csv")
    r = invoke("render", "--trace", tmp_path / "missing.csv", "--out", tmp_path / "o")
    assert (r.exit_code, r.stderr.count("\n")) == (2, 1) and "not found" in r.stderr
    r = invoke("render", "--trace", ok, "--theta-w", 70, "--out", tmp_path / "o")
    assert (r.exit_code, r.stderr.count("\n")) == (2, 1) and "ran at 74" in r.stderr
    f = tmp_path / "other.csv"
    f.write_text(ok.read_text().replace(f"robot_hash={trials[0].robot_hash}", "robot_hash=0123456789abcdef"))
    r = invoke("render", "--trace", f, "--step", 5, "--out", tmp_path / "o")
    assert (r.exit_code, r.stderr.count("\n")) == (2, 1) and "another robot" in r.stderr
    if rd.off_screen_problem() is not None:
        pytest.skip(rd.off_screen_problem())
    r = invoke(
        "render",
        "--trace",
        ok,
        "--trace",
        _write(trials[1], tmp_path / "no.csv"),
        "--step",
        5,
        "--out",
        tmp_path / "o",
    )
    assert r.exit_code == 0, r.stderr
    for name in ("trajectories.png", "trajectories_contour.png", "trajectories_contour.svg", "landscape.png"):
        assert name in r.stdout and (tmp_path / "o" / name).stat().st_size > 10_000


@pytest.mark.shared
@pytest.mark.skipif(not LAB_URDF.is_file(), reason="../shared/ref/lab_robot is absent")
def test_lab_robot_trace_on_the_builtin_landscape_is_refused(tmp_path):
    r = run_trial(74.0, 30.0, phase=0.7, cv=0.0, rng=1, duration_s=0.3, robot=LAB_URDF, dt_s=5e-4, trace=True)
    res = invoke("render", "--trace", _write(r, tmp_path / "lab.csv"), "--step", 5, "--out", tmp_path / "o")
    assert (res.exit_code, res.stderr.count("\n")) == (2, 1) and "another robot" in res.stderr


# ------------------------------------------------------------------------------------------------ physical robot
from tests.conftest import SHARED as CONF_SHARED  # noqa: E402

PHYSICAL = CONF_SHARED / "ref" / "physical_robot"
CONF_LAB_URDF = CONF_SHARED / "ref" / "lab_robot" / "lab_robot.urdf"


def test_render_physical_bad_input_is_one_line(tmp_path):
    r = invoke("render", "--physical", tmp_path / "absent", "--out", tmp_path / "o")
    assert (r.exit_code, r.stderr.count("\n")) == (2, 1) and "does not exist" in r.stderr
    r = invoke("render", "--physical", tmp_path, "--trace", tmp_path / "t.csv", "--out", tmp_path / "o")
    assert (r.exit_code, r.stderr.count("\n")) == (2, 1) and "not both" in r.stderr


@pytest.mark.shared
@pytest.mark.skipif(
    not (PHYSICAL / "robot_attempts.mat").is_file() or not CONF_LAB_URDF.is_file(),
    reason="../shared/ref/physical_robot or lab_robot is absent",
)
def test_render_physical_draws_every_recorded_attempt_of_the_wing_angle(tmp_path):
    from landscape.analysis.physical.attempts import physical_attempts

    r = invoke(
        "render", "--physical", PHYSICAL, "--theta-w", 70, "--robot", CONF_LAB_URDF, "--out", tmp_path / "o"
    )
    assert (r.exit_code, r.stderr.count("\n")) == (2, 1) and "ran at 60, 75, 90" in r.stderr
    attempts = physical_attempts(PHYSICAL, theta_w_cmd_deg=90.0, theta_l_deg=0.0)  # the default leg: still
    n_ok = sum(a.righted for a in attempts)
    assert 0 < n_ok < len(attempts)  # both colours are drawn
    if rd.off_screen_problem() is not None:
        pytest.skip(rd.off_screen_problem())
    out = tmp_path / "o"
    r = invoke(
        "render", "--physical", PHYSICAL, "--theta-w", 90, "--robot", CONF_LAB_URDF, "--step", 5, "--out", out
    )
    assert r.exit_code == 0, r.stderr
    assert (
        f"wing 90° (measured plateau 82.1°), leg 0°: {len(attempts)} attempts of 5 trials, {n_ok} righted"
        in (r.stdout)
    )
    svg = (out / "trajectories_contour.svg").read_text()
    assert len(re.findall(r'id="attempt-\d+-righted"', svg)) == n_ok
    assert len(re.findall(r'id="attempt-\d+-not-righted"', svg)) == len(attempts) - n_ok
    assert f"{len(attempts)} physical attempts: {n_ok} righted" in svg
    assert "wing 82.1°" in svg  # the landscape of the measured plateau
    assert (out / "trajectories.png").stat().st_size > 10_000
