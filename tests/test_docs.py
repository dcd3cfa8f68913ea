"""The documentation's API reference covers every public name, its pages name no issue of the tracker, and its
gallery is what the docs build runs."""

from __future__ import annotations

import importlib
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
API = ROOT / "docs" / "api"


def _directives() -> tuple[set[str], set[str]]:
    """Modules given to ``automodule`` (with members) and objects given to ``autoclass``/``autoexception``/...
    in the API pages."""
    text = "\n".join(p.read_text(encoding="utf-8") for p in API.glob("*.md"))
    modules, objects = set(), set()
    for kind, name, rest in re.findall(r"^\.\. auto(\w+):: (\S+)\n((?:   .*\n)*)", text, flags=re.M):
        if kind == "module":
            if ":no-members:" not in rest:
                modules.add(name)
        else:
            objects.add(name)
    return modules, objects


@pytest.mark.parametrize("package", ["geometry", "landscape", "sim"])
def test_the_api_reference_documents_every_public_name(package):
    """Each name a package exports is documented: by ``automodule`` of the module that defines it (listed in that
    module's ``__all__`` if it has one, and carrying a docstring or ``#:`` comment autodoc shows), or by an
    explicit directive."""
    modules, objects = _directives()
    pkg = importlib.import_module(package)
    missing = []
    for name in pkg.__all__:
        where = pkg._EXPORTS[name]
        obj = getattr(pkg, name)
        if f"{where}.{name}" in objects:
            continue
        mod = importlib.import_module(where)
        public = name in getattr(mod, "__all__", [name])
        defined_here = getattr(obj, "__module__", where) == where or not callable(obj)
        if not (where in modules and public and defined_here):
            missing.append(f"{package}.{name} (from {where})")
    assert not missing, f"not in docs/api/: {missing}"


ISSUE_REFERENCE = re.compile(r"\bissues?\s*#?\d+|\(#\d+\)|(?<![\w&/#])#\d+\b(?!\s*[;{])", flags=re.I)
"""A reference to the tracker: "issue #15", "issue 15", "(#15)", "#15's". Not a colour (#333) or an anchor."""


def _doc_sources() -> list[Path]:
    """The documentation's own files: pages, gallery scripts, templates, configuration (not what the build
    generates)."""
    generated = {"_build", "auto_examples", "generated", "gen_modules"}
    return sorted(
        p
        for p in (ROOT / "docs").rglob("*")
        if p.suffix in {".md", ".rst", ".py", ".html", ".css", ".txt"} and not generated & set(p.parts)
    )


def test_the_docs_speak_of_the_project_not_its_tracker():
    """No page, example or template of docs/ refers to an issue by number (the changelog may)."""
    hits = [
        f"{p.relative_to(ROOT)}:{i}: {line.strip()[:100]}"
        for p in _doc_sources()
        for i, line in enumerate(p.read_text(encoding="utf-8").splitlines(), 1)
        if ISSUE_REFERENCE.search(line)
    ]
    assert hits == []


@pytest.mark.parametrize(
    "text, hit",
    [
        ("the Wilson rule of issue #15", True),
        ("see issue 15", True),
        ("Fix the map (#12)", True),
        ("#12's changes", True),
        ("color: #333;", False),
        ("[the benchmarks](benchmarks.md#landscape-and-barriers)", False),
        ("θw 74°, 2 issues", False),
    ],
)
def test_the_issue_reference_pattern(text, hit):
    assert bool(ISSUE_REFERENCE.search(text)) is hit


def test_the_gallery_has_six_executed_examples_with_quick_and_full_versions():
    examples = sorted((ROOT / "docs" / "examples").glob("plot_*.py"))
    assert len(examples) >= 6
    conf = (ROOT / "docs" / "conf.py").read_text(encoding="utf-8")
    assert '"filename_pattern": r"/plot_"' in conf  # every plot_*.py executes at build time
    for ex in examples:
        text = ex.read_text(encoding="utf-8")
        assert "plt." in text, f"{ex.name} draws no figure"
        if "LANDSCAPE_DOCS_FULL" in text:
            assert "Quick version" in text and "Full version" in text, ex.name
