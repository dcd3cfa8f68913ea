"""Every number the command line takes has a stated range: its --help says it, and a value outside it is refused in
one line with exit status 2 before any work. Walks the click tree, so a new numeric option that is not a
``ranged_option`` (a bare ``type=float``, an ``IntRange``, a number read from a ``str``) fails here.

Values inside their range that look like a slip of units (an angle in radians, a mass in grams) are used, with
one warning line."""

from __future__ import annotations

import math

import click
import pytest

from geometry.bounds import Bounds
from landscape.cli import cli, main
from landscape.cli.options import RangedParam, RobotParam
from tests.conftest import outside

TEXT_OPTIONS = {
    "--mesh": "a mesh file",
    "--com": "X,Y,Z in the mesh's units, refused outside the mesh's convex hull once the mesh is read",
    "--joints": "a joint map 'wing=...;leg=...'",
    "--model": "a model set: a shipped name or a .toml file",
    "--base": "a model set: a shipped name or a .toml file",
    "--scheduler": "a Dask scheduler address",
    "--host": "an address to bind",
    "--token": "a secret",
    "--vary": "TABLE.KEY=V1,V2 of a model set, each candidate checked as the model set checks its tables",
    "--cells": "WING:LEG cells, refused unless recorded",
    "sets": "model set names or files",
}
"""The options that take text rather than numbers, each with what it takes. A new option of type str must be
added here (saying why it is not a number) or be a ranged_option."""
NOT_NUMBERS = (click.Path, click.Choice, click.types.BoolParamType, click.File, RobotParam)


def _commands(cmd=cli, path=()):
    if isinstance(cmd, click.Group):
        for name, sub in sorted(cmd.commands.items()):
            yield from _commands(sub, (*path, name))
    else:
        yield path, cmd


PARAMS = [
    pytest.param(path, p, id=f"{' '.join(path)} {p.opts[0]}")
    for path, cmd in _commands()
    for p in cmd.params
    if not (isinstance(p, click.Option) and (p.is_flag or p.opts[0] in ("--help", "-h")))
]
RANGED = [x for x in PARAMS if isinstance(x.values[1].type, RangedParam)]


def _inside(b: Bounds) -> float:
    lo = b.lo if not math.isinf(b.lo) else b.hi - 2
    hi = b.hi if not math.isinf(b.hi) else lo + 2
    v = (lo + hi) / 2
    return float(math.floor(v) if b.integer else v)


def test_the_walk_sees_the_numeric_options():
    ids = {x.id for x in RANGED}
    assert {
        "sweep --cv",
        "simulate --cv",
        "compute --step",
        "serve --port",
        "physical validate --phase",
    } <= ids
    assert len(RANGED) >= 70


@pytest.mark.parametrize("path, p", PARAMS)
def test_every_number_is_a_ranged_option(path, p):
    """A numeric option is a ranged_option; text options say what they take; everything else takes no number."""
    t = p.type
    where = f"{' '.join(path)} {p.opts[0]}"
    if isinstance(t, RangedParam):
        return
    assert not isinstance(t, click.types._NumberParamTypeBase), (
        f"{where} is a bare {t.name}: make it a ranged_option (landscape/cli/options.py) with its Bounds"
    )
    if isinstance(t, click.Tuple):
        assert not any(isinstance(x, click.types._NumberParamTypeBase) for x in t.types), where
        return
    if t is click.STRING:
        assert p.opts[0] in TEXT_OPTIONS or p.name in TEXT_OPTIONS, (
            f"{where} reads text: if it holds numbers make it a ranged_option, else add it to TEXT_OPTIONS "
            "saying what it takes"
        )
        return
    assert isinstance(t, NOT_NUMBERS), (
        f"{where}: type {t!r} is neither a RangedParam nor known to hold no number"
    )


@pytest.mark.parametrize("path, p", RANGED)
def test_help_states_the_range(path, p):
    assert p.type.bounds.text in p.help, f"{' '.join(path)} {p.opts[0]}: {p.help!r}"


@pytest.mark.parametrize("path, p", RANGED)
def test_outside_the_range_is_one_line_and_exit_2(capsys, path, p):
    opt, b = p.opts[0], p.type.bounds
    for text in outside(b):
        assert main([*path, f"{opt}={text}"]) == 2, (path, opt, text)
        err = capsys.readouterr().err
        assert err == f"landscape: error: {b.outside_message(float(text), opt)}\n", err
    if b.integer and b.hi - b.lo >= 1:
        half = (b.lo if not math.isinf(b.lo) else b.hi - 1) + 0.5
        assert main([*path, f"{opt}={half}"]) == 2
        assert capsys.readouterr().err.startswith(f"landscape: error: {opt} must be a whole number")


@pytest.mark.parametrize("path, p", RANGED)
def test_inside_the_range_and_the_default_are_taken(path, p):
    b = p.type.bounds
    v = _inside(b)
    got = p.type.convert(str(v) if not b.integer else str(int(v)), p, None)
    assert got == ([v] if p.type.many else v)
    if isinstance(p.default, (int, float, str)):
        p.type.convert(p.default, p, None)  # the default is inside its own range


@pytest.mark.parametrize(
    "argv, want",
    [
        (["sweep", "--cv", "10%"], [0.1]),
        (["sweep", "--cv", "0%:25%:5%"], [0.0, 0.05, 0.1, 0.15, 0.2, 0.25]),
        (["sweep", "--cv", "0:0.25:0.05"], [0.0, 0.05, 0.1, 0.15, 0.2, 0.25]),
        (["simulate", "--cv", "12.5%"], 0.125),
        (["physical", "validate", "--cv", "0.3%"], 0.003),
        (["physical", "validate", "--phase", "Protocol"], "protocol"),
    ],
)
def test_a_percentage_is_read_only_when_written_as_one(argv, want):
    """'10%' is exactly the fraction 0.1 reads as (the same trial seeds); a bare 10 is refused (above)."""
    path, opt, text = argv[:-2], argv[-2], argv[-1]
    cmd = cli
    for name in path:
        cmd = cmd.commands[name]
    p = next(q for q in cmd.params if opt in q.opts)
    assert p.type.convert(text, p, None) == want


def test_cv_of_ten_is_refused_with_the_fraction_it_probably_means(capsys):
    assert main(["sweep", "--cv", "10", "--db", "unused.sqlite"]) == 2
    assert capsys.readouterr().err == (
        "landscape: error: --cv 10 is outside [0, 1]: Cv is sigma / Tl as a fraction; for 10 % give 0.1 or '10%'\n"
    )
    assert main(["sweep", "--cv", "0,15%", "--db", "unused.sqlite"]) == 2
    assert "mixes percentages and fractions" in capsys.readouterr().err


# ---------------------------------------------------------------------------------------------- unit slips
def test_an_angle_in_radians_is_warned_of_and_used(capsys):
    assert main(["compute", "--theta-w", "1.3", "--step", "30", "--method", "grid"]) == 0
    out, err = capsys.readouterr()
    assert err == (
        "landscape: warning: --theta-w 1.3 is taken in degrees, as every angle is; if you meant 1.3 rad, give "
        "--theta-w 74.48\n"
    )
    assert "theta_w 1.3°" in out


@pytest.mark.parametrize(
    "argv",
    [
        ["compute", "--theta-w", "30", "--step", "30", "--method", "grid"],  # degrees: no warning
        ["compute", "--theta-w", "0", "--step", "30", "--method", "grid"],  # 0 is 0 in any unit
        ["compute", "--theta-w", "3", "--step", "30", "--method", "grid"],  # 3 rad = 172 deg: past the limit
    ],
)
def test_plausible_degrees_are_not_warned_of(capsys, argv):
    assert main(argv) == 0
    assert capsys.readouterr().err == ""


def test_a_leg_angle_list_in_radians_is_warned_of_once(capsys, tmp_path):
    argv = ["barrier-map", "--theta-w", "74", "--theta-l", "0.2,0.5", "--step", "30", "--method", "grid"]
    assert main([*argv, "--out", str(tmp_path)]) == 0
    err = capsys.readouterr().err
    assert err.count("landscape: warning:") == 1
    assert "--theta-l values of at most 0.5 are taken in degrees" in err and "(0.2 rad is 11.46 deg)" in err


def test_a_mass_in_grams_is_warned_of_and_used(capsys, tmp_path):
    import trimesh

    stl = tmp_path / "box.stl"
    trimesh.creation.box(extents=(0.1, 0.06, 0.02)).export(stl)
    assert main(["compute", "--mesh", str(stl), "--mass", "260", "--step", "30", "--method", "grid"]) == 0
    assert capsys.readouterr().err == ""
    assert main(["compute", "--mesh", str(stl), "--mass", "2600", "--step", "30", "--method", "grid"]) == 0
    out, err = capsys.readouterr()
    assert (
        err
        == "landscape: warning: --mass 2600 kg is more than 1000 kg; if you meant grams, give --mass 2.6\n"
    )
    assert "mass         2600000.0 g" in out
