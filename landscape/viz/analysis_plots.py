"""Figures of :mod:`landscape.analysis.trials` (edge layer, matplotlib Agg): each writes a PNG and an SVG and returns the
PNG path."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
from matplotlib.colors import ListedColormap

from landscape.analysis.trials import AccuracyCell, BarrierOutcome, PhaseMap, ProbabilityCell
from landscape.viz._mpl import plt, save

OUTCOME_CMAP = ListedColormap(["#d7301f", "#1a9850"])


def _save(fig, png: Path) -> Path:
    return save(fig, png, svg_too=True, dpi=130, bbox_inches="tight")


def _grid(n: int, ncols: int = 3) -> tuple[int, int]:
    ncols = min(ncols, n)
    return (n + ncols - 1) // ncols, ncols


def plot_probability(cells: Sequence[ProbabilityCell], png: Path, *, title: str = "") -> Path:
    """Self-righting probability over theta_w x theta_l, one panel per Cv, with n and Wilson 95 % intervals."""
    cvs = sorted({c.cv for c in cells})
    ws = sorted({c.theta_w_deg for c in cells})
    ls = sorted({c.theta_l_deg for c in cells})
    nr, nc = _grid(len(cvs))
    fig, axes = plt.subplots(nr, nc, figsize=(3.6 * nc, 3.1 * nr), squeeze=False, constrained_layout=True)
    im = None
    for ax, cv in zip(axes.flat, cvs, strict=False):
        p = np.full((len(ws), len(ls)), np.nan)
        for c in cells:
            if c.cv != cv:
                continue
            i, j = ws.index(c.theta_w_deg), ls.index(c.theta_l_deg)
            p[i, j] = c.p
            ax.text(
                j,
                i,
                f"{c.p:.2f}\n[{c.ci_low:.2f}, {c.ci_high:.2f}]\nn={c.n}",
                ha="center",
                va="center",
                fontsize=6.5,
                color="white" if c.p < 0.6 else "black",
            )
        im = ax.imshow(p, origin="lower", cmap="viridis", vmin=0.0, vmax=1.0, aspect="auto")
        ax.set_xticks(range(len(ls)), [f"{x:g}" for x in ls])
        ax.set_yticks(range(len(ws)), [f"{x:g}" for x in ws])
        ax.set_xlabel("leg amplitude θl (°)")
        ax.set_ylabel("wing angle θw (°)")
        ax.set_title(f"Cv = {cv * 100:g} %")
    for ax in list(axes.flat)[len(cvs) :]:
        ax.set_visible(False)
    if im is not None:
        fig.colorbar(im, ax=axes, shrink=0.8, label="self-righting probability")
    if title:
        fig.suptitle(title)
    return _save(fig, png)


def plot_phase_maps(maps: Sequence[PhaseMap], png: Path, *, title: str = "") -> Path:
    """Single-attempt outcome against phase and theta_l, one panel per theta_w (green success, red failure)."""
    nr, nc = _grid(len(maps), 2)
    fig, axes = plt.subplots(nr, nc, figsize=(5.2 * nc, 2.4 * nr), squeeze=False, constrained_layout=True)
    for ax, pm in zip(axes.flat, maps, strict=False):
        step = float(np.min(np.diff(pm.phases))) if len(pm.phases) > 1 else 0.05
        edges_x = np.append(pm.phases - step / 2, pm.phases[-1] + step / 2) * 100
        dl = float(np.min(np.diff(pm.theta_l_deg))) if len(pm.theta_l_deg) > 1 else 10.0
        edges_y = np.append(pm.theta_l_deg - dl / 2, pm.theta_l_deg[-1] + dl / 2)
        ax.pcolormesh(
            edges_x,
            edges_y,
            np.where(np.isnan(pm.success), np.nan, pm.success >= 0.5),
            cmap=OUTCOME_CMAP,
            vmin=0,
            vmax=1,
            edgecolors="white",
            linewidth=0.5,
        )
        ax.set_yticks(pm.theta_l_deg)
        ax.set_xlabel("phase φ of the wing opening (% of Tl)")
        ax.set_ylabel("θl (°)")
        ax.set_title(
            f"θw = {pm.theta_w_deg:g}°, Tl = {pm.leg_period_s:g} s: "
            f"{int(np.nansum(pm.success >= 0.5))}/{int((pm.n > 0).sum())} attempts right"
        )
    for ax in list(axes.flat)[len(maps) :]:
        ax.set_visible(False)
    if title:
        fig.suptitle(title)
    return _save(fig, png)


def plot_prediction(
    acc: Sequence[AccuracyCell], noisy: Sequence[AccuracyCell], png: Path, *, title: str = ""
) -> Path:
    """(a) Prediction accuracy over Tw x Tl without noise; (b) predicted against simulated self-righting
    probability with noise (Wilson 95 % intervals of the simulation)."""
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.2), constrained_layout=True)
    tws = sorted({c.wing_period_s for c in acc})
    tls = sorted({c.leg_period_s for c in acc})
    if acc:
        m = np.full((len(tws), len(tls)), np.nan)
        for c in acc:
            i, j = tws.index(c.wing_period_s), tls.index(c.leg_period_s)
            m[i, j] = c.accuracy
            a.text(
                j,
                i,
                f"{c.accuracy * 100:.0f} %\n({c.correct}/{c.n})",
                ha="center",
                va="center",
                fontsize=8,
                color="white" if c.accuracy < 0.6 else "black",
            )
        im = a.imshow(m, origin="lower", cmap="viridis", vmin=0, vmax=1, aspect="auto")
        a.set_xticks(range(len(tls)), [f"{x:g}" for x in tls])
        a.set_yticks(range(len(tws)), [f"{x:g}" for x in tws])
        fig.colorbar(im, ax=a, label="accuracy")
        accs = np.array([c.accuracy for c in acc])
        a.set_title(
            f"first righting attempt predicted: {accs.mean() * 100:.0f} ± {accs.std(ddof=1) * 100 if len(accs) > 1 else 0:.0f} %"
        )
    else:
        a.text(0.5, 0.5, "no multi-attempt trials with a phase map", ha="center", transform=a.transAxes)
    a.set_xlabel("leg period Tl (s)")
    a.set_ylabel("wing period Tw (s)")
    if noisy:
        sim_p = np.array([c.simulated_p for c in noisy])
        pred_p = np.array([c.predicted_p for c in noisy])
        yerr = np.clip(
            [[c.simulated_p - c.ci_low for c in noisy], [c.ci_high - c.simulated_p for c in noisy]], 0, 1
        )
        sc = b.scatter(pred_p, sim_p, c=[c.cv * 100 for c in noisy], cmap="plasma", zorder=3, s=18)
        b.errorbar(pred_p, sim_p, yerr=yerr, fmt="none", ecolor="0.7", zorder=2, lw=0.8)
        fig.colorbar(sc, ax=b, label="Cv (%)")
        b.plot([0, 1], [0, 1], "k--", lw=0.8)
        rmse = float(np.sqrt(np.mean((sim_p - pred_p) ** 2)))
        b.set_title(f"with noise: {len(noisy)} settings, RMS difference {rmse:.2f}")
    else:
        b.text(0.5, 0.5, "no noisy multi-attempt trials with a phase map", ha="center", transform=b.transAxes)
    b.set_xlim(-0.03, 1.03)
    b.set_ylim(-0.03, 1.03)
    b.set_xlabel("predicted probability (phase map + the trials' own noise)")
    b.set_ylabel("simulated probability")
    if title:
        fig.suptitle(title)
    return _save(fig, png)


def plot_evolution(
    pm: PhaseMap,
    theta_l_deg: float,
    sequences: Sequence[tuple[str, np.ndarray, int | None]],
    png: Path,
    *,
    title: str = "",
) -> Path:
    """Phases visited over attempts, drawn over the single-attempt map row of ``theta_l_deg``.

    ``sequences``: (label, phases of attempts 1..K, first attempt on a good phase or None) per panel.
    """
    row = int(np.flatnonzero(np.isclose(pm.theta_l_deg, theta_l_deg))[0])
    step = float(np.min(np.diff(pm.phases))) if len(pm.phases) > 1 else 0.05
    fig, axes = plt.subplots(
        1, len(sequences), figsize=(5.0 * len(sequences), 3.8), squeeze=False, constrained_layout=True
    )
    for ax, (label, phases, first) in zip(axes.flat, sequences, strict=True):
        k = np.arange(1, len(phases) + 1)
        for ph, s in zip(pm.phases, pm.success[row], strict=True):
            if np.isfinite(s):
                ax.axvspan(
                    (ph - step / 2) * 100,
                    (ph + step / 2) * 100,
                    color=OUTCOME_CMAP(int(s >= 0.5)),
                    alpha=0.25,
                    lw=0,
                )
        ax.plot(np.asarray(phases) * 100, k, "o-", color="k", ms=4, lw=0.8)
        if first is not None:
            ax.plot(
                phases[first - 1] * 100,
                first,
                "*",
                color="gold",
                mec="k",
                ms=16,
                zorder=5,
                label=f"first good phase: attempt {first}",
            )
            ax.legend(loc="upper right", fontsize=8)
        ax.set_xlim(-step * 50, 100 - step * 50)
        ax.set_ylim(len(phases) + 0.5, 0.5)
        ax.set_xlabel("phase φ (% of Tl)  [green: a single attempt rights]")
        ax.set_ylabel("attempt")
        ax.set_title(label, fontsize=9)
    if title:
        fig.suptitle(title)
    return _save(fig, png)


def plot_barrier_outcome(results: Sequence[BarrierOutcome], png: Path, *, title: str = "") -> Path:
    """(a) Self-righting probability against the exact barrier with logistic fits, one colour per Cv; (b) mean
    time to right against the barrier; (c) grid against exact barrier."""
    fig, (a, b, c) = plt.subplots(1, 3, figsize=(15, 4.3), constrained_layout=True)
    cmap = plt.get_cmap("plasma")
    cvs = [r.cv for r in results]
    span = max(cvs) if cvs and max(cvs) > 0 else 1.0
    for r in results:
        col = cmap(0.85 * r.cv / span)
        p = np.array([x.p for x in r.cells])
        yerr = np.clip([p - [x.ci_low for x in r.cells], [x.ci_high for x in r.cells] - p], 0, 1)
        a.errorbar(
            r.exact_mj,
            p,
            yerr=yerr,
            fmt="o",
            color=col,
            ms=4,
            lw=0.7,
            capsize=2,
            label=f"Cv {r.cv * 100:g} %: ρ = {r.rho:.2f} [{r.rho_low:.2f}, {r.rho_high:.2f}]",
        )
        ok = np.isfinite(r.exact_mj)
        if ok.any():
            xs = np.linspace(np.nanmin(r.exact_mj), np.nanmax(r.exact_mj), 200)
            a.plot(xs, r.fit.p(xs), "-", color=col, lw=1)
        t = np.array([x.mean_time_to_right_s for x in r.cells])
        b.plot(r.exact_mj, t, "o", color=col, ms=4, label=f"Cv {r.cv * 100:g} %: ρ = {r.rho_time:.2f}")
    a.set_xlabel("minimal righting barrier, exact (mJ)")
    a.set_ylabel("self-righting probability")
    a.legend(fontsize=7)
    b.set_xlabel("minimal righting barrier, exact (mJ)")
    b.set_ylabel("mean time to right (s)")
    b.legend(fontsize=7)
    if results:
        r0 = results[0]
        c.plot(r0.exact_mj, r0.grid_mj, "o", ms=4)
        lim = [np.nanmin([r0.exact_mj, r0.grid_mj]), np.nanmax([r0.exact_mj, r0.grid_mj])]
        c.plot(lim, lim, "k--", lw=0.8)
        for x, e, g in zip(r0.cells, r0.exact_mj, r0.grid_mj, strict=True):
            c.annotate(f"{x.theta_w_deg:g}/{x.theta_l_deg:g}", (e, g), fontsize=6)
    c.set_xlabel("exact barrier (mJ)")
    c.set_ylabel("1° grid barrier (mJ)")
    c.set_title("labels: θw/θl (°)", fontsize=9)
    if title:
        fig.suptitle(title)
    return _save(fig, png)
