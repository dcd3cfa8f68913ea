"""A barrier map's start minima and barriers equal those of the code before issue #12's map speed-up.

barrier_map_reference.json holds, for the built-in robot (theta_w -10..90 at 5 deg, theta_l 0 and 30) and the
lab robot (theta_w -10..90 at 2.5 deg, theta_l 0), every pose's start minimum and its righting, pitch-wise,
roll-wise and escape exits (barrier, saddle, direction) as ``barrier_map(..., method="exact")`` computed them at
commit bd6cd45 (before the compiled searches, batched path pieces and worker processes), except 21 of the
built-in robot's saddles, replaced by their mirror images (roll sign) when the exact method's tie rule between
equal saddles came in (issue #12; their energies unchanged), 9 more at theta_l 0, where the built-in robot is
mirror-symmetric, reported at positive roll by ``landscape.computation.positive_roll_twins`` (the tie rule between
mirror saddles; energies unchanged), and three rows rewritten when the exact method began merging facets within
its length tolerance (issue #31): the built-in robot at theta_w 65 (theta_l 0 and 30), whose resting face and
every barrier above it moved by 1.2e-7 J (5e-8 m of CoM height, within the tolerance), and the lab robot's
righting saddle at theta_w 0, which moved 0.14 deg along a ridge at the same energy. The map must give the same numbers to 1e-12 J
(barriers, energies) and 1e-9 deg (angles) in this process and over worker processes.
"""

import json
from pathlib import Path

import numpy as np
import pytest

from geometry.errors import UsageError
from geometry.robots import load_robot
from landscape.computation import barrier_map, map_workers
from tests.conftest import HAVE_LAB, LAB_ABSENT, LAB_URDF

REFERENCE = json.loads((Path(__file__).with_name("barrier_map_reference.json")).read_text())
EXITS = ("righting", "pitch_wise", "roll_wise", "escape")


def _assert_equal_to_reference(bm, ref):
    assert [(c.theta_w_deg, c.theta_l_deg) for c in bm.computations] == [
        (r["theta_w_deg"], r["theta_l_deg"]) for r in ref["rows"]
    ]
    for c, r in zip(bm.computations, ref["rows"], strict=True):
        where = f"theta_w {c.theta_w_deg}, theta_l {c.theta_l_deg}"
        assert c.minimum.energy_j == pytest.approx(r["min_energy_j"], abs=1e-12), where
        assert c.minimum.pitch_deg == pytest.approx(r["min_pitch_deg"], abs=1e-9), where
        assert c.minimum.roll_deg == pytest.approx(r["min_roll_deg"], abs=1e-9), where
        for k in EXITS:
            x, want = getattr(c.barrier, k), r[k]
            assert (x is None) == (want is None), (where, k)
            if x is None:
                continue
            assert x.barrier_j == pytest.approx(want[0], abs=1e-12), (where, k)
            assert (x.saddle_pitch_deg, x.saddle_roll_deg) == pytest.approx(want[1:3], abs=1e-9), (where, k)
            assert x.direction == want[3], (where, k)
    righting = np.array([np.nan if r["righting"] is None else r["righting"][0] for r in ref["rows"]])
    np.testing.assert_allclose(bm.righting_j.ravel(), righting, rtol=0, atol=1e-12)


@pytest.mark.parametrize("workers", [1, 2])
def test_builtin_map_equals_reference(workers):
    ref = REFERENCE["builtin"]
    calls = []
    bm = barrier_map(
        load_robot(None),
        ref["theta_w_deg"],
        ref["theta_l_deg"],
        method="exact",
        workers=workers,
        progress=calls.append,
    )
    assert calls == [1] * len(ref["rows"])
    assert bm.righting_j.shape == (len(ref["theta_w_deg"]), len(ref["theta_l_deg"]))
    _assert_equal_to_reference(bm, ref)


@pytest.mark.skipif(not HAVE_LAB, reason=LAB_ABSENT)
@pytest.mark.parametrize("workers", [1, 2])
def test_lab_map_equals_reference(workers):
    ref = REFERENCE["lab"]
    bm = barrier_map(
        load_robot(LAB_URDF), ref["theta_w_deg"], ref["theta_l_deg"], method="exact", workers=workers
    )
    _assert_equal_to_reference(bm, ref)


def test_workers_are_checked_and_capped():
    assert map_workers(3, 8) == 3
    assert map_workers(20, None) >= 1
    with pytest.raises(UsageError, match="workers must be a whole number >= 1"):
        barrier_map(load_robot(None), [0.0], [0.0], workers=0)


def test_joint_limits_are_checked_before_any_worker_starts():
    """A pose outside the joint limits is refused before any work, whatever the workers."""
    with pytest.raises(ValueError):
        barrier_map(load_robot(None), [0.0, 1e6], [0.0], workers=2)


def test_map_without_sector_exits_keeps_minima_righting_and_escape():
    """``sector_exits=False`` skips each pose's landscape grid: the pitch-wise and roll-wise exits are None and
    everything else equals the reference."""
    ref = REFERENCE["builtin"]
    rows = ref["rows"][::4]
    ws = sorted({r["theta_w_deg"] for r in rows})
    bm = barrier_map(load_robot(None), ws, [0.0], method="exact", workers=1, sector_exits=False)
    want = {(r["theta_w_deg"], r["theta_l_deg"]): r for r in ref["rows"]}
    for c in bm.computations:
        r = want[(c.theta_w_deg, c.theta_l_deg)]
        assert c.barrier.pitch_wise is None and c.barrier.roll_wise is None
        assert c.timing_s["landscape"] < 1e-3  # no grid was built
        assert c.minimum.energy_j == pytest.approx(r["min_energy_j"], abs=1e-12)
        for k in ("righting", "escape"):
            x = getattr(c.barrier, k)
            assert (x is None) == (r[k] is None)
            if x is not None:
                assert x.barrier_j == pytest.approx(r[k][0], abs=1e-12)
                assert (x.saddle_pitch_deg, x.saddle_roll_deg, x.direction) == (
                    pytest.approx(r[k][1], abs=1e-9),
                    pytest.approx(r[k][2], abs=1e-9),
                    r[k][3],
                )


def test_compute_without_grid():
    from landscape.computation import compute

    robot = load_robot(None)
    full = compute(robot, theta_w_deg=40.0, theta_l_deg=0.0)
    lean = compute(robot, theta_w_deg=40.0, theta_l_deg=0.0, landscape_grid=False)
    assert lean.landscape is None and full.landscape is not None
    assert lean.minimum == full.minimum
    assert lean.barrier.righting.barrier_j == full.barrier.righting.barrier_j
    assert lean.barrier.escape.barrier_j == full.barrier.escape.barrier_j
    assert lean.barrier.pitch_wise is None and full.barrier.pitch_wise is not None
    with pytest.raises(UsageError, match="searches the landscape grid"):
        compute(robot, theta_w_deg=40.0, theta_l_deg=0.0, method="grid", landscape_grid=False)
