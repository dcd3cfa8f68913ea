"""The layers of the package, held by import-linter's contracts in pyproject.toml (a wrong import fails here
with the rule it breaks), and the import costs they buy."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def test_import_contracts_hold():
    pytest.importorskip("importlinter")
    from importlinter.cli import lint_imports

    assert lint_imports(config_filename=str(ROOT / "pyproject.toml"), no_cache=True) == 0


def test_import_contracts_catch_an_upward_import(tmp_path):
    """The contracts are not vacuous: a numerics module importing sim breaks one, and says which."""
    pytest.importorskip("importlinter")
    pkg = tmp_path / "tree"
    for sub in ("geometry", "landscape", "sim"):
        (pkg / sub).mkdir(parents=True)
        (pkg / sub / "__init__.py").write_text("")
    (pkg / "landscape" / "energy.py").write_text("import sim\n")
    for sub in ("barriers", "analysis", "viz", "cli", "service"):
        (pkg / "landscape" / sub).mkdir()
        (pkg / "landscape" / sub / "__init__.py").write_text("")
    for name in (
        "_energy_kernels",
        "_minima_kernels",
        "_computation_kernels",
        "grid",
        "minima",
        "computation",
        "gradient",
        "uncertainty",
    ):
        (pkg / "landscape" / f"{name}.py").write_text("")
    cfg = (ROOT / "pyproject.toml").read_text()
    (pkg / "pyproject.toml").write_text(cfg[cfg.index("[tool.importlinter]") :])
    out = subprocess.run(
        [
            sys.executable,
            "-c",
            "from importlinter.cli import lint_imports; import sys; "
            "sys.exit(lint_imports(config_filename='pyproject.toml', no_cache=True))",
        ],
        cwd=pkg,
        env={"PYTHONPATH": str(pkg), "PATH": ""},
        capture_output=True,
        text=True,
    )
    assert out.returncode != 0
    assert "the landscape numerics import only geometry" in out.stdout and "BROKEN" in out.stdout
    assert "landscape.energy -> sim" in out.stdout


@pytest.mark.parametrize(
    "module, heavy",
    [
        (
            "landscape.cli",
            (
                "pybullet",
                "scipy.stats",
                "matplotlib",
                "pyvista",
                "distributed",
                "numba",
                "trimesh",
                "fastapi",
                "uvicorn",
            ),
        ),
        ("landscape.computation", ("pybullet", "matplotlib", "pyvista", "click", "sim")),
    ],
)
def test_light_imports(module, heavy):
    """Importing the command line loads no engine, statistics or plotting; the numerics load no edge."""
    code = f"import sys, {module}; print(' '.join(sorted(m for m in {heavy!r} if m in sys.modules)))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd=ROOT)
    assert out.stdout.strip() == ""


@pytest.mark.parametrize("args", [["check", "."], ["format", "--check", "."]])
def test_ruff_holds_the_style(args):
    """ruff's rules (pyproject.toml: the banned imports per layer among them) and ruff format hold on the tree."""
    ruff = Path(sys.executable).parent / "ruff"
    if not ruff.is_file():
        pytest.skip("ruff is not installed (it comes with the test extra)")
    out = subprocess.run([str(ruff), *args], capture_output=True, text=True, cwd=ROOT)
    assert out.returncode == 0, out.stdout + out.stderr
