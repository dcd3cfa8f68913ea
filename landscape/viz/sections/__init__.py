"""The report's sections: the source paper's analyses of a trial database, each written as CSV tables and
PNG/SVG figures (edge layer; ``landscape analyze …`` and ``landscape report`` call these), one module per section.

Each ``section_*`` function reads trial rows, writes its files into ``out`` and returns a
:class:`landscape.viz.report.Section`; a section whose trials are missing says which command produces them.
:data:`SECTIONS` lists them in page order and :func:`build_report` writes them as one page. A new analysis is one
module here with its ``section_*`` function, and one entry in :data:`SECTIONS`.
"""

from __future__ import annotations

import platform
import time
from pathlib import Path

from landscape.viz.report import Section, write_report
from landscape.viz.sections.barrier import section_barrier
from landscape.viz.sections.data import (
    PAPER_SWEEP,
    PHASE_MAP_SWEEP,
    PHASE_MAP_TL_SWEEP,
    PREDICTION_SWEEP,
    load_rows,
)
from landscape.viz.sections.energy import section_energy
from landscape.viz.sections.evolution import section_evolution
from landscape.viz.sections.phase_map import section_phase_map
from landscape.viz.sections.physical import section_physical
from landscape.viz.sections.prediction import section_prediction
from landscape.viz.sections.probability import section_probability
from landscape.viz.sections.trajectories import section_trajectories
from landscape.viz.sections.validation import section_validation

__all__ = [
    "PAPER_SWEEP",
    "PHASE_MAP_SWEEP",
    "PHASE_MAP_TL_SWEEP",
    "PREDICTION_SWEEP",
    "SECTIONS",
    "build_report",
    "load_rows",
    "section_barrier",
    "section_energy",
    "section_evolution",
    "section_phase_map",
    "section_physical",
    "section_prediction",
    "section_probability",
    "section_trajectories",
    "section_validation",
]


#: the report's sections in page order; a new analysis is one ``section_*`` function and one entry here
SECTIONS = {
    "probability": section_probability,
    "phase map": section_phase_map,
    "prediction": section_prediction,
    "phase evolution": section_evolution,
    "barrier vs outcome": section_barrier,
    "trajectories": section_trajectories,
    "energy": section_energy,
}
#: sections that take the trials' robot (``robot=``)
_ROBOT_SECTIONS = {"barrier vs outcome", "trajectories", "energy"}
#: sections that also take the physical data directory (``physical_dir=``)
_PHYSICAL_SECTIONS = {"energy"}


def build_report(
    db: Path,
    out: Path,
    *,
    robot: str | Path | None = None,
    physical_dir: str | Path | None = None,
    validations: list[str | Path] = (),
) -> tuple[Path, list[Section]]:
    """Every section of :data:`SECTIONS` on the trials of ``db``, and one self-contained HTML page in ``out``;
    with ``physical_dir`` (the lab's data directory), also :func:`section_physical`; with ``validations``
    (``landscape physical validate`` outputs), also :func:`section_validation`.

    Returns
    -------
    page : Path
        The written ``index.html``.
    sections : list of Section
        As written (a section without data says which sweep produces it).
    """
    from importlib.metadata import PackageNotFoundError, version

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    rows = load_rows(db)
    timings: dict[str, float] = {}
    sections = []
    for name, fn in SECTIONS.items():
        t0 = time.perf_counter()
        kw = {"robot": robot} if name in _ROBOT_SECTIONS else {}
        if name in _PHYSICAL_SECTIONS:
            kw["physical_dir"] = physical_dir
        sections.append(fn(rows, out, db, **kw))
        timings[name] = time.perf_counter() - t0
    if physical_dir is not None:
        t0 = time.perf_counter()
        sections.append(section_physical(rows, out, db, data_dir=physical_dir, robot=robot))
        timings["physical robot"] = time.perf_counter() - t0
    if validations:
        t0 = time.perf_counter()
        sections.append(section_validation(out, validations=list(validations), data_dir=physical_dir))
        timings["validation"] = time.perf_counter() - t0
    ok = [r for r in rows if r["status"] == "ok"]
    inputs = {
        "database": str(Path(db).resolve()),
        "trials": str(len(rows)),
        "diverged": str(sum(r["status"] == "diverged" for r in rows)),
        "robots": ", ".join(sorted({f"{Path(r['robot']).name} ({r['robot_hash']})" for r in rows})),
        "time steps (s)": ", ".join(f"{x:g}" for x in sorted({r["dt_s"] for r in rows})),
        "trial CPU time (s)": f"{sum(r['cpu_s'] or 0.0 for r in ok):.0f}",
        **({"physical data": str(Path(physical_dir).resolve())} if physical_dir is not None else {}),
        "package versions in the database": ", ".join(sorted({str(r["version"]) for r in rows})),
    }
    versions = {"python": platform.python_version(), "platform": platform.platform()}
    for pkg in ("selfrighting-landscape", "numpy", "scipy", "numba", "pybullet", "matplotlib", "trimesh"):
        try:
            versions[pkg] = version(pkg)
        except PackageNotFoundError:  # a missing optional package is reported, not fatal
            versions[pkg] = "not installed"
    page = write_report(
        sections,
        out,
        title="Self-righting: barrier, coordination and randomness",
        inputs=inputs,
        versions=versions,
        timings_s=timings,
    )
    return page, sections
