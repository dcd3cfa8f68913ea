"""Barrier gradients and intervals on the command line: ``compute`` (table and ``--json``) and ``barrier-map``."""

from __future__ import annotations

import json

import numpy as np
import pytest

from landscape.cli import cli
from tests.conftest import csv_rows, run_cli

EXITS = ("righting", "pitch_wise", "roll_wise", "escape")
KEYS = {
    "com_j_per_m",
    "mass_j_per_kg",
    "theta_w_j_per_deg",
    "theta_l_j_per_deg",
    "differentiable",
    "reason",
    "one_sided_com_j_per_m",
    "reach_m",
}


def _json(capsys, *argv):
    code, out, err = run_cli(capsys, "compute", *argv, "--json")
    assert code == 0, err
    return json.loads(out)


def test_compute_json_has_every_exits_gradient_and_matches_to_dict(capsys):
    from geometry.robots import load_robot
    from landscape.computation import compute

    d = _json(capsys, "--theta-w", "74", "--theta-l", "30", "--step", "3")
    grad = d["barrier"]["gradient"]
    assert set(grad) == set(EXITS) and all(set(grad[k]) == KEYS for k in EXITS)
    r = grad["righting"]
    assert len(r["com_j_per_m"]) == 3 and r["differentiable"] and r["reason"] is None
    want = compute(load_robot(), theta_w_deg=74.0, theta_l_deg=30.0, step_deg=3.0).to_dict()
    assert grad == want["barrier"]["gradient"]


def test_compute_json_is_null_where_a_derivative_does_not_exist(capsys):
    """Leg at 0: mirror saddles, so no CoM gradient and no theta_l derivative, with the reason; theta_w has one."""
    r = _json(capsys, "--theta-w", "74", "--step", "3")["barrier"]["gradient"]["righting"]
    assert r["com_j_per_m"] is None and r["theta_l_j_per_deg"] is None and r["theta_w_j_per_deg"] < 0
    assert (
        r["differentiable"] is False and "2 saddles" in r["reason"] and len(r["one_sided_com_j_per_m"]) == 2
    )


def test_a_rigid_mesh_has_no_joint_derivatives(capsys, tmp_path):
    import trimesh

    trimesh.creation.box(extents=(0.1, 0.06, 0.02)).export(tmp_path / "box.stl")
    d = _json(capsys, "--mesh", tmp_path / "box.stl", "--com", "0,0.005,0", "--step", "5")
    r = d["barrier"]["gradient"]["righting"]
    assert r["theta_w_j_per_deg"] is None and r["theta_l_j_per_deg"] is None
    assert r["differentiable"] and len(r["com_j_per_m"]) == 3


def test_compute_table_prints_gradients_and_the_direction_that_lowers_the_barrier(capsys):
    code, out, err = run_cli(capsys, "compute", "--theta-w", "74", "--theta-l", "30", "--step", "3")
    assert code == 0, err
    lines = out.splitlines()
    head = next(i for i, x in enumerate(lines) if x.startswith("gradients"))
    assert "mJ per mm of CoM" in lines[head] and "per degree of theta_w, theta_l" in lines[head]
    assert [x.split()[0] for x in lines[head + 1 : head + 5]] == [
        "righting",
        "pitch-wise",
        "roll-wise",
        "escape",
    ]
    lower = next(x for x in lines if x.startswith("lower it"))
    d = [float(v) for v in lower.split("(")[1].split(")")[0].split(",")]
    assert np.linalg.norm(d) == pytest.approx(1.0, abs=2e-3) and "mJ per mm" in lower


def test_compute_intervals_are_labelled_and_in_the_json(capsys):
    argv = ("--theta-w", "74", "--theta-l", "30", "--step", "3", "--com-uncertainty", "1", "--samples", "4")
    code, out, err = run_cli(capsys, "compute", *argv)
    assert code == 0, err
    assert "first order: B -+" in out and "Monte-Carlo: lowest and highest barrier recomputed" in out
    assert "N = 4, r = 1 mm, seed 0" in out
    iv = _json(capsys, *argv)["barrier"]["interval"]
    assert iv["com_m"] == 0.001 and iv["samples"] == 4 and iv["seed"] == 0
    r = iv["righting"]
    assert r["first_order_j"][0] < r["first_order_j"][1] and r["monte_carlo_j"][0] < r["monte_carlo_j"][1]


@pytest.mark.parametrize(
    "argv, needle",
    [
        (["--com-uncertainty", "-1"], "--com-uncertainty -1 mm is outside [0, 50] mm"),
        (["--com-uncertainty", "nan"], "--com-uncertainty must be a finite number"),
        (["--com-uncertainty", "60"], "--com-uncertainty 60 mm is outside [0, 50] mm"),
        (["--mass-uncertainty", "-5"], "--mass-uncertainty -5 g is outside [0, 10000] g"),
        (["--mass-uncertainty", "inf"], "--mass-uncertainty must be a finite number"),
        (["--com-uncertainty", "1", "--samples", "0"], "--samples 0 is outside [1, 100000]"),
        (["--samples", "5"], "give --com-uncertainty MM (> 0) too"),
        (["--com-uncertainty", "1", "--seed", "-1"], "--seed -1 is outside"),
        (["--theta-w", "0", "--com-uncertainty", "20"], "only 17.9 mm inside its hull"),
        (["--mass-uncertainty", "300"], "is not below the mass (260 g)"),
    ],
)
def test_bad_uncertainties_get_one_line_and_exit_2(capsys, argv, needle):
    code, out, err = run_cli(capsys, "compute", "--theta-w", "74", "--step", "5", *argv)
    assert code == 2 and needle in err and len(err.strip().splitlines()) == 1, err
    assert "Traceback" not in err + out


@pytest.mark.parametrize("command", ["compute", "barrier-map"])
def test_uncertainty_options_state_their_ranges(command):
    params = {p.name: p for p in cli.commands[command].params}
    assert "[0, 50] mm" in params["com_uncertainty"].help
    assert "[0, 10000] g" in params["mass_uncertainty"].help
    assert "[1, 100000]" in params["samples"].help and "[0, 2^32 - 1]" in params["seed"].help


def test_barrier_map_writes_gradient_columns_and_bands(capsys, tmp_path):
    out = tmp_path / "bm"
    code, stdout, err = run_cli(
        capsys,
        "barrier-map",
        "--theta-w",
        "70,80",
        "--theta-l",
        "0,30",
        "--step",
        "3",
        "--com-uncertainty",
        "1",
        "--out",
        out,
    )
    assert code == 0, err
    rows = csv_rows(out / "barrier_map.csv")
    assert len(rows) == 4 and (out / "barrier_bands.png").stat().st_size > 10_000
    for key in ("righting_com_y_j_per_m", "escape_theta_w_j_per_deg", "righting_first_order_low_j"):
        assert key in rows[0]
    by = {(float(r["theta_w_deg"]), float(r["theta_l_deg"])): r for r in rows}
    sym, off = by[(70.0, 0.0)], by[(70.0, 30.0)]
    # the mirror-symmetric pose: no CoM gradient, the band from the Monte-Carlo recomputation
    assert sym["righting_differentiable"] == "False" and sym["righting_com_y_j_per_m"] == ""
    assert sym["righting_first_order_low_j"] == "" and float(sym["righting_monte_carlo_low_j"]) > 0
    assert off["righting_differentiable"] == "True" and float(off["righting_first_order_low_j"]) > 0
    assert "righting barrier not differentiable at 2 of 4 poses (band there: Monte-Carlo)" in stdout
    assert "(70°, 0°), (80°, 0°)" in stdout


def test_a_model_sets_com_change_to_first_order_and_recomputed(capsys):
    """physical-offset moves only the CoM (2 mm towards -y): recomputing with the CoM alone moved is the whole
    set's change. physical-head moves the head (13.4 g, 17 mm back) and with it the CoM: the whole set also
    changes the geometry, so its change differs from the CoM's alone. First order is the base's gradient times
    the CoM's move."""
    for name in ("physical-offset", "physical-head"):
        d = _json(capsys, "--theta-w", "75", "--step", "5", "--model", name)
        ch = d["model_set_change"]
        r = {k: ch[k]["righting"] for k in ("first_order_j", "com_only_j", "recomputed_j")}
        if name == "physical-offset":
            assert ch["com_m"] == pytest.approx([0.0, -0.002, 0.0], abs=1e-12)
            assert r["com_only_j"] == pytest.approx(r["recomputed_j"], abs=1e-12)
        else:
            assert ch["com_m"][0] < -5e-4 and abs(ch["com_m"][1]) < 1e-9
            assert abs(r["recomputed_j"] - r["com_only_j"]) > 10 * abs(r["com_only_j"])
        assert r["first_order_j"] is None or np.isfinite(r["first_order_j"])
    code, out, err = run_cli(capsys, "compute", "--theta-w", "75", "--step", "5", "--model", "physical-head")
    assert (
        code == 0 and "set change   physical-head moves the CoM by (" in out and "and a part with it" in out
    )
