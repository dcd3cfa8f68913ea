"""Writing results to files people can open: JSON, NPZ, CSV. (Edge layer: the only landscape code touching disk.)"""

from __future__ import annotations

import csv
import json
import re
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:  # annotations only: writing JSON loads neither the numerics nor the engine
    from landscape.computation import BarrierMap, Computation

MJ = 1e3


def barrier_fields(b) -> dict:
    """Flat barrier fields (J, degrees) of a Barrier (:func:`landscape.computation.barrier_fields`)."""
    from landscape.computation import barrier_fields as fields

    return fields(b)


EXITS = ("righting", "pitch_wise", "roll_wise", "escape")


def gradient_columns(c: Computation) -> dict:
    """Each exit's first-order change as flat columns (SI: J/m, J/kg, J/deg): ``<exit>_com_{x,y,z}_j_per_m``,
    ``<exit>_mass_j_per_kg``, ``<exit>_theta_{w,l}_j_per_deg`` (empty where it does not exist),
    ``<exit>_differentiable`` and ``<exit>_reason``; with intervals also ``<exit>_first_order_{low,high}_j`` and
    ``<exit>_monte_carlo_{low,high}_j``."""
    out = {}
    for name in EXITS:
        g = c.gradient.get(name)
        com = None if g is None or g.com_j_per_m is None else g.com_j_per_m
        for i, axis in enumerate("xyz"):
            out[f"{name}_com_{axis}_j_per_m"] = None if com is None else float(com[i])
        out[f"{name}_mass_j_per_kg"] = None if g is None else g.mass_j_per_kg
        out[f"{name}_theta_w_j_per_deg"] = None if g is None else g.theta_w_j_per_deg
        out[f"{name}_theta_l_j_per_deg"] = None if g is None else g.theta_l_j_per_deg
        out[f"{name}_differentiable"] = None if g is None else g.differentiable
        out[f"{name}_reason"] = None if g is None else g.reason
    if c.intervals is not None:
        for name in EXITS:
            x = c.intervals.exits.get(name)
            for kind in ("first_order", "monte_carlo"):
                band = None if x is None else getattr(x, f"{kind}_j")
                out[f"{name}_{kind}_low_j"] = None if band is None else band[0]
                out[f"{name}_{kind}_high_j"] = None if band is None else band[1]
    return out


def barrier_map_rows(bm: BarrierMap) -> list[dict]:
    """One row per pose of a barrier map: the angles, the start minimum, :func:`barrier_fields` and
    :func:`gradient_columns`."""
    return [
        {
            "theta_w_deg": c.theta_w_deg,
            "theta_l_deg": c.theta_l_deg,
            "min_pitch_deg": c.minimum.pitch_deg,
            "min_roll_deg": c.minimum.roll_deg,
            "min_energy_j": c.minimum.energy_j,
            **barrier_fields(c.barrier),
            **gradient_columns(c),
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
    d = c.to_dict(paths=True)
    out = {
        "robot": {
            "name": robot_name,
            "source": robot_source,
            "robot_hash": robot_hash,
            "description_hash": description_hash or robot_hash,
        }
    }
    for k, v in d.items():
        out[k] = v
        if k == "com_m":
            out["com_source"] = com_source
    return out


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


CSV_DECIMALS = {"_j": 9, "_deg": 6}
"""Decimals a CSV column keeps, by its unit suffix: energies to 1e-9 J, angles to 1e-6 degrees. Reruns on two
machines differ by floating-point rounding only (about 1e-16 J and 1e-12 degrees), far below these digits, so a
rerun writes the same bytes."""
CSV_RATE_DIGITS = 9
"""Significant digits of a rate column (a unit suffix ``*_per_*``: a gradient in J/m, J/kg or J/deg), whose
scale varies too much between columns for fixed decimals; below 1e-12 of its unit a rate is written as 0 (a
rounding residue of an exact zero)."""
_RATE = re.compile(r"_per_[a-z0-9]+$")


def _rounded(key: str, value):
    """``value`` rounded as ``key``'s unit suffix says (:data:`CSV_DECIMALS`, :data:`CSV_RATE_DIGITS`); -0.0
    becomes 0.0."""
    if not (isinstance(value, (float, np.floating)) and np.isfinite(value)):
        return value
    if _RATE.search(key):
        return float(f"{round(float(value), 12):.{CSV_RATE_DIGITS}g}") + 0.0
    for suffix, decimals in CSV_DECIMALS.items():
        if key.endswith(suffix):
            return round(float(value), decimals) + 0.0
    return value


def write_rows_csv(rows: list[dict], path: Path) -> Path:
    """Write a list of flat dicts as CSV with a header, each number in a ``*_j`` or ``*_deg`` column rounded to
    :data:`CSV_DECIMALS`, each in a rate column (``*_per_*``) to :data:`CSV_RATE_DIGITS` significant digits.

    Examples
    --------
    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     row = {"theta_w_deg": 74.00000000001, "righting_j": 0.0086885123456, "righting_theta_w_j_per_deg":
    ...            -0.0017912345678912, "n": 3}
    ...     print(write_rows_csv([row], Path(d) / "t.csv").read_text(), end="")
    theta_w_deg,righting_j,righting_theta_w_j_per_deg,n
    74.0,0.008688512,-0.00179123457,3
    """
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows({k: _rounded(k, v) for k, v in row.items()} for row in rows)
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
