"""The README's Python examples run as written (so a README line that stops working turns CI red)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

README = Path(__file__).resolve().parents[1] / "README.md"


def _fenced_blocks(info: str) -> list[str]:
    """The README's fenced code blocks whose info string is ``info`` ("" for plain ```)."""
    blocks, current = [], None
    for line in README.read_text(encoding="utf-8").splitlines():
        if line.startswith("```"):
            if current is None:
                current = [] if line[3:].strip() == info else False
            else:
                if current is not False:
                    blocks.append("\n".join(current) + "\n")
                current = None
        elif current:
            current.append(line)
        elif current == []:
            current.append(line)
    return blocks


def _python_blocks() -> list[str]:
    return _fenced_blocks(info="python")


def test_readme_has_the_python_twins():
    blocks = _python_blocks()
    assert blocks, "the README lost its Python API block"
    text = "\n".join(blocks)
    for cmd in (
        "compute",
        "barrier-map",
        "render",
        "simulate",
        "sweep",
        "export",
        "analyze",
        "report",
        "bench",
        "robot export",
        "physical table",
        "physical kinematics",
        "physical actuation",
        "physical validate",
        "physical calibrate",
        "serve",
    ):
        assert f"# landscape {cmd}" in text or f"; landscape {cmd}" in text, f"no Python twin for {cmd}"


@pytest.mark.parametrize("block", _python_blocks())
def test_readme_python_block_runs(block, capsys):
    pytest.importorskip("pybullet")
    namespace: dict = {}
    exec(compile(block, str(README), "exec"), namespace)
    out = capsys.readouterr().out
    assert "righting" in out and "mJ by roll" in out
    assert namespace["summary"].ran == 2 and namespace["page"].is_file()
    assert "speed-up" in namespace["table"] and "robot.urdf" in namespace["files_by_name"]


# ---------------------------------------------------------------------------------------------- $ landscape ...
VOLATILE = (
    "timing",
    "ms",
    " s ",
    " s;",
    " s)",
    "trials/s",
    "CPU",
    "/root/",
    "checked in",
    "...",
    "…",
    "wrote",
    "seed ",
    "0 already in",
    "s wall",
)
"""Output lines holding times, paths or machine-dependent counts: not compared."""


def _examples() -> list[tuple[str, list[str]]]:
    """Every `$ landscape ...` line of the README with the output lines printed under it."""
    out: list[tuple[str, list[str]]] = []
    for block in _fenced_blocks(info=""):
        current = None  # output lines belong to the command above them in the same block
        for line in block.splitlines():
            if line.startswith("$ landscape"):
                current = (line[2:].strip(), [])
                out.append(current)
            elif current is not None and line.strip() and not line.startswith("$"):
                current[1].append(line.rstrip())
    return out


def _slow(cmd: str) -> bool:
    return (
        "results.sqlite" in cmd
        or (" sweep" in cmd and "--trials" not in cmd)
        or " report" in cmd
        or " physical validate" in cmd
        or " physical calibrate" in cmd
    )


EXAMPLES = _examples()


def test_the_readme_shows_examples():
    assert len(EXAMPLES) >= 5 and any(c.startswith("landscape compute") for c, _ in EXAMPLES)


@pytest.mark.parametrize(
    "cmd, expected",
    [pytest.param(c, e, marks=[pytest.mark.slow] if _slow(c) else [], id=c[:60]) for c, e in EXAMPLES],
)
def test_readme_command_prints_what_the_readme_shows(cmd, expected, tmp_path):
    """Each README command runs as written (from a scratch directory) and prints the README's stable lines."""
    import shlex
    import subprocess
    import sys

    if "../shared" in cmd and not (README.parent.parent / "shared").is_dir():
        pytest.skip("needs ../shared")
    args = shlex.split(cmd)
    args = [str(README.parent.parent / a[3:]) if a.startswith("../shared") else a for a in args]
    exe = Path(sys.executable).parent / "landscape"
    r = subprocess.run([str(exe), *args[1:]], capture_output=True, text=True, cwd=tmp_path, timeout=900)
    text = r.stdout + r.stderr
    error_example = any(e.startswith("landscape: error:") for e in expected)
    assert (r.returncode == 2) if error_example else (r.returncode == 0), text
    if "--json" in args:
        _check_json_excerpt(expected, r.stdout, cmd)
        return
    for line in expected:
        if not any(v in line for v in VOLATILE):
            assert line.strip() in text, f"README line not printed by `{cmd}`:\n{line}\n--- got ---\n{text}"


def _leaves(obj, out: dict) -> dict:
    if isinstance(obj, dict):
        for k, v in obj.items():
            if isinstance(v, (dict, list)):
                _leaves(v, out)
            else:
                out.setdefault(k, []).append(v)
    elif isinstance(obj, list):
        out.setdefault("", []).extend(obj)
    return out


def _check_json_excerpt(expected: list[str], stdout: str, cmd: str) -> None:
    """A README JSON excerpt is abridged and rounded: every `"key": number` shown must be a value of that key
    in the real output, to the digits shown; every `"key": "text"` must be there as written."""
    import json

    values = _leaves(json.loads(stdout), {})
    pairs = re.findall(r'"(\w+)": (-?[0-9]+(?:\.[0-9]+)?|"[^"]*")', "\n".join(expected))
    assert pairs, cmd
    for key, shown in pairs:
        got = values.get(key, [])
        if shown.startswith('"'):
            assert shown.strip('"') in got, (key, shown, got)
        else:
            digits = len(shown.split(".")[1]) if "." in shown else 0
            assert any(isinstance(v, (int, float)) and round(v, digits) == float(shown) for v in got), (
                key,
                shown,
                got,
            )
