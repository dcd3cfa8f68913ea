"""The README's two set-up commands, run in order in a fresh copy of the checkout, leave the Python API importable
from any directory (a numba cache written beside the installed sources by the first command once outlived its
uninstall and made ``landscape`` an empty namespace package after the second)."""

from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
README = REPO / "README.md"
#: what `pip install` of the checkout reads (the packages, their metadata and the pins)
INSTALLED = ("pyproject.toml", "README.md", "constraints.txt", "geometry", "landscape", "sim")


def readme_setup_commands() -> list[list[str]]:
    """The README's set-up commands (its first ``bash`` block), each split at ``&&`` into its steps."""
    text = README.read_text(encoding="utf-8")
    block = text.split("```bash\n", 1)[1].split("```", 1)[0]
    return [[step.strip() for step in line.split("&&")] for line in block.splitlines() if line.strip()]


def test_readme_setup_commands_are_the_two_installs():
    commands = readme_setup_commands()
    assert len(commands) == 2
    assert ".venv/bin/pip install ." in commands[0]
    assert any("pip install" in s and "-e" in s for s in commands[1])


def test_ci_runs_the_readme_test_command_and_the_e2e_tests():
    """.ci/run runs the README's second set-up command as written, and the tests that command leaves out."""
    ci = (REPO / ".ci" / "run").read_text(encoding="utf-8")
    second = " && ".join(readme_setup_commands()[1])
    assert second in ci, f".ci/run does not run the README's test command: {second}"
    assert "-m e2e" in ci


@pytest.mark.slow
@pytest.mark.timeout(1800)
def test_python_api_after_both_readme_commands(tmp_path):
    checkout = tmp_path / "checkout"
    for name in INSTALLED:
        src = REPO / name
        if src.is_dir():
            shutil.copytree(src, checkout / name, ignore=shutil.ignore_patterns("__pycache__", "*.egg-info"))
        else:
            checkout.mkdir(exist_ok=True)
            shutil.copy2(src, checkout / name)
    env = {k: v for k, v in os.environ.items() if k not in ("VIRTUAL_ENV", "PYTHONPATH", "NUMBA_CACHE_DIR")}
    env["LANDSCAPE_CACHE"] = str(tmp_path / "cache")  # robots and kernels of this copy stay in tmp_path
    for steps in readme_setup_commands():
        for step in steps:
            if "pytest" in step:  # the test suite itself, which this test is part of
                continue
            done = subprocess.run(step, shell=True, cwd=checkout, env=env, capture_output=True, text=True)
            assert done.returncode == 0, f"{step}\n{done.stdout[-2000:]}\n{done.stderr[-2000:]}"
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    code = (
        "import landscape; print(landscape.__file__); "
        "c = landscape.compute(landscape.load_robot(), theta_w_deg=74.0); "
        "print(f'{c.barrier.righting.barrier_j * 1e3:.3f}')"
    )
    done = subprocess.run(
        [str(checkout / ".venv" / "bin" / "python"), "-c", code],
        cwd=elsewhere,
        env=env,
        capture_output=True,
        text=True,
    )
    assert done.returncode == 0, done.stderr[-2000:]
    init, barrier_mj = done.stdout.split()
    assert Path(init) == checkout / "landscape" / "__init__.py"  # the editable install, not a stranded folder
    assert barrier_mj == "8.689"  # the README's righting barrier at 74 deg
    site = list((checkout / ".venv" / "lib").glob("python*/site-packages"))
    assert site and not (site[0] / "landscape").exists(), "the first install left files behind"
