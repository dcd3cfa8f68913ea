"""benchmarks/studies/engine_swap.py: the start variants place the robot where they say, in both engines, and the
study prints its table end to end on two attempts."""

import numpy as np
import pytest

from tests.conftest import load_script

pytest.importorskip("pybullet")
pytest.importorskip("mujoco")


def test_the_start_variants_place_the_hull_where_they_say():
    bench = load_script("benchmarks/studies/engine_swap.py")
    from sim.engine import open_world
    from sim.model import sim_model

    drop = bench.pybullet_drop_m()
    assert (
        0.02 < drop < 0.06
    )  # pybullet's bounding boxes (with its collision margin) leave the hull this high
    model = sim_model()
    pose = dict(pitch_rad=np.deg2rad(model.rest_pitch_deg), roll_rad=0.0, joints_rad=np.zeros(5))
    try:
        bench._patch_place(bench.HULL_CLEARANCE_M)
        with open_world("pybullet", model, dt_s=1.25e-4) as w:
            w.place(**pose)
            assert bench.hull_gap_m(w) == pytest.approx(bench.HULL_CLEARANCE_M, abs=1e-6)
        bench._patch_place(drop)
        with open_world("mujoco", model, dt_s=1.25e-4) as w:
            w.place(**pose)
            assert w._lowest_z() == pytest.approx(drop, abs=1e-9)
    finally:
        bench._patch_place(None)
    with open_world("pybullet", model, dt_s=1.25e-4) as w:  # undone: pybullet's own placement again
        w.place(**pose)
        assert bench.hull_gap_m(w) == pytest.approx(drop, abs=1e-6)


@pytest.mark.e2e  # the whole study on two attempts: 24 trials, about 25 s
def test_the_study_prints_its_table(capsys):
    bench = load_script("benchmarks/studies/engine_swap.py")
    assert bench.main(["--limit", "2", "--workers", "1", "--no-quarter"]) == 0
    out = capsys.readouterr().out
    assert "2 of the borderline single attempts" in out
    rows = [line for line in out.splitlines() if line.startswith("| ") and "variant" not in line]
    assert len(rows) == len(bench.variants(0.038, quarter=False))
    assert "| pybullet default | - |" in out and out.count("| 2/2 | 2/2 |") >= 1
    assert bench.main(["--limit", "0"]) == 2
