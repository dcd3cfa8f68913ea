"""Which physical cause closes the gap between simulation and the physical robot? (issue #15, section 3: ablation)

Starts from the source paper's model set (or ``--base NAME|FILE``) and switches on one cause at a time, each
taken from a fuller set (default: the shipped ``physical`` set, or a calibrated one with ``--from FILE``):

- ``actuation``: the ``[actuation]`` table (the measured per-servo profiles, left/right asymmetry included);
- ``contact``: the ``[contact]`` table (friction, stiffness, damping);
- every table a set may add (``sim.model_set.OPTIONAL_TABLES``: ``compliance``, ``body_torsion``,
  ``leg_compliance``, ``leg_bend``, ``head_compliance``, ``mass``, ``geometry``), when the fuller set has it;
- ``all``: the fuller set itself.

Each variant runs through ``landscape physical validate``'s library function on every cell (same phases and
seeds for every variant), and the table gives the cells agreeing (fit, held-out, all), the log-likelihood of the
physical outcomes, the per-attempt rates agreeing and the simulated side fraction. Every variant keeps its own
trial store in ``--out``, so a rerun resumes.

Run:  PYTHONPATH=. .venv/bin/python benchmarks/physical/physical_ablation.py [--base paper] [--from FILE] [--trials 10]
      [--out DIR]
      [--data ../shared/ref/physical_robot] [--robot ../shared/ref/lab_robot/lab_robot.urdf]

Last run: see the docs' physical-robot chapter (docs/physical/), the command above with its output.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import tomli_w

from geometry.errors import UsageError
from landscape.analysis.physical.validation import validate
from sim.model_set import OPTIONAL_TABLES, load_model_set, read_toml

ROOT = Path(__file__).resolve().parents[2]
CAUSES = ("actuation", "contact", *OPTIONAL_TABLES)


def variant(base_file: Path, full_file: Path, tables: tuple[str, ...], name: str, out: Path) -> Path:
    """The base set with ``tables`` taken from the fuller set, written to ``out/NAME.toml``."""
    base = read_toml(base_file)
    full = read_toml(full_file)
    for t in tables:
        if t in full:
            base[t] = full[t]
        else:
            base.pop(t, None)
    base["name"] = name
    base["description"] = (
        f"ablation: {base_file.stem} with {', '.join(tables) or 'nothing'} from {full_file.name}"
    )
    path = out / f"{name}.toml"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(tomli_w.dumps(base))
    return path


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--base", default="paper", help="The set each cause is switched on in.")
    ap.add_argument("--from", dest="full", default="physical", help="The fuller set the causes come from.")
    ap.add_argument("--trials", type=int, default=10)
    ap.add_argument("--data", default=str(ROOT.parent / "shared/ref/physical_robot"))
    ap.add_argument("--robot", default=str(ROOT.parent / "shared/ref/lab_robot/lab_robot.urdf"))
    ap.add_argument("--out", default="ablation")
    ap.add_argument("--workers", type=int, default=None)
    args = ap.parse_args(argv)
    try:
        return _run(args)
    except UsageError as exc:  # a bad set, data or robot: one line, as the landscape command does
        ap.exit(2, f"{ap.prog}: error: {exc}\n")


def _run(args) -> int:
    out = Path(args.out)
    base = Path(load_model_set(args.base).source)
    full = Path(load_model_set(args.full).source)
    b, f = read_toml(base), read_toml(full)
    have = [c for c in CAUSES if c in f and f[c] != b.get(c)]  # the causes the fuller set changes
    stem = load_model_set(base).name
    variants = [(stem, base)]
    variants += [(f"{stem}+{c}", variant(base, full, (c,), f"{stem}+{c}", out / "sets")) for c in have]
    variants.append((f"all ({load_model_set(full).name})", full))
    rows = []
    for label, path in variants:
        ms = load_model_set(path)
        v, _ = validate(
            args.data, db=out / f"trials_{ms.name}_{ms.model_set_hash}.sqlite", robot=args.robot,
            model_set=path, trials=args.trials, workers=args.workers, progress=False,
        )  # fmt: skip
        s = v.side
        rows.append(
            (
                label,
                "{}/{}".format(*v.agree_counts["fit"]),
                "{}/{}".format(*v.agree_counts["held-out"]),
                "{}/{}".format(*v.agree_counts["all"]),
                f"{v.log_likelihood['all']:.1f}",
                f"{sum(a.agree for a in v.attempts)}/{len(v.attempts)}",
                f"{s.sim_positive}/{s.sim_events}" if s.sim_events else "–",
            )
        )
        print(f"done: {label}", file=sys.stderr)
    head = ("model set", "fit cells agree", "held-out agree", "all agree", "log-lik.", "attempt rates agree",
            "righting to + roll")  # fmt: skip
    print(
        f"robot {Path(args.robot).name}, {args.trials} trials a cell, Cv 0.05; physical robot: 43/46 to + roll"
    )
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    for r in rows:
        print("| " + " | ".join(r) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
