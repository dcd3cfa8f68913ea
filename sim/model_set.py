"""Named, versioned model parameter sets: the actuation profile and the contact model a trial runs with.

A set is a small TOML file; the package ships ``sim/models/paper.toml`` (the source paper's idealised profiles
and the default contact: the default, identical to trials made before model sets existed) and
``sim/models/physical.toml`` (the physical robot's measured wing speeds; not yet calibrated). ``--model NAME``
picks a shipped set, ``--model FILE.toml`` any other. Layout::

    name = "paper"
    version = 1
    description = "..."
    [actuation]
    profile = "idealised"        # the only profile so far
    wing_open_deg_s = 300.0
    wing_close_deg_s = 250.0
    wing_close_start_s = 1.05
    leg_cross_s = 0.15
    [contact]
    lateral_friction = 1.0
    restitution = 0.1
    stiffness_n_m = 1e4          # both omitted: pybullet's rigid contact
    damping_n_s_m = 100.0
    solver_iterations = 20

Every key is required except the two soft-contact keys (omit both for rigid contact); an unknown key is refused,
so a typo cannot silently leave a parameter at its default. The set's ``model_set_hash`` hashes its parsed
content (not the file's bytes: comments and formatting do not change it), so two files with the same parameters
are the same model.
"""

from __future__ import annotations

import hashlib
import json
import math
from dataclasses import dataclass
from pathlib import Path

from geometry.errors import UsageError

from .actuation import Actuation
from .world import Contact

MODELS_DIR = Path(__file__).resolve().parent / "models"
DEFAULT_MODEL_SET = "paper"
PROFILES = ("idealised",)
_TOP = {"name", "version", "description", "actuation", "contact"}
_ACTUATION = {"profile", "wing_open_deg_s", "wing_close_deg_s", "wing_close_start_s", "leg_cross_s"}
_CONTACT = {"lateral_friction", "restitution", "stiffness_n_m", "damping_n_s_m", "solver_iterations"}


class ModelSetError(UsageError):
    """A model set that cannot be found or read, or holds a bad value."""


@dataclass(frozen=True)
class ModelSet:
    """A model parameter set.

    Attributes
    ----------
    name : str
    version : int
    description : str
    source : str
        The file it was read from.
    profile : str
        Actuation profile kind (``"idealised"``).
    wing_open_deg_s, wing_close_deg_s, wing_close_start_s, leg_cross_s : float
        Profile timing (:class:`sim.actuation.Actuation`).
    contact : Contact
    model_set_hash : str
        16 hex digits of the SHA-256 of the parsed content.
    """

    name: str
    version: int
    description: str
    source: str
    profile: str
    wing_open_deg_s: float
    wing_close_deg_s: float
    wing_close_start_s: float
    leg_cross_s: float
    contact: Contact
    model_set_hash: str

    def actuation(
        self,
        theta_w_deg: float,
        theta_l_deg: float,
        *,
        wing_period_s: float | None = None,
        leg_period_s: float | None = None,
    ) -> Actuation:
        """The set's :class:`Actuation` at (theta_w, theta_l) (periods: the protocol's unless given)."""
        kw = {} if wing_period_s is None else {"wing_period_s": wing_period_s}
        if leg_period_s is not None:
            kw["leg_period_s"] = leg_period_s
        return Actuation(
            theta_w_deg,
            theta_l_deg,
            wing_open_deg_s=self.wing_open_deg_s,
            wing_close_deg_s=self.wing_close_deg_s,
            wing_close_start_s=self.wing_close_start_s,
            leg_cross_s=self.leg_cross_s,
            **kw,
        )

    @property
    def label(self) -> str:
        """``name vVERSION (hash)``."""
        return f"{self.name} v{self.version} ({self.model_set_hash})"


def shipped_model_sets() -> list[str]:
    """Names of the sets shipped in ``sim/models/``.

    Examples
    --------
    >>> shipped_model_sets()
    ['paper', 'physical']
    """
    return sorted(p.stem for p in MODELS_DIR.glob("*.toml"))


def _resolve(name_or_file: str | Path) -> Path:
    text = str(name_or_file)
    if text in shipped_model_sets():
        return MODELS_DIR / f"{text}.toml"
    path = Path(text)
    if path.suffix == ".toml" or path.exists():
        if not path.is_file():
            raise ModelSetError(
                f"model set file '{path}' not found; give a shipped set "
                f"({', '.join(shipped_model_sets())}) or an existing .toml file"
            )
        return path
    raise ModelSetError(
        f"unknown model set {text!r}; give a shipped set ({', '.join(shipped_model_sets())}) or a .toml file"
    )


def _number(section: dict, key: str, where: str, *, positive: bool = True, allow_zero: bool = False) -> float:
    v = section.get(key)
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        raise ModelSetError(f"{where}: {key} must be a finite number; got {v!r}")
    if positive and not (v > 0 or (allow_zero and v == 0)):
        raise ModelSetError(f"{where}: {key} must be {'>= 0' if allow_zero else '> 0'}; got {v!r}")
    return float(v)


def _check_keys(section, allowed: set[str], required: set[str], where: str) -> dict:
    if not isinstance(section, dict):
        raise ModelSetError(f"{where} must be a table; got {section!r}")
    unknown = sorted(set(section) - allowed)
    if unknown:
        raise ModelSetError(f"{where}: unknown key {unknown[0]!r}; allowed: {', '.join(sorted(allowed))}")
    missing = sorted(required - set(section))
    if missing:
        raise ModelSetError(f"{where}: missing key {missing[0]!r}")
    return section


def load_model_set(name_or_file: str | Path = DEFAULT_MODEL_SET) -> ModelSet:
    """Read a model set by shipped name or TOML file.

    Raises
    ------
    ModelSetError
        If it cannot be found or parsed, a key is unknown or missing, or a value is out of range.

    Examples
    --------
    >>> ms = load_model_set("paper")
    >>> ms.name, ms.wing_open_deg_s, ms.contact.friction
    ('paper', 300.0, 1.0)
    """
    try:
        import tomllib
    except ImportError:  # pragma: no cover - Python 3.10
        import tomli as tomllib  # type: ignore[no-redef]

    path = _resolve(name_or_file)
    try:
        data = tomllib.loads(path.read_text())
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise ModelSetError(f"model set '{path}' is not valid TOML: {exc}") from None
    where = f"model set '{path}'"
    _check_keys(data, _TOP, _TOP - {"description"}, where)
    if not isinstance(data["name"], str) or not data["name"].strip():
        raise ModelSetError(f"{where}: name must be a non-empty string; got {data['name']!r}")
    if isinstance(data["version"], bool) or not isinstance(data["version"], int) or data["version"] < 0:
        raise ModelSetError(f"{where}: version must be a whole number >= 0; got {data['version']!r}")
    act = _check_keys(data["actuation"], _ACTUATION, _ACTUATION, f"{where} [actuation]")
    if act["profile"] not in PROFILES:
        raise ModelSetError(
            f"{where} [actuation]: profile must be one of {', '.join(PROFILES)}; got {act['profile']!r}"
        )
    con = _check_keys(
        data["contact"], _CONTACT, _CONTACT - {"stiffness_n_m", "damping_n_s_m"}, f"{where} [contact]"
    )
    soft = [k for k in ("stiffness_n_m", "damping_n_s_m") if k in con]
    if len(soft) == 1:
        raise ModelSetError(
            f"{where} [contact]: give both stiffness_n_m and damping_n_s_m (soft contact) or "
            "neither (rigid contact)"
        )
    w = f"{where} [contact]"
    iters = con["solver_iterations"]
    if isinstance(iters, bool) or not isinstance(iters, int) or iters < 1:
        raise ModelSetError(f"{w}: solver_iterations must be a whole number >= 1; got {iters!r}")
    contact = Contact(
        friction=_number(con, "lateral_friction", w, allow_zero=True),
        restitution=_number(con, "restitution", w, allow_zero=True),
        stiffness_n_m=_number(con, "stiffness_n_m", w) if soft else None,
        damping_n_s_m=_number(con, "damping_n_s_m", w, allow_zero=True) if soft else None,
        solver_iterations=int(iters),
    )
    if contact.restitution > 1:
        raise ModelSetError(f"{w}: restitution must be in [0, 1]; got {contact.restitution!r}")
    wa = f"{where} [actuation]"
    timing = {
        k: _number(act, k, wa)
        for k in ("wing_open_deg_s", "wing_close_deg_s", "wing_close_start_s", "leg_cross_s")
    }
    canonical = {
        "name": data["name"],
        "version": data["version"],
        "actuation": {"profile": act["profile"], **timing},
        "contact": {
            "lateral_friction": contact.friction,
            "restitution": contact.restitution,
            "stiffness_n_m": contact.stiffness_n_m,
            "damping_n_s_m": contact.damping_n_s_m,
            "solver_iterations": contact.solver_iterations,
        },
    }
    digest = hashlib.sha256(json.dumps(canonical, sort_keys=True).encode()).hexdigest()[:16]
    ms = ModelSet(
        data["name"],
        int(data["version"]),
        str(data.get("description", "")),
        str(path),
        act["profile"],
        contact=contact,
        model_set_hash=digest,
        **timing,
    )
    try:
        ms.actuation(0.0, 0.0)
    except ValueError as exc:
        raise ModelSetError(f"{wa}: {exc}") from None
    return ms
