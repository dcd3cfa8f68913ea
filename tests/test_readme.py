"""The README's Python examples run as written (so a README line that stops working turns CI red)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

README = Path(__file__).resolve().parents[1] / "README.md"


def _python_blocks() -> list[str]:
    return re.findall(r"```python\n(.*?)```", README.read_text(encoding="utf-8"), flags=re.S)


def test_readme_has_the_python_twins():
    blocks = _python_blocks()
    assert blocks, "the README lost its Python API block"
    text = "\n".join(blocks)
    for cmd in ("compute", "barrier-map", "render", "simulate", "sweep", "export", "analyze", "report", "bench",
                "robot export"):
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
