"""What the API reference documents: the modules, each one's public functions and classes, and the names the
gallery's examples may call them by.

The reference's index (``docs/api/index.md``) lists the modules in autosummary tables and, under each module,
its functions and classes; the module template (``docs/_templates/autosummary/module.rst``) gives each module a
page with its docstring, its constants and a table that generates one page per function or class. The rule of
what a module documents lives here, once: the Sphinx build passes it to the templates and ``tests/test_docs.py``
checks the index against it.

A Sphinx extension: ``setup`` puts ``api_members`` (module -> kind -> names) and ``api_aliases`` (an object's
documented name -> every name it is importable by, for sphinx-gallery's "Examples using" mini-galleries) into
``autosummary_context``.
"""

from __future__ import annotations

import importlib
import inspect
import pkgutil

PACKAGES = ("geometry", "landscape", "sim")
"""The packages the reference documents."""
EDGE = ("landscape.cli", "landscape.service", "landscape.viz")
"""Their edge: the command line, the service and the drawing code, documented as commands and endpoints (the
how-to guides), not here."""
KINDS = ("functions", "classes", "exceptions")


def _private(name: str) -> bool:
    return any(part.startswith("_") for part in name.split("."))


def _public_part(module: str) -> str:
    """The module path up to its first private part: ``landscape.barriers._base`` -> ``landscape.barriers``."""
    parts = module.split(".")
    return ".".join(parts[: next((i for i, p in enumerate(parts) if p.startswith("_")), len(parts))])


def modules() -> list[str]:
    """Every public module of :data:`PACKAGES` outside :data:`EDGE`, packages first, in import-path order."""
    out = []
    for package in PACKAGES:
        out.append(package)
        pkg = importlib.import_module(package)
        out += sorted(
            m.name
            for m in pkgutil.walk_packages(pkg.__path__, f"{package}.")
            if not _private(m.name) and not m.name.startswith(EDGE)
        )
    return out


def members(module: str) -> dict[str, list[str]]:
    """The public functions, classes and exceptions ``module`` documents, by kind, in the order of its ``__all__``
    (else of definition).

    A name is public when it is in the module's ``__all__`` (if it has one) and does not start with ``_``. The
    module documents it when it defines it, or when its ``__all__`` re-exports it from one of its own private
    modules (``landscape.barriers.Barrier`` from ``landscape.barriers._base``); a re-export of another public
    module's name (``landscape.compute``) is documented there.
    """
    mod = importlib.import_module(module)
    names = getattr(mod, "__all__", None)
    if names is None:
        names = [n for n in vars(mod) if not n.startswith("_")]
    out: dict[str, list[str]] = {k: [] for k in KINDS}
    for name in names:
        obj = getattr(mod, name)
        if not (inspect.isclass(obj) or inspect.isfunction(obj)):
            continue
        home = getattr(obj, "__module__", None)
        if home != module and not (hasattr(mod, "__all__") and home and _public_part(home) == module):
            continue
        if inspect.isfunction(obj):
            out["functions"].append(name)
        else:
            out["exceptions" if issubclass(obj, BaseException) else "classes"].append(name)
    return out


def aliases(module: str, name: str, among: list[str]) -> list[str]:
    """Every ``M.name`` the object ``module.name`` is importable by, ``M`` one of the modules ``among``
    (``landscape.computation.compute`` -> ``landscape.compute``, ``landscape.computation.compute``;
    ``geometry.robots.load_robot`` -> ``geometry.load_robot``, ``geometry.robots.load_robot``,
    ``landscape.load_robot``): sphinx-gallery files an example's call under a name the example can use."""
    obj = getattr(importlib.import_module(module), name)
    return [f"{m}.{name}" for m in among if getattr(importlib.import_module(m), name, None) is obj]


def context() -> dict:
    """The templates' ``api_members`` and ``api_aliases``."""
    mods = modules()
    api_members = {m: members(m) for m in mods}
    api_aliases = {
        f"{m}.{n}": aliases(m, n, mods)
        for m, kinds in api_members.items()
        for names in kinds.values()
        for n in names
    }
    return {"api_members": api_members, "api_aliases": api_aliases}


def _config_inited(app, config) -> None:
    config.autosummary_context = {**config.autosummary_context, **context()}


def setup(app):
    app.connect("config-inited", _config_inited)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
