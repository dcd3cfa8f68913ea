"""The physical-robot chapter's commands print what the chapter shows (docs/physical/*.md), as the README's do."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.test_readme import _slow
from tests.test_readme import test_readme_command_prints_what_the_readme_shows as check_command

REPO = Path(__file__).resolve().parents[1]
CHAPTER = REPO / "docs" / "physical"


def _console_examples() -> list[tuple[str, str, list[str]]]:
    """Every `$ landscape ...` line of the chapter's ```console blocks: (page, command, the output lines under it)."""
    out: list[tuple[str, str, list[str]]] = []
    for page in sorted(CHAPTER.glob("*.md")):
        inside, current = False, None
        for line in page.read_text(encoding="utf-8").splitlines():
            if line.startswith("```"):
                inside, current = (line[3:].strip() == "console") and not inside, None
            elif inside and line.startswith("$ landscape"):
                current = (page.name, line[2:].strip(), [])
                out.append(current)
            elif inside and current is not None and line.strip() and not line.startswith("$"):
                current[2].append(line.rstrip())
    return out


EXAMPLES = _console_examples()


def test_the_chapter_shows_its_commands():
    pages = {page for page, _, _ in EXAMPLES}
    assert {"index.md", "data.md", "resting-pose.md", "outcomes.md", "side.md"} <= pages
    assert any(cmd.startswith("landscape physical validate") for _, cmd, _ in EXAMPLES)


@pytest.mark.parametrize(
    "cmd, expected",
    [
        pytest.param(c, e, marks=[pytest.mark.slow] if _slow(c) else [], id=f"{p}: {c[:50]}")
        for p, c, e in EXAMPLES
    ],
)
def test_chapter_command_prints_what_the_chapter_shows(cmd, expected, tmp_path):
    """Each command runs as written (from a scratch directory) and prints the chapter's stable lines, checked as
    the README's are."""
    check_command(cmd, expected, tmp_path)
