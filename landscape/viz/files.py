"""Writing results to files people can open: JSON, NPZ, CSV. (Edge layer: the only landscape code touching disk.)"""

from __future__ import annotations

import csv
import json
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:  # annotations only: writing JSON loads neither the numerics nor the engine
    from landscape.barriers import Exit
    from landscape.computation import BarrierMap, Computation

MJ = 1e3


def _exit_dict(x: Exit | None) -> dict | None:
    if x is None:
        return None
    return {
        "barrier_j": x.barrier_j,
        "saddle_pitch_deg": x.saddle_pitch_deg,
        "saddle_roll_deg": x.saddle_roll_deg,
        "direction": x.direction,
        "path_deg": np.round(x.path_deg, 6).tolist(),
    }


def barrier_fields(b) -> dict:
    """Flat barrier fields (J, degrees) of a Barrier, as the JSON summary and the barrier-map CSV report them."""
    r = b.righting
    return {
        "righting_j": None if r is None else r.barrier_j,
        "escape_j": None if b.escape is None else b.escape.barrier_j,
        "saddle_pitch_deg": None if r is None else r.saddle_pitch_deg,
        "saddle_roll_deg": None if r is None else r.saddle_roll_deg,
        "direction": None if r is None else r.direction,
        "pitch_wise_j": None if b.pitch_wise is None else b.pitch_wise.barrier_j,
        "roll_wise_j": None if b.roll_wise is None else b.roll_wise.barrier_j,
        "escape_saddle_pitch_deg": None if b.escape is None else b.escape.saddle_pitch_deg,
        "escape_saddle_roll_deg": None if b.escape is None else b.escape.saddle_roll_deg,
        "escape_direction": None if b.escape is None else b.escape.direction,
    }


def barrier_map_rows(bm: BarrierMap) -> list[dict]:
    """One row per pose of a barrier map: the angles, the start minimum and :func:`barrier_fields`."""
    return [
        {
            "theta_w_deg": c.theta_w_deg,
            "theta_l_deg": c.theta_l_deg,
            "min_pitch_deg": c.minimum.pitch_deg,
            "min_roll_deg": c.minimum.roll_deg,
            "min_energy_j": c.minimum.energy_j,
            **barrier_fields(c.barrier),
        }
        for c in bm.computations
    ]


def summary(
    c: Computation,
    *,
    robot_name: str,
    robot_source: str | None,
    robot_hash: str,
    com_source: str = "",
    description_hash: str | None = None,
) -> dict:
    """The JSON summary of one computation (energies in J, angles in degrees, lengths in m).

    ``robot_hash`` identifies the robot and how its joints are driven (``Robot.robot_hash``);
    ``description_hash`` its files alone (``Robot.description_hash``; default: ``robot_hash``).
    """
    b = c.barrier
    return {
        "robot": {
            "name": robot_name,
            "source": robot_source,
            "robot_hash": robot_hash,
            "description_hash": description_hash or robot_hash,
        },
        "theta_w_deg": c.theta_w_deg,
        "theta_l_deg": c.theta_l_deg,
        "step_deg": c.step_deg,
        "method": c.method,
        "mass_kg": c.mass_kg,
        "com_m": [float(x) for x in c.com_m],
        "com_source": com_source,
        "start_deg": {"pitch_deg": c.start_deg[0], "roll_deg": c.start_deg[1]},
        "minimum": {
            "pitch_deg": c.minimum.pitch_deg,
            "roll_deg": c.minimum.roll_deg,
            "energy_j": c.minimum.energy_j,
            "height_m": c.minimum.height_m,
        },
        "barrier": barrier_fields(b),
        "paths": {k: _exit_dict(getattr(b, k)) for k in ("righting", "pitch_wise", "roll_wise", "escape")},
        "timing_s": {k: round(v, 6) for k, v in c.timing_s.items()},
    }


def write_computation(c: Computation, summary_dict: dict, out_dir: Path) -> list[Path]:
    """Write landscape.npz, landscape.csv and summary.json into ``out_dir``; return the paths."""
    out_dir.mkdir(parents=True, exist_ok=True)
    angles, energy = c.landscape.inclusive()
    npz = out_dir / "landscape.npz"
    np.savez_compressed(
        npz,
        pitch_deg=angles,
        roll_deg=angles,
        energy_j=energy,
        mass_kg=c.mass_kg,
        com_m=c.com_m,
        step_deg=c.step_deg,
        theta_w_deg=np.nan if c.theta_w_deg is None else c.theta_w_deg,
        theta_l_deg=np.nan if c.theta_l_deg is None else c.theta_l_deg,
        minimum_deg=np.array([c.minimum.pitch_deg, c.minimum.roll_deg]),
        righting_path_deg=np.zeros((0, 2)) if c.barrier.righting is None else c.barrier.righting.path_deg,
    )
    csv_path = out_dir / "landscape.csv"
    pp, rr = np.meshgrid(angles, angles, indexing="ij")
    table = np.column_stack([pp.ravel(), rr.ravel(), energy.ravel()])
    np.savetxt(
        csv_path,
        table,
        delimiter=",",
        header="pitch_deg,roll_deg,energy_j",
        comments="",
        fmt=["%.6g", "%.6g", "%.12g"],
    )
    js = out_dir / "summary.json"
    js.write_text(json_text(summary_dict, indent=2) + "\n")
    return [npz, csv_path, js]


def write_rows_csv(rows: list[dict], path: Path) -> Path:
    """Write a list of flat dicts as CSV with a header."""
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    return path


def finite_or_none(obj):
    """``obj`` with every non-finite float (NaN, inf) replaced by None, recursively through dicts, lists and
    tuples: strict JSON has no NaN or Infinity.

    Examples
    --------
    >>> finite_or_none({"a": float("nan"), "b": [1.0, float("inf")], "c": "x"})
    {'a': None, 'b': [1.0, None], 'c': 'x'}
    """
    if isinstance(obj, float):
        return obj if np.isfinite(obj) else None
    if isinstance(obj, dict):
        return {k: finite_or_none(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [finite_or_none(v) for v in obj]
    return obj


def json_text(obj, **kw) -> str:
    """Strict JSON of ``obj`` (non-finite numbers become null; never NaN or Infinity tokens)."""
    return json.dumps(finite_or_none(obj), allow_nan=False, **kw)
