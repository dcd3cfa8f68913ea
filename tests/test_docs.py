"""The documentation's API reference covers every public name, its pages name no issue of the tracker, and its
gallery is what the docs build runs."""

from __future__ import annotations

import importlib
import re
from pathlib import Path

import pytest

from tests.conftest import load_script

ROOT = Path(__file__).resolve().parents[1]
API = ROOT / "docs" / "api"


@pytest.fixture(scope="module")
def apiref():
    """docs/_ext/apiref.py: the rule of what the reference documents, as the docs build applies it."""
    return load_script("docs/_ext/apiref.py")


def _tables() -> tuple[set[str], dict[str, set[str]]]:
    """The API index's autosummary entries as full names: the modules (the tables with ``:toctree:``, which generate
    the module pages, whose own tables generate the function and class pages), and the objects of every other
    table by the heading above it (a module's name, or ``import PACKAGE`` for the names a package exports)."""
    text = (API / "index.md").read_text(encoding="utf-8")
    modules, objects = set(), {}
    block = r"^\.\. autosummary::\n((?:   :.*\n)*)\n((?:   \S.*\n)+)"
    for heading, body in re.findall(r"^#+ (.*)\n((?:(?!#).*\n)*)", text, flags=re.M):
        for options, entries in re.findall(block, body, flags=re.M):
            names = {e.strip().lstrip("~") for e in entries.splitlines()}
            if ":toctree:" in options:
                modules |= names
            else:
                objects.setdefault(heading.strip("` "), set()).update(names)
    return modules, objects


def _documented_data(module: str) -> set[str]:
    """Module-level names with a docstring or ``#:`` comment: the constants a module page shows."""
    from sphinx.pycode import ModuleAnalyzer

    return {name for scope, name in ModuleAnalyzer.for_module(module).find_attr_docs() if not scope}


def test_every_module_has_a_page(apiref):
    modules, _ = _tables()
    assert modules == set(apiref.modules())


def test_every_public_function_and_class_has_a_line_in_the_index(apiref):
    """Under each module's heading the index lists its functions and classes, the ones its page documents (one
    page each, from the module page's table)."""
    _, objects = _tables()
    wrong = {
        m: (sorted(want - got), sorted(got - want))
        for m in apiref.modules()
        if (want := {f"{m}.{n}" for names in apiref.members(m).values() for n in names})
        != (got := objects.get(m, set()))
    }
    assert wrong == {}, "docs/api/index.md: module -> (missing, not public there)"


@pytest.mark.parametrize("package", ["geometry", "landscape", "sim"])
def test_the_api_reference_documents_every_public_name(apiref, package):
    """Each name a package exports has a line in the index's table of that package, under the module that defines
    it, whose page documents it: a function or class has its own page, a constant its docstring or ``#:`` comment
    on the module's page."""
    _, objects = _tables()
    pkg = importlib.import_module(package)
    missing = []
    for name in pkg.__all__:
        where = pkg._EXPORTS[name]
        if f"{where}.{name}" not in objects[f"import {package}"]:
            missing.append(f"{package}.{name} (from {where}) is not in the table `import {package}`")
        elif callable(getattr(pkg, name)):
            if name not in {n for names in apiref.members(where).values() for n in names}:
                missing.append(f"{package}.{name}: {where} does not list it (its __all__?)")
        elif name not in _documented_data(where):
            missing.append(f"{package}.{name}: no docstring or #: comment in {where}")
    assert not missing


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
