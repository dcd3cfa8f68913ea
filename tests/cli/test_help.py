"""Help that answers (#17): every option of every command says what it is, its unit and its default, and the same
option has the same type everywhere. Walks the click tree, so a new option without help fails here."""

from __future__ import annotations

import re

import click
import pytest

from landscape.cli import cli, main
from landscape.cli.options import THETA_W_OUT_OF_JOINT_RANGE, THETA_W_OUT_OF_RANGE, RobotParam


def _commands(cmd=cli, path=()):
    if isinstance(cmd, click.Group):
        for name, sub in sorted(cmd.commands.items()):
            yield from _commands(sub, (*path, name))
    else:
        yield " ".join(path), cmd


OPTIONS = [
    pytest.param(name, p, id=f"{name} {p.opts[0]}")
    for name, cmd in _commands()
    for p in cmd.params
    if isinstance(p, click.Option) and p.opts[0] not in ("--help", "-h")
]
ANGLE = re.compile(r"\bdeg(rees?)?\b|°")
SECONDS = re.compile(r"\bs\b|\bseconds?\b")


def test_the_walk_sees_every_command():
    names = {name for name, _ in _commands()}
    assert {
        "compute",
        "render",
        "simulate",
        "sweep",
        "analyze evolution",
        "report",
        "physical table",
    } <= names


@pytest.mark.parametrize("name, opt", OPTIONS)
def test_every_option_has_help_and_a_default(name, opt):
    assert opt.help and opt.help.strip(), f"{name} {opt.opts[0]} has no help text"
    if not (opt.is_flag or opt.required or opt.show_default):
        assert "default" in opt.help.lower(), f"{name} {opt.opts[0]}: help does not say the default"


@pytest.mark.parametrize("name, opt", OPTIONS)
def test_angles_and_times_state_their_unit(name, opt):
    flag = opt.opts[0]
    if flag.startswith("--theta-") or flag == "--step":
        assert ANGLE.search(opt.help), f"{name} {flag}: help names no angle unit: {opt.help!r}"
    if flag in ("--duration", "--dt") or flag.endswith("-period"):
        assert SECONDS.search(opt.help), f"{name} {flag}: help names no time unit: {opt.help!r}"


def test_robot_is_one_shared_option():
    robots = [(name, p) for name, p in (o.values for o in OPTIONS) if p.opts[0] == "--robot"]
    assert len(robots) >= 8
    for name, p in robots:
        assert isinstance(p.type, RobotParam), f"{name} --robot is {p.type.name}"
        assert p.help.startswith("The robot: a URDF file or a registered name"), name


@pytest.mark.parametrize(
    "flag, commands",
    [
        ("--model", {"simulate", "sweep", "physical validate"}),
        ("--workers", {"sweep", "physical validate", "physical calibrate"}),
        ("--no-progress", {"sweep", "physical validate", "physical calibrate"}),
        ("--wing-period", {"simulate", "analyze evolution"}),
        ("--leg-period", {"simulate", "analyze evolution"}),
        ("--cv", {"physical validate", "physical calibrate"}),
        ("--seed", {"physical validate", "physical calibrate"}),
        ("--duration", {"physical validate", "physical calibrate"}),
    ],
)
def test_shared_options_are_alike(flag, commands):
    """An option shared from landscape/cli/options.py has one type, default and help in every command."""
    found = {name: p for name, p in (o.values for o in OPTIONS) if p.opts[0] == flag and name in commands}
    assert set(found) == commands
    first = found[min(commands)]
    for name, p in found.items():
        assert (p.name, repr(p.type), p.default, p.show_default, p.help) == (
            first.name,
            repr(first.type),
            first.default,
            first.show_default,
            first.help,
        ), name


@pytest.mark.parametrize(
    "argv",
    [
        ["compute", "--robot", "missing.urdf"],
        ["simulate", "--theta-w", "74", "--theta-l", "30", "--robot", "missing.urdf"],
        ["report", "--db", "x.sqlite", "--robot", "missing.urdf"],
    ],
)
def test_missing_robot_is_refused_alike(capsys, argv):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "URDF file missing.urdf not found" in err


@pytest.mark.parametrize("theta_w", ["-12", "120"])
def test_theta_w_range_is_the_same_for_compute_and_barrier_map(capsys, theta_w):
    """The landscape commands take the wing joints' whole range (built-in: [-10, 95])."""
    expected = THETA_W_OUT_OF_JOINT_RANGE.format(got=float(theta_w), lo=-10.0, hi=95.0, robot="builtin_robot")
    for argv in (["compute", "--step", "30"], ["barrier-map", "--step", "30"]):
        assert main([*argv, "--theta-w", theta_w]) == 2, argv
        assert capsys.readouterr().err == f"landscape: error: {expected}\n"


@pytest.mark.parametrize("theta_w", ["-5", "120"])
def test_theta_w_range_is_the_same_for_simulate_and_sweep(capsys, theta_w):
    """The trial commands open the wings from closed: [0, the joints' limit] (built-in: [-10, 95] -> [0, 95])."""
    expected = THETA_W_OUT_OF_RANGE.format(got=float(theta_w), lo=0.0, hi=95.0, robot="builtin_robot")
    for argv in (
        ["simulate", "--theta-l", "30", "--duration", "0.1"],
        ["sweep", "--db", "unused.sqlite", "--trials", "1"],
    ):
        assert main([*argv, "--theta-w", theta_w]) == 2, argv
        assert capsys.readouterr().err == f"landscape: error: {expected}\n"


def test_theta_w_inside_the_range_is_accepted(capsys):
    assert main(["compute", "--theta-w", "0", "--step", "30", "--method", "grid"]) == 0
    capsys.readouterr()
