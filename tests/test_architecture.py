"""The module import graph of vessel_gym and cfd: no import cycles, and the dependency rules of the design.

The graph is read from the source with :mod:`ast`, without importing anything, so it sees every import
statement wherever it stands: at module level, inside functions (lazy imports of optional or heavy
dependencies), and under ``if TYPE_CHECKING:``. Lazy and type-only imports count as edges: a lazy import
that closes a cycle only hides it from the interpreter, and a type-only one still ties the two modules'
designs together.

How an import becomes an edge:

- ``import a.b.c`` and ``from a.b import c`` (where ``a/b/c.py`` or ``a/b/c/`` exists) are edges to ``a.b.c``;
  ``from a.b import name`` (a name defined in ``a/b/__init__.py``) is an edge to the package ``a.b``.
- Relative imports are resolved against the importing module's package.
- The parent packages that Python initialises on the way (``a`` and ``a.b`` for ``a.b.c``) are not edges:
  they are the same for every module of a package and would make every package that imports its own
  submodules in ``__init__`` look cyclic.
- Imports computed at run time (``importlib.import_module(f"...{name}")``) cannot be read from the source
  and are not in the graph; vessel_gym.envs uses one to resolve its lazily exported classes.

Only modules of the two packages are nodes; third-party and standard-library imports are kept as the
"external" names of each module for the dependency rules.
"""

from __future__ import annotations

import ast
import re
from collections.abc import Iterator
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("vessel_gym", "cfd")

# Groups of modules tied together by import cycles that exist today (each group a strongly connected
# component of the graph, its modules sorted). Remove a group when its cycles are broken: the test fails on
# a group not listed and on a listed group that no longer exists exactly, so the list can only shrink.
KNOWN_CYCLES: frozenset[tuple[str, ...]] = frozenset()

# vessel_gym.physics is the equations: it never reaches up into the tasks, the link, the viewer, the
# manoeuvre trials or the controllers, nor into gymnasium, pygame or sockets (DESIGN.md, "Layout").
PHYSICS_FORBIDDEN = (
    "vessel_gym.envs",
    "vessel_gym.net",
    "vessel_gym.ui",
    "vessel_gym.manoeuvres",
    "vessel_gym.control",
    "gymnasium",
    "pygame",
    "socket",
)
# cfd uses vessel_gym only for the ship-file format and the physics (to validate the ship file it writes
# and to run captive tests on the model): DESIGN.md, "cfd -> physics data format only"; and the command lines'
# shared conventions (one-line errors, exit code 2, defaults in --help), whose one home is vessel_gym.cli_args.
CFD_ALLOWED_FROM_VESSEL_GYM = ("vessel_gym.physics", "vessel_gym.cli_args")

# vessel_gym.net is the link (UDP, protocol, NMEA, AIS, the panels' UDP client); what a person sees and drives
# (pygame chart, keyboard play, helm and viewer panels) is vessel_gym.ui, which may use net but not the other
# way round. The CLI launches both and may import both.
UI = ("vessel_gym.ui",)

# A module doing one job stays short enough to read: at most MAX_MODULE_LINES lines in vessel_gym and agents
# (cfd has its own, stricter limit below). These modules are longer today and wait to be split; each leaves
# the list once it is down to SPLIT_TARGET_LINES (the test fails on a listed module that is that short or
# gone), so the list can only shrink, and no new module joins it.
MAX_MODULE_LINES = 700
SPLIT_TARGET_LINES = 600
LONG_MODULES_TO_SPLIT: frozenset[str] = frozenset()


@dataclass
class Module:
    name: str
    path: Path
    is_package: bool
    internal: set[str] = field(default_factory=set)  # modules of PACKAGES it imports
    external: set[str] = field(default_factory=set)  # everything else it imports (top-level dotted names)


def _module_name(path: Path) -> tuple[str, bool]:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    is_package = parts[-1] == "__init__"
    if is_package:
        parts.pop()
    return ".".join(parts), is_package


def _walk_sources() -> Iterator[Path]:
    for pkg in PACKAGES:
        yield from sorted((ROOT / pkg).rglob("*.py"))


@cache
def graph() -> dict[str, Module]:
    """Every module of vessel_gym and cfd with the modules it imports."""
    modules: dict[str, Module] = {}
    for path in _walk_sources():
        name, is_package = _module_name(path)
        modules[name] = Module(name, path, is_package)

    def resolve(target: str, mod: Module) -> None:
        if target.split(".")[0] not in PACKAGES:
            mod.external.add(target)
            return
        while target and target not in modules:  # a name inside a module: the module itself
            target = target.rpartition(".")[0]
        if target and target != mod.name:
            mod.internal.add(target)

    for mod in modules.values():
        tree = ast.parse(mod.path.read_text(), filename=str(mod.path))
        package = mod.name if mod.is_package else mod.name.rpartition(".")[0]
        for node in ast.walk(tree):
            if isinstance(node, ast.Import):
                for alias in node.names:
                    resolve(alias.name, mod)
            elif isinstance(node, ast.ImportFrom):
                if node.level:
                    base = package.split(".")
                    base = base[: len(base) - (node.level - 1)]
                    stem = ".".join(base + ([node.module] if node.module else []))
                else:
                    stem = node.module or ""
                for alias in node.names:
                    sub = f"{stem}.{alias.name}"
                    resolve(sub if sub in modules else stem, mod)
    return modules


def cyclic_groups(modules: dict[str, Module]) -> list[tuple[str, ...]]:
    """The groups of modules that import each other in a cycle: every strongly connected component of more
    than one module (Tarjan's algorithm), each as a sorted tuple, sorted."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found: list[tuple[str, ...]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(modules[v].internal):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                found.append(tuple(sorted(comp)))

    for v in sorted(modules):
        if v not in index:
            visit(v)
    return sorted(found)


def cycle_through(component: tuple[str, ...], modules: dict[str, Module]) -> tuple[str, ...]:
    """The shortest closed import path from the group's first module back to it (breadth-first search)."""
    start, members = component[0], set(component)
    parents: dict[str, str] = {}
    frontier = [start]
    while frontier:
        nxt = []
        for v in frontier:
            for w in sorted(modules[v].internal & members):
                if w == start:
                    path = [v]
                    while path[-1] != start:
                        path.append(parents[path[-1]])
                    return tuple(reversed(path))
                if w not in parents:
                    parents[w] = v
                    nxt.append(w)
        frontier = nxt
    raise AssertionError(f"no cycle through {component}")  # pragma: no cover - a component has one


def _within(name: str, prefixes: tuple[str, ...]) -> bool:
    return any(name == p or name.startswith(p + ".") for p in prefixes)


# -- the graph reader itself, on a package written for the purpose ------------------------------------------------


def test_reader_sees_function_level_relative_and_type_checking_imports(tmp_path, monkeypatch):
    pkg = tmp_path / "cfd"
    (pkg / "sub").mkdir(parents=True)
    (pkg / "__init__.py").write_text("VERSION = 1\n")
    (pkg / "sub" / "__init__.py").write_text("")
    (pkg / "a.py").write_text("from . import b\nfrom .sub.c import thing\n")
    (pkg / "b.py").write_text(
        "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from cfd.a import x\n"
        "def f():\n    import socket\n    from . import VERSION\n"
    )
    (pkg / "sub" / "c.py").write_text("def g():\n    from ..a import y\n")
    (tmp_path / "vessel_gym").mkdir()
    monkeypatch.setattr(__import__(__name__), "ROOT", tmp_path)
    graph.cache_clear()
    try:
        g = graph()
        assert g["cfd.a"].internal == {"cfd.b", "cfd.sub.c"}
        assert g["cfd.b"].internal == {"cfd.a", "cfd"} and "socket" in g["cfd.b"].external
        assert g["cfd.sub.c"].internal == {"cfd.a"}
        assert cyclic_groups(g) == [("cfd.a", "cfd.b", "cfd.sub.c")]
        # the shortest cycle through the first module: a -> b -> a
        assert cycle_through(("cfd.a", "cfd.b", "cfd.sub.c"), g) == ("cfd.a", "cfd.b")
    finally:
        graph.cache_clear()


# -- the rules ---------------------------------------------------------------------------------------------------


def test_the_graph_covers_both_packages():
    g = graph()
    assert {"vessel_gym.physics.simulation", "vessel_gym.net.wrapper", "cfd.pipeline", "cfd.cli"} <= set(g)
    assert "cfd.runner" in g["cfd.cli"].internal  # a function-level import is read too


def test_no_import_cycles():
    g = graph()
    found = set(cyclic_groups(g))
    new = sorted(found - KNOWN_CYCLES)
    assert not new, "import cycles: " + "; ".join(" -> ".join(cycle_through(c, g) + (c[0],)) for c in new)
    gone = sorted(KNOWN_CYCLES - found)
    assert not gone, f"no longer cyclic as listed, update KNOWN_CYCLES: {gone}"


@pytest.mark.parametrize("name", sorted(n for n in graph() if _within(n, ("vessel_gym.physics",))))
def test_physics_depends_on_nothing_above_it(name):
    mod = graph()[name]
    bad = sorted(m for m in mod.internal | mod.external if _within(m, PHYSICS_FORBIDDEN))
    assert not bad, f"{name} imports {', '.join(bad)}"


@pytest.mark.parametrize("name", sorted(n for n in graph() if _within(n, ("cfd",))))
def test_cfd_uses_only_the_ship_format_and_physics_of_vessel_gym(name):
    mod = graph()[name]
    bad = sorted(
        m for m in mod.internal if _within(m, ("vessel_gym",)) and not _within(m, CFD_ALLOWED_FROM_VESSEL_GYM)
    )
    assert not bad, f"{name} imports {', '.join(bad)}"


def test_net_reads_no_private_attribute_of_another_object():
    """The link reaches the physics and the environments through their public calls (the helm through
    ``Simulation.override_helm``), never through another object's ``_private`` attributes."""
    bad = []
    for name, mod in graph().items():
        if not _within(name, ("vessel_gym.net",)):
            continue
        for node in ast.walk(ast.parse(mod.path.read_text())):
            if (
                isinstance(node, ast.Attribute)
                and node.attr.startswith("_")
                and not node.attr.startswith("__")
                and not (isinstance(node.value, ast.Name) and node.value.id in ("self", "cls"))
            ):
                bad.append(f"{name}:{node.lineno} .{node.attr}")
    assert not bad, "private attributes read from outside: " + ", ".join(bad)


def test_no_cfd_module_over_600_lines():
    """A module doing one job stays short enough to read (cfd's case writer was split at 997 lines)."""
    long = {n: len(m.path.read_text().splitlines()) for n, m in graph().items() if _within(n, ("cfd",))}
    assert all(v <= 600 for v in long.values()), {n: v for n, v in long.items() if v > 600}


def test_net_imports_nothing_from_ui():
    """The link works without a screen: net never imports ui."""
    found = {
        (name, m)
        for name, mod in graph().items()
        if _within(name, ("vessel_gym.net",))
        for m in mod.internal
        if _within(m, UI)
    }
    assert not found, "net imports ui: " + ", ".join(f"{a} -> {b}" for a, b in sorted(found))


def test_ui_and_traffic_live_in_their_homes():
    """What a person sees is in ui/, the scenarios' traffic beside the scenarios; the old homes are gone."""
    g = graph()
    assert {
        "vessel_gym.ui.chart",
        "vessel_gym.ui.play",
        "vessel_gym.ui.panels",
        "vessel_gym.ui.view3d",
        "vessel_gym.scenarios.traffic",
    } <= set(g)
    assert not any(
        _within(m, UI) for m in g["vessel_gym.net.clients"].internal | g["vessel_gym.net.clients"].external
    )
    assert "pygame" not in g["vessel_gym.net.clients"].external


# Former homes of moved modules: removed (version 0.1 keeps no re-exports), so each name has one home.
OLD_HOMES = ("vessel_gym.render", "vessel_gym.play", "vessel_gym.net.traffic", "vessel_gym.net.view3d")


def _imported_names(tree: ast.AST) -> Iterator[str]:
    """Every dotted name an import statement of ``tree`` reaches: ``import a.b`` gives a.b, ``from a import b, c``
    gives a.b and a.c (a submodule or a name, either way what the statement asks for)."""
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            yield from (alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and not node.level:
            yield node.module
            yield from (f"{node.module}.{alias.name}" for alias in node.names)


@pytest.mark.parametrize("old", OLD_HOMES)
def test_old_homes_are_gone(old):
    assert not [m for m in graph() if _within(m, (old,))], f"{old} is back: import the name from its one home"
    users = [
        str(path.relative_to(ROOT))
        for folder in ("vessel_gym", "cfd", "agents", "tests", "benchmarks", "docs")
        for path in sorted((ROOT / folder).rglob("*.py"))
        if any(_within(name, (old,)) for name in _imported_names(ast.parse(path.read_text())))
    ]
    # the docs' code: "import a.b", "from a.b import c", "from a import b"
    parent, _, leaf = old.rpartition(".")
    pattern = re.compile(
        rf"(from|import)\s+{re.escape(old)}\b|from\s+{re.escape(parent)}\s+import\s[^\n]*\b{leaf}\b"
    )
    users += [
        str(path.relative_to(ROOT))
        for path in [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]
        if pattern.search(path.read_text())
    ]
    assert not users, f"{old} is still imported in {users}"


def _line_counts() -> dict[str, int]:
    counts = {}
    for pkg in ("vessel_gym", "agents"):
        for path in sorted((ROOT / pkg).rglob("*.py")):
            counts[_module_name(path)[0]] = len(path.read_text().splitlines())
    return counts


def test_no_module_over_700_lines_outside_the_list_to_split():
    counts = _line_counts()
    long = {n: v for n, v in counts.items() if v > MAX_MODULE_LINES and n not in LONG_MODULES_TO_SPLIT}
    assert not long, f"modules over {MAX_MODULE_LINES} lines (split them by job): {long}"
    done = sorted(n for n in LONG_MODULES_TO_SPLIT if counts.get(n, 0) <= SPLIT_TARGET_LINES)
    assert not done, f"gone or down to {SPLIT_TARGET_LINES} lines, remove from LONG_MODULES_TO_SPLIT: {done}"


def _python_files() -> Iterator[Path]:
    for folder in ("vessel_gym", "cfd", "agents", "tests", "benchmarks"):
        yield from sorted((ROOT / folder).rglob("*.py"))


def test_no_sys_path_edits():
    """Every import resolves through the installed package (vessel_gym, cfd and agents are one distribution):
    no module, script, test or benchmark edits sys.path."""
    found = []
    for path in _python_files():
        for node in ast.walk(ast.parse(path.read_text())):
            if (
                isinstance(node, ast.Attribute)
                and node.attr == "path"
                and isinstance(node.value, ast.Name)
                and node.value.id == "sys"
            ):
                found.append(f"{path.relative_to(ROOT)}:{node.lineno}")
    assert not found, f"sys.path used in {found}"


def test_the_command_lines_share_one_home_for_their_conventions():
    """One-line errors, exit code 2 and defaults in --help are vessel_gym.cli_args's: no command line defines its
    own argparse parser or help formatter class, nor its own error printer."""
    home = ROOT / "vessel_gym" / "cli_args.py"
    copies = []
    for path in _python_files():
        if path == home or path.is_relative_to(ROOT / "tests"):
            continue
        for node in ast.walk(ast.parse(path.read_text())):
            bases = [ast.unparse(b) for b in getattr(node, "bases", [])]
            if isinstance(node, ast.ClassDef) and any(
                b.endswith(("ArgumentParser", "HelpFormatter")) for b in bases
            ):
                copies.append(f"{path.relative_to(ROOT)}:{node.name}")
            if isinstance(node, ast.FunctionDef) and node.name.lstrip("_") == "error_line":
                copies.append(f"{path.relative_to(ROOT)}:{node.name}")
    assert not copies, f"copies of vessel_gym.cli_args's helpers: {copies}"
