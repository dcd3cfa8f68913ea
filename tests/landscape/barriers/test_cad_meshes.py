"""The exact method on CAD-like meshes: finely triangulated flat faces, rounding noise, any CoM inside.

Each family and its reference (closed form or clean twin) and the bound every error must stay within are
defined once, in ``benchmarks/accuracy.py`` (``cad_case``, ``cad_check``), whose ``--cad`` table reports the
same checks over seeded draws.
"""

import json

import numpy as np
import pytest
import trimesh
from hypothesis import example, given, settings
from hypothesis import strategies as st

from landscape.cli import main
from tests.conftest import load_script

ACC = load_script("benchmarks/accuracy.py")

# the plate of the report: 0.4 x 0.3 x 0.02 m, every face 512 coplanar triangles, CoM (0.03, 0.02, 0.001) m
PLATE_COM_M = (0.03, 0.02, 0.001)
PLATE_LIFT_M = np.hypot(0.15 - 0.02, 0.01 + 0.001) - 0.011  # over the long edge nearest the CoM


def _plate_obj(path, seed: int, noise_m: float = 1e-12):
    mesh = trimesh.creation.box(extents=[0.4, 0.3, 0.02])
    for _ in range(4):
        mesh = mesh.subdivide()
    v = mesh.vertices + np.random.default_rng(seed).uniform(-noise_m, noise_m, mesh.vertices.shape)
    with open(path, "w") as f:
        f.writelines(f"v {x:.17g} {y:.17g} {z:.17g}\n" for x, y, z in v)
        f.writelines(f"f {a} {b} {c}\n" for a, b, c in mesh.faces + 1)
    return path


@pytest.mark.parametrize("seed", range(1, 25))
def test_the_reported_plate_rights_over_its_long_edge_for_every_seed(capsys, tmp_path, seed):
    """The report's recipe: 20 of these 24 seeds raised an internal error before facets were merged."""
    obj = _plate_obj(tmp_path / "plate.obj", seed)
    code = main(
        ["compute", "--mesh", str(obj), "--mass", "1.5", "--com=0.03,0.02,0.001", "--start-pitch=0",
         "--start-roll=0", "--json"]
    )  # fmt: skip
    out, err = capsys.readouterr()
    assert code == 0, err
    s = json.loads(out)
    lift_m = s["barrier"]["righting_j"] / (1.5 * 9.81)
    assert lift_m == pytest.approx(PLATE_LIFT_M, rel=1e-6, abs=1e-11)
    # the saddle: rolled about the long edge toward +y, up-direction from the edge to the CoM
    assert s["barrier"]["saddle_pitch_deg"] == pytest.approx(0.0, abs=1e-6)
    assert s["barrier"]["saddle_roll_deg"] == pytest.approx(-np.degrees(np.arctan2(0.13, 0.011)), abs=1e-6)


@settings(max_examples=60, deadline=None)
@given(
    family=st.sampled_from(ACC.CAD_FAMILIES),
    subdivisions=st.integers(0, 5),
    sections=st.sampled_from([3, 4, 6, 8, 16, 32, 64]),
    noise_exp=st.floats(-13.0, -7.0),
    com_frac=st.tuples(*[st.floats(-1.0, 1.0)] * 3),
    seed=st.integers(0, 2**31 - 1),
)
@example(family="plate", subdivisions=4, sections=8, noise_exp=-12.3, com_frac=(0.1, 0.1, 0.1), seed=2)
@example(family="box", subdivisions=5, sections=8, noise_exp=-7.0, com_frac=(0.9, -0.9, 0.9), seed=3)
@example(family="prism", subdivisions=3, sections=6, noise_exp=-8.7, com_frac=(0.5, 0.5, 0.2), seed=5)
@example(family="capsule", subdivisions=0, sections=64, noise_exp=-12.0, com_frac=(0.7, -0.1, -0.9), seed=1)
@example(family="cylinder", subdivisions=0, sections=12, noise_exp=-7.8, com_frac=(0.03, 0.6, -0.95), seed=7)
def test_cad_like_bodies_match_their_reference_within_the_stated_bound(
    family, subdivisions, sections, noise_exp, com_frac, seed
):
    """No internal error; righting and escape barriers and saddles within the bound ``cad_check`` states, for
    boxes, plates and prisms subdivided 0-5 times, cylinders and capsules, noise 1e-13 to 1e-7 of the size."""
    if family == "prism":
        sections = min(sections, 6)
    case = ACC.cad_case(
        family,
        subdivisions=subdivisions,
        sections=sections,
        noise_rel=10.0**noise_exp,
        com_frac=com_frac,
        seed=seed,
    )
    res = ACC.cad_check(case)
    assert res["error"] is None, case.label
    assert res["barrier_ratio"] <= 1.0, (case.label, res)
    assert res["saddle_ratio"] <= 1.0, (case.label, res)


def test_the_check_fails_a_wrong_answer():
    """The bound is tight enough to catch an error of a tenth of a millimetre of lift on the plate."""
    case = ACC.cad_case(
        "plate", subdivisions=0, sections=8, noise_rel=1e-13, com_frac=(0.1, 0.1, 0.1), seed=0
    )
    bad = case._replace(closed=(case.closed[0] + 1.5 * 9.81 * 1e-4, case.closed[1]))
    assert ACC.cad_check(case)["barrier_ratio"] <= 1.0 < ACC.cad_check(bad)["barrier_ratio"]
