"""How often would a perfect model pass the referee?  The chance that ``landscape physical validate`` counts a
cell as agreeing when the simulation's true success probability equals the robot's (issue #15's acceptance:
at least 11 of 12 cells).

A cell agrees when each success fraction lies inside the other's Wilson 95 % interval
(``landscape.analysis.physical.validation``). The robot's true probability in a cell is not known; given its k of n
recorded successes it is taken either as exactly k / n (the plug-in: the robot's fractions are the truth) or as
Beta(k + 1, n - k + 1) (uniform prior). Per cell and number of simulated trials, exactly (no sampling):

- *perfect, p = k/n*: the model's true probability is the robot's recorded fraction.
- *perfect, these data*: the model's true probability is the robot's; the robot's recorded k stays as it is.
  P(agree) = sum over the simulated counts that agree of the beta-binomial probability.
- *perfect, new data*: the same, but the robot's 5 trials are drawn anew too (the referee's chance before the
  lab ran its trials).
- *best possible*: the model's probability chosen, per cell, to make agreement with the recorded k likeliest
  (a model tuned to the referee, not to the robot): the ceiling of any model.
- *perfect, these data, Fisher*: as *perfect, these data*, with a cell counted when Fisher's exact test cannot
  tell the two fractions apart (p >= 0.05; ``landscape physical validate`` prints that count too).

The number of agreeing cells out of 12 is then a sum of independent Bernoulli variables (the cells' trials are
independent); its distribution follows by convolution. Printed: the expected count and P(>= 11), P(12); then,
per cell at the first number of trials, which simulated counts agree and each model's P(agree). A cell where the
robot righted 5 of 5 (or 0 of 5) agrees only with a simulation that rights every trial (or none), because a
Wilson interval reaches 100 % only at k = n.

Run:  PYTHONPATH=. .venv/bin/python benchmarks/physical/referee_power.py [--data DIR] [--trials 10,20,40]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from scipy.stats import betabinom, binom

from geometry.errors import UsageError

ROOT = Path(__file__).resolve().parents[2]
P_GRID = np.linspace(0.0, 1.0, 2001)
"""Probabilities searched for the best possible model."""


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--data", default=str(ROOT.parent / "shared/ref/physical_robot"))
    ap.add_argument("--trials", default="10,20,40", help="simulated trials per cell, a list")
    ap.add_argument("--need", type=int, default=11, help="agreeing cells the acceptance asks for")
    args = ap.parse_args(argv)
    try:
        trials = [int(x) for x in args.trials.split(",")]
        if not trials or min(trials) < 1:
            raise ValueError
    except ValueError:
        ap.exit(
            2, f"{ap.prog}: error: --trials must be whole numbers >= 1, e.g. 10,20; got {args.trials!r}\n"
        )
    try:
        from landscape.analysis.physical.cells import physical_cells
        from landscape.analysis.physical.outcome import physical_trials

        cells = [(c.successes, c.n) for c in physical_cells(physical_trials(args.data))]
    except UsageError as exc:  # bad data: one line, as the landscape command does
        ap.exit(2, f"{ap.prog}: error: {exc}\n")
    if not 1 <= args.need <= len(cells):
        ap.exit(
            2, f"{ap.prog}: error: --need must lie in 1..{len(cells)} (the robot's cells); got {args.need}\n"
        )
    print(power_table(cells, trials, args.need))
    return 0


def agreeing_counts(k: int, n: int, n_sim: int, rule: str = "wilson") -> np.ndarray:
    """The simulated success counts (0..n_sim) that agree with k of n: by the validation's Wilson rule, or
    (``rule="fisher"``) those Fisher's exact test cannot tell apart (p >= ``CONSISTENT_P``)."""
    from landscape.analysis.physical.validation import fractions_agree
    from landscape.analysis.trials import CONSISTENT_P, fisher_p

    if rule == "fisher":
        return np.array([m for m in range(n_sim + 1) if fisher_p(k, n, m, n_sim) >= CONSISTENT_P], dtype=int)
    return np.array([m for m in range(n_sim + 1) if fractions_agree(k, n, m, n_sim)], dtype=int)


def p_agree_plugin(k: int, n: int, n_sim: int) -> float:
    """P(agree) for a model whose probability is the robot's recorded fraction k / n."""
    return float(binom.pmf(agreeing_counts(k, n, n_sim), n_sim, k / n).sum())


def p_agree_perfect(k: int, n: int, n_sim: int, rule: str = "wilson") -> float:
    """P(agree) for a model whose probability is the robot's, given the robot's recorded k of n."""
    a, b = k + 1, n - k + 1
    return float(betabinom.pmf(agreeing_counts(k, n, n_sim, rule), n_sim, a, b).sum())


def p_consistent_perfect(k: int, n: int, n_sim: int) -> float:
    """:func:`p_agree_perfect` by Fisher's exact test instead of the Wilson rule."""
    return p_agree_perfect(k, n, n_sim, "fisher")


def p_agree_new_data(k: int, n: int, n_sim: int) -> float:
    """P(agree) for a perfect model when the robot's n trials are drawn anew as well (same posterior)."""
    a, b = k + 1, n - k + 1
    w = betabinom.pmf(np.arange(n + 1), n, a, b)  # the robot's new count, marginally
    # given the robot's new count j, the shared probability's posterior is Beta(a + j, b + n - j)
    return float(sum(w[j] * betabinom.pmf(agreeing_counts(j, n, n_sim), n_sim, a + j, b + n - j).sum()
                     for j in range(n + 1)))  # fmt: skip


def p_agree_best(k: int, n: int, n_sim: int) -> float:
    """The largest P(agree) with the recorded k of n over every model probability."""
    ok = agreeing_counts(k, n, n_sim)
    return float(binom.pmf(ok[:, None], n_sim, P_GRID[None, :]).sum(axis=0).max())


def count_distribution(ps) -> np.ndarray:
    """P(exactly j of the cells agree), j = 0..len(ps), for independent cells agreeing with probabilities ps."""
    dist = np.array([1.0])
    for p in ps:
        dist = np.convolve(dist, [1.0 - p, p])
    return dist


def power_table(cells: list[tuple[int, int]], trials: list[int], need: int) -> str:
    lines = [
        f"the robot's cells: {', '.join(f'{k}/{n}' for k, n in cells)}; a cell agrees when each fraction lies in the "
        "other's Wilson 95 % interval",
        f"| simulated trials a cell | model | expected agreeing cells | P(>= {need} of {len(cells)}) | "
        f"P({len(cells)} of {len(cells)}) |",
        "|---|---|---|---|---|",
    ]
    for n_sim in trials:
        for label, f in (
            ("perfect, p = k/n", p_agree_plugin),
            ("perfect, these data", p_agree_perfect),
            ("perfect, new data", p_agree_new_data),
            ("best possible, these data", p_agree_best),
            ("perfect, these data, Fisher p >= 0.05 instead", p_consistent_perfect),
        ):
            ps = [f(k, n, n_sim) for k, n in cells]
            d = count_distribution(ps)
            lines.append(
                f"| {n_sim} | {label} | {sum(ps):.2f} | {d[need:].sum() * 100:.0f} % | {d[-1] * 100:.0f} % |"
            )
    n_sim = trials[0]
    lines += [
        "",
        f"per cell, {n_sim} simulated trials: the simulated counts that agree; P(agree) for a perfect model "
        "(p = k/n; p ~ Beta) and the best possible one",
        "| robot | agreeing simulated counts | perfect, p = k/n | perfect, these data | best possible |",
        "|---|---|---|---|---|",
    ]
    for k, n in sorted(set(cells)):
        ok = agreeing_counts(k, n, n_sim)
        shown = f"{ok[0]}..{ok[-1]} of {n_sim}" if len(ok) > 1 else f"{ok[0]} of {n_sim}"
        lines.append(
            f"| {k}/{n} | {shown} | {p_agree_plugin(k, n, n_sim) * 100:.0f} % | "
            f"{p_agree_perfect(k, n, n_sim) * 100:.0f} % | {p_agree_best(k, n, n_sim) * 100:.0f} % |"
        )
    return "\n".join(lines)


if __name__ == "__main__":
    raise SystemExit(main())
