"""Accuracy against time: grid barriers at shrinking steps (4- and 8-connected) and icosphere barriers at rising
levels, versus the exact method; and the exact method on CAD-like meshes (``--cad``).

For the lab robot (../shared/ref/lab_robot when present, else the built-in robot) at theta_w in {60, 74, 90} and
for closed-form shapes, prints a markdown table (method, time, righting and escape barriers, absolute and
relative error against exact) and writes a log-log plot of error against time.

    python benchmarks/accuracy.py [--out figures/accuracy.png] [--steps 4 2 1 0.5 0.25] [--repeat 3]

With ``--cad N`` it instead runs N seeded cases of each CAD-like family (:data:`CAD_FAMILIES`: boxes, plates
and prisms subdivided 0 to 5 times, cylinders and capsules at several tessellations, every vertex moved by
uniform noise of 1e-13 to 1e-7 of the size, a CoM anywhere inside) and prints one row per family: cases,
internal errors, the worst barrier and saddle errors against each case's reference (the closed form for
boxes and plates, the clean, undivided twin otherwise) as multiples of the bound :func:`cad_check` states, and
the time per case.

    python benchmarks/accuracy.py --cad 40 [--seed 0]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path
from typing import NamedTuple

import numpy as np
import trimesh

from geometry import Robot
from landscape.barriers.exact import exact_barrier
from landscape.barriers.grid import grid_barrier
from landscape.barriers.sphere import sphere_barrier, sphere_graph
from landscape.computation import start_orientation, warm_up
from landscape.energy import energy_landscape
from landscape.minima import grid_minimum

LAB_URDF = Path(__file__).resolve().parents[2] / "shared" / "ref" / "lab_robot" / "lab_robot.urdf"


def _lab_robot() -> tuple[str, Robot] | None:
    if LAB_URDF.is_file():
        return "lab robot", Robot.from_urdf(LAB_URDF)
    try:
        from geometry.builtin import load_builtin_robot  # type: ignore[import-not-found]
    except ImportError:
        return None
    return "built-in robot", load_builtin_robot()


def _cases():
    """(name, pose, start (pitch, roll) deg, closed-form righting barrier J or None)."""
    g = 9.81
    out = []
    lab = _lab_robot()
    if lab is not None:
        name, robot = lab
        for tw in (60.0, 74.0, 90.0):
            pose = robot.pose(tw, 0.0)
            out.append((f"{name} θw={tw:g}", pose, start_orientation(robot, pose, tw, 0.0), None))
    box = Robot.from_trimesh(trimesh.creation.box(extents=(0.3, 0.2, 0.1)), mass_kg=1.0, com=[0, 0, 0])
    out.append(("box 0.3x0.2x0.1", box.pose(), (0.0, 0.0), g * (np.hypot(0.1, 0.05) - 0.05)))
    cube = Robot.from_trimesh(trimesh.creation.box(extents=(0.2,) * 3), mass_kg=1.0, com=[0, 0, 0])
    out.append(("cube 0.2", cube.pose(), (0.0, 0.0), g * 0.1 * (np.sqrt(2) - 1)))
    plate = Robot.from_trimesh(trimesh.creation.box(extents=(0.3, 0.3, 0.01)), mass_kg=1.0, com=[0, 0, 0])
    out.append(("plate 0.3x0.3x0.01", plate.pose(), (0.0, 0.0), g * (np.hypot(0.15, 0.005) - 0.005)))
    skew = Robot.from_trimesh(
        trimesh.creation.box(extents=(0.3, 0.2, 0.1)), mass_kg=1.0, com=[0.03, 0.015, -0.02]
    )
    out.append(("box, off-centre CoM", skew.pose(), (0.0, 0.0), None))
    return out


def _timed(fn, repeat: int):
    best, out = np.inf, None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def _grid(pose, step, conn, start):
    ls = energy_landscape(pose, step_deg=step)
    return grid_barrier(ls, grid_minimum(ls, *start), connectivity=conn)


# ------------------------------------------------------------------------------------------ CAD-like meshes
CAD_FAMILIES = ("box", "plate", "prism", "cylinder", "capsule")
G_CAD = 9.81
MASS_CAD_KG = 1.5


class CadCase(NamedTuple):
    """One CAD-like body: the noisy mesh's pose, its clean twin's pose, and the closed-form righting exit.

    ``closed`` is (barrier J, saddle up-direction) for boxes and plates, else None; ``noise_m`` is the noise
    amplitude (each coordinate moved by at most this), ``size_m`` the body's diameter.
    """

    family: str
    label: str
    pose: object
    clean: object
    noise_m: float
    size_m: float
    closed: tuple | None


def _clean_mesh(family: str, dims: tuple[float, float, float], sections: int) -> trimesh.Trimesh:
    a, b, c = dims
    if family in ("box", "plate"):
        return trimesh.creation.box(extents=(a, b, c))
    if family == "prism":  # a triangular, square-less or hexagonal prism lying on a side face
        return trimesh.creation.cylinder(radius=b / 2, height=a, sections=sections, transform=_AXIS_X)
    if family == "cylinder":
        return trimesh.creation.cylinder(radius=b / 2, height=a, sections=sections, transform=_AXIS_X)
    if family == "capsule":
        return trimesh.creation.capsule(height=a, radius=b / 2, count=[sections, sections], transform=_AXIS_X)
    raise ValueError(f"unknown family {family!r}; choose one of {CAD_FAMILIES}")


_AXIS_X = np.array([[0.0, 0.0, 1.0, 0.0], [0.0, 1.0, 0.0, 0.0], [-1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]])


def cad_case(
    family: str,
    *,
    subdivisions: int,
    sections: int,
    noise_rel: float,
    com_frac: tuple[float, float, float],
    seed: int,
) -> CadCase:
    """A CAD-like body of ``family``: its flat faces subdivided, every vertex moved by uniform noise.

    Parameters
    ----------
    family : str
        One of :data:`CAD_FAMILIES`: box 0.4 x 0.3 x 0.2 m, plate 0.4 x 0.3 x 0.02 m, prism (``sections``
        sides, 0.4 m long, 0.3 m across), cylinder (``sections`` facets), capsule (``sections`` segments).
    subdivisions : int
        Times every triangle is split into four (boxes, plates, prisms), 0 to 5.
    sections : int
        Tessellation of prisms, cylinders and capsules.
    noise_rel : float
        Noise amplitude relative to the body's diameter (each coordinate moved by at most that).
    com_frac : tuple of 3 floats in [-1, 1]
        CoM as a fraction of the way from the centre to the hull along each axis (scaled into the hull).
    seed : int
        Seed of the noise.
    """
    dims = {"plate": (0.4, 0.3, 0.02)}.get(family, (0.4, 0.3, 0.2))
    mesh = _clean_mesh(family, dims, sections)
    if family in ("box", "plate", "prism"):
        for _ in range(subdivisions):
            mesh = mesh.subdivide()
    size = float(np.linalg.norm(mesh.extents))
    noise = noise_rel * size
    rng = np.random.default_rng(seed)
    noisy = mesh.vertices + rng.uniform(-noise, noise, mesh.vertices.shape)
    clean_pts = _clean_mesh(family, dims, sections).vertices
    # the CoM: com_frac of the way to the hull along each axis, shrunk to stay 5 % of the depth inside
    lo, hi = clean_pts.min(axis=0), clean_pts.max(axis=0)
    com = (lo + hi) / 2 + 0.9 * np.asarray(com_frac) * (hi - lo) / 2
    if family == "capsule":  # along the axis, within the cylindrical part
        com[0] = 0.9 * com_frac[0] * dims[0] / 2
    if family not in ("box", "plate"):  # round sections: keep the CoM inside the inscribed square
        com[1:] = (lo[1:] + hi[1:]) / 2 + 0.9 * np.asarray(com_frac[1:]) * (hi[1:] - lo[1:]) / 2 * np.cos(
            np.pi / max(sections, 3)
        ) / np.sqrt(2)
    pose = Robot.from_trimesh(
        trimesh.Trimesh(noisy, mesh.faces, process=False), mass_kg=MASS_CAD_KG, com=com.tolist()
    ).pose()
    clean = Robot.from_trimesh(
        _clean_mesh(family, dims, sections), mass_kg=MASS_CAD_KG, com=com.tolist()
    ).pose()
    closed = _box_righting(np.asarray(dims), com) if family in ("box", "plate") else None
    label = f"{family} subdiv {subdivisions} sections {sections} noise {noise_rel:.1e} com {np.round(com, 4).tolist()}"
    return CadCase(family, label, pose, clean, noise, size, closed)


def _box_righting(dims, com):
    """Closed form: a box resting on its bottom face (start up-direction +z) rights over the nearest of the four
    bottom edges; barrier m g (distance from the CoM to that edge - CoM height), saddle up = edge-to-CoM."""
    half = dims / 2
    h0 = com[2] + half[2]
    best = None
    for axis, sign in ((0, 1), (0, -1), (1, 1), (1, -1)):
        foot = com.copy()
        foot[axis], foot[2] = sign * half[axis], -half[2]
        w = com - foot
        lift = float(np.linalg.norm(w)) - h0
        if best is None or lift < best[0] - 1e-15:
            best = (lift, w / np.linalg.norm(w))
    return MASS_CAD_KG * G_CAD * best[0], best[1]


def _angle_rad(u, v) -> float:
    return float(np.arctan2(np.linalg.norm(np.cross(u, v)), np.dot(u, v)))


def cad_check(case: CadCase) -> dict:
    """The exact method on a CAD-like case against its reference, with the bound each error must stay within.

    The body starts on the face its clean twin rests on from pitch = roll = 0. The righting and escape barriers
    must agree with the reference within ``1e-6 * |reference| + m g (2 sqrt(3) e + 4 tol)``: noise of amplitude
    ``e`` per coordinate moves every hull point by at most ``sqrt(3) e``, hence the CoM height at every
    orientation, and so a minimax level above a minimum, by at most twice that; ``tol`` is the exact method's
    length tolerance (``LENGTH_RTOL`` times the diameter), within which it merges facets. Their saddles must lie
    within ``1e-6 rad + 10 sqrt(3) e / d`` of the reference's (``d`` the CoM's distance to the nearest face), or
    of another of the reference's saddles at the same level within the barrier bound (mirror saddles tie, and
    noise breaks the tie). The pitch- and roll-wise barriers are upper bounds over the hull's arcs that lie
    inside a sector, not continuous in the geometry (a facet that noise adds near a pole changes which arcs
    there are): they must exist where the reference's do and lie no lower than the righting barrier; their
    relative difference from the reference is reported, not bounded.

    Returns a dict: ``error`` (message, or None), ``barrier_ratio`` and ``saddle_ratio`` (worst error over its
    bound; <= 1 passes) and ``sector_rel`` (largest relative difference of the sector barriers).
    """
    from landscape.barriers.exact import LENGTH_RTOL, exact_barrier

    out = {"error": None, "barrier_ratio": 0.0, "saddle_ratio": 0.0, "sector_rel": 0.0}
    try:
        ref = exact_barrier(case.clean, 0.0, 0.0, g_m_s2=G_CAD)
        got = exact_barrier(case.pose, ref.start.pitch_deg, ref.start.roll_deg, g_m_s2=G_CAD)
    except Exception as exc:  # noqa: BLE001 - the benchmark counts internal errors
        out["error"] = f"{type(exc).__name__}: {exc}"
        return out
    mg = MASS_CAD_KG * G_CAD
    e_abs = mg * (2 * np.sqrt(3) * case.noise_m + 4 * LENGTH_RTOL * case.size_m)
    crit = ref.landscape.critical
    a_tol = 1e-6 + 10 * np.sqrt(3) * case.noise_m / float(ref.landscape.face_height_m.min())
    for kind in ("righting", "escape", "pitch_wise", "roll_wise"):
        g, r = getattr(got.barrier, kind), getattr(ref.barrier, kind)
        if (g is None) != (r is None):
            out["error"] = (
                f"{kind}: {'no exit' if g is None else 'an exit'} where the reference has the opposite"
            )
            return out
        if g is None:
            continue
        r_j, r_up = r.barrier_j, _up(r.saddle_pitch_deg, r.saddle_roll_deg)
        if kind == "righting" and case.closed is not None:  # the closed form, J above the start
            r_j, r_up = case.closed
        bound = 1e-6 * abs(r_j) + e_abs
        if kind.endswith("_wise"):
            if g.barrier_j < got.barrier.righting.barrier_j - bound:
                out["error"] = f"{kind} barrier {g.barrier_j:.9g} J lies below the righting barrier"
                return out
            out["sector_rel"] = max(out["sector_rel"], abs(g.barrier_j - r_j) / max(abs(r_j), bound))
            continue
        out["barrier_ratio"] = max(out["barrier_ratio"], abs(g.barrier_j - r_j) / bound)
        g_up = _up(g.saddle_pitch_deg, g.saddle_roll_deg)
        same = np.abs(crit.saddles_energy_j - (r_j + ref.start.energy_j)) <= bound
        cands = [r_up] + [_up(*d) for d in crit.saddles_deg[same]]
        out["saddle_ratio"] = max(out["saddle_ratio"], min(_angle_rad(g_up, c) for c in cands) / a_tol)
    return out


def _up(pitch_deg: float, roll_deg: float) -> np.ndarray:
    from geometry.frames import up_vector

    return up_vector(np.deg2rad(pitch_deg), np.deg2rad(roll_deg))


def cad_cases(n: int, seed: int = 0):
    """``n`` seeded cases of each family (the benchmark's draw; the tests draw with hypothesis)."""
    rng = np.random.default_rng(seed)
    for family in CAD_FAMILIES:
        for _ in range(n):
            yield cad_case(
                family,
                subdivisions=int(rng.integers(0, 6)),
                sections=int(rng.choice([3, 4, 6] if family == "prism" else [8, 12, 16, 32, 64])),
                noise_rel=float(10 ** rng.uniform(-13, -7)),
                com_frac=tuple(rng.uniform(-1, 1, 3)),
                seed=int(rng.integers(2**31)),
            )


def cad_main(n: int, seed: int) -> int:
    """Print the CAD-like families' table (see the module docstring)."""
    from landscape.computation import warm_up

    warm_up()
    rows: dict[str, list] = {f: [] for f in CAD_FAMILIES}
    for case in cad_cases(n, seed):
        t0 = time.perf_counter()
        res = cad_check(case)
        rows[case.family].append((res, time.perf_counter() - t0, case.label))
    print(
        "| family | cases | internal errors | worst barrier error / bound | worst saddle error / bound "
        "| worst sector difference (relative) | ms per case |"
    )
    print("|---|---:|---:|---:|---:|---:|---:|")
    for family, rs in rows.items():
        errs = [r for r, _, _ in rs if r["error"]]
        ok = [r for r, _, _ in rs if not r["error"]]
        worst_b = max((r["barrier_ratio"] for r in ok), default=np.nan)
        worst_s = max((r["saddle_ratio"] for r in ok), default=np.nan)
        worst_sec = max((r["sector_rel"] for r in ok), default=np.nan)
        ms = 1e3 * float(np.mean([t for _, t, _ in rs]))
        print(
            f"| {family} | {len(rs)} | {len(errs)} | {worst_b:.3g} | {worst_s:.3g} | {worst_sec:.2g} | {ms:.1f} |"
        )
    bad = [
        (lab, r)
        for rs in rows.values()
        for r, _, lab in rs
        if r["error"] or max(r["barrier_ratio"], r["saddle_ratio"]) > 1
    ]
    for lab, r in bad[:10]:
        print(f"  FAIL {lab}: {r}")
    return 1 if bad else 0


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument(
        "--cad", type=int, default=0, metavar="N", help="run N cases of each CAD-like family instead"
    )
    ap.add_argument("--seed", type=int, default=0, help="seed of the CAD-like cases")
    ap.add_argument("--out", type=Path, default=Path("figures/accuracy.png"))
    ap.add_argument("--steps", type=float, nargs="+", default=[4.0, 2.0, 1.0, 0.5, 0.25])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--levels", type=int, nargs="+", default=[4, 5, 6, 7], help="icosphere levels")
    args = ap.parse_args(argv)
    if args.cad:
        return cad_main(args.cad, args.seed)
    warm_up()
    rows = []
    print(
        "| shape | method | time (ms) | righting (mJ) | abs err (mJ) | rel err | escape (mJ) | escape abs err (mJ) |"
    )
    print("|---|---|---:|---:|---:|---:|---:|---:|")
    for name, pose, start, closed in _cases():
        _ = pose.hull
        t_ex, ex = _timed(lambda pose=pose, start=start: exact_barrier(pose, *start), args.repeat)
        ref = ex.barrier.righting.barrier_j
        ref_esc = ex.barrier.escape.barrier_j if ex.barrier.escape else np.nan
        note = "" if closed is None else f" (closed form {closed * 1e3:.6f})"
        print(
            f"| {name} | exact{note} | {t_ex * 1e3:.1f} | {ref * 1e3:.6f} | 0 | 0 | {ref_esc * 1e3:.6f} | 0 |"
        )
        rows.append((name, "exact", 0, t_ex, 0.0))
        for conn in (4, 8):
            for step in args.steps:
                t, gb = _timed(
                    lambda pose=pose, step=step, conn=conn, start=start: _grid(pose, step, conn, start),
                    1 if step < 0.5 else args.repeat,
                )
                val = gb.righting.barrier_j
                esc = gb.escape.barrier_j if gb.escape else np.nan
                err = abs(val - ref)
                print(
                    f"| {name} | grid {step:g}° {conn}-conn | {t * 1e3:.1f} | {val * 1e3:.6f} | {err * 1e3:.6f} "
                    f"| {err / ref if ref else np.nan:.2e} | {esc * 1e3:.6f} | {abs(esc - ref_esc) * 1e3:.6f} |"
                )
                rows.append((name, f"grid {conn}", step, t, err / ref if ref else np.nan))
        for level in args.levels:
            sphere_graph(level)
            t, sb = _timed(
                lambda pose=pose, start=start, level=level: sphere_barrier(pose, *start, subdivisions=level),
                1 if level > 6 else args.repeat,
            )
            val = sb.barrier.righting.barrier_j
            esc = sb.barrier.escape.barrier_j if sb.barrier.escape else np.nan
            err = abs(val - ref)
            print(
                f"| {name} | sphere level {level} ({sb.n_vertices} dirs, {sphere_graph(level).spacing_deg:.2f}°) "
                f"| {t * 1e3:.1f} | {val * 1e3:.6f} | {err * 1e3:.6f} | {err / ref if ref else np.nan:.2e} "
                f"| {esc * 1e3:.6f} | {abs(esc - ref_esc) * 1e3:.6f} |"
            )
            rows.append((name, "sphere", level, t, err / ref if ref else np.nan))
    _plot(rows, args.out)
    print(f"\nwrote {args.out}")
    return 0


def _plot(rows, out: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    names = list(dict.fromkeys(r[0] for r in rows))
    fig, ax = plt.subplots(figsize=(7.5, 5.0))
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    floor = 1e-7  # exact has no discretisation error; drawn at this floor
    for i, name in enumerate(names):
        c = colors[i % len(colors)]
        for conn, ls in (("grid 4", ":"), ("grid 8", "-"), ("sphere", "--")):
            sel = [r for r in rows if r[0] == name and r[1] == conn]
            ax.plot(
                [r[3] for r in sel],
                [max(r[4], floor) for r in sel],
                ls,
                marker="s" if conn == "sphere" else "o",
                ms=3,
                color=c,
                label=f"{name}, {conn}-conn" if conn == "grid 8" else None,
            )
        t_ex = [r[3] for r in rows if r[0] == name and r[1] == "exact"][0]
        ax.plot([t_ex], [floor], "*", ms=11, color=c)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("wall time per barrier (s)")
    ax.set_ylabel("relative error of the righting barrier")
    ax.set_title(
        "Grid (solid: 8-conn, dotted: 4-conn), icosphere (dashed) vs exact (stars, at the floor)", fontsize=9
    )
    ax.legend(fontsize=7, loc="upper right")
    ax.grid(True, which="both", alpha=0.3)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.tight_layout()
    fig.savefig(out, dpi=130)
    plt.close(fig)


if __name__ == "__main__":
    raise SystemExit(main())
