"""matplotlib for the figure modules: the headless Agg backend, chosen once, and one way to save a figure."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

__all__ = ["plt", "save"]


def save(fig, path: str | Path, *, svg_too: bool = False, **savefig_kw) -> Path:
    """Write ``fig`` to ``path`` (and the same name with ``.svg`` when ``svg_too``), creating the directory; the
    figure is closed whatever happens. Returns ``path``."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    try:
        fig.savefig(path, **savefig_kw)
        if svg_too:
            fig.savefig(path.with_suffix(".svg"), **{k: v for k, v in savefig_kw.items() if k != "dpi"})
    finally:
        plt.close(fig)
    return path
