"""The house's rules, checked on the source: one-way layers, no import circles, no Qt in the core
(in the import graph and in a fresh interpreter), and files a person can hold in their head.

The graph is read from the source with :mod:`ast` (every ``import`` anywhere in a module, also
inside functions, except under ``if TYPE_CHECKING:``), so an import deferred into a function to
dodge a circle is still a circle here. ``docs/architecture.md`` draws the same layers.
"""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = {"tactile_core": ROOT / "tactile_core", "tactile_tuner": ROOT / "app"}

#: tactile_core's layers, bottom first: a module may import its own layer and those below.
LAYERS = (
    ("tactile_core._shared", "tactile_core._version"),
    ("tactile_core.rendering",),
    ("tactile_core.device",),
    ("tactile_core.serve",),
    ("tactile_core.stream",),
    ("tactile_core.files",),
    ("tactile_core.experiments",),
    ("tactile_core.bench", "tactile_core.cli", "tactile_core.__main__", "tactile_core.script"),
)
QT = ("PySide6", "pyqtgraph", "PyQt5", "PyQt6", "shiboken6")
MAX_LINES = 500


def module_name(path: Path) -> tuple[str, bool]:
    for package, folder in PACKAGES.items():
        if folder in path.parents:
            parts = [package, *path.relative_to(folder).with_suffix("").parts]
            is_package = parts[-1] == "__init__"
            return ".".join(parts[:-1] if is_package else parts), is_package
    raise ValueError(path)


def sources() -> dict[str, tuple[Path, bool]]:
    found = {}
    for folder in PACKAGES.values():
        for path in folder.rglob("*.py"):
            if "__pycache__" not in path.parts:
                name, is_package = module_name(path)
                found[name] = (path, is_package)
    return found


SOURCES = sources()


def _type_checking_blocks(tree: ast.AST) -> set[int]:
    skip = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            for inner in node.body:
                skip.update(id(n) for n in ast.walk(inner))
    return skip


def imports_of(name: str) -> set[str]:
    """Every module ``name`` imports (absolute names, resolved to modules that exist)."""
    path, is_package = SOURCES[name]
    tree = ast.parse(path.read_text(), filename=str(path))
    skip = _type_checking_blocks(tree)
    found = set()
    for node in ast.walk(tree):
        if id(node) in skip:
            continue
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = name.split(".") if is_package else name.split(".")[:-1]
                base = base[: len(base) - (node.level - 1)]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module
            for alias in node.names:  # "from . import wire" imports the module "wire"
                sub = f"{target}.{alias.name}"
                found.add(sub if sub in SOURCES else target)
    return found


GRAPH = {
    name: {dep for dep in imports_of(name) if dep in SOURCES and dep != name} for name in SOURCES
}


def layer_of(name: str) -> int | None:
    for index, prefixes in enumerate(LAYERS):
        if any(name == p or name.startswith(p + ".") for p in prefixes):
            return index
    return None


def test_the_graph_was_read():
    # a walker that found nothing would pass every rule below
    assert len(SOURCES) > 60
    assert "tactile_core.rendering.shapes" in GRAPH["tactile_core.rendering.rasterize"]
    assert "tactile_core.device.wire" in GRAPH["tactile_core.device.link"]


def find_cycle(graph: dict[str, set[str]]) -> list[str] | None:
    """One import circle, as the list of modules around it, or None (iterative DFS)."""
    state: dict[str, int] = {}
    for start in sorted(graph):
        if start in state:
            continue
        stack = [(start, iter(sorted(graph[start])))]
        path = [start]
        state[start] = 1
        while stack:
            node, children = stack[-1]
            child = next(children, None)
            if child is None:
                state[node] = 2
                stack.pop()
                path.pop()
            elif state.get(child) == 1:
                return [*path[path.index(child) :], child]
            elif child not in state:
                state[child] = 1
                stack.append((child, iter(sorted(graph[child]))))
                path.append(child)
    return None


def test_find_cycle_finds_a_planted_circle():
    assert find_cycle({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": set()}) == ["a", "b", "c", "a"]
    assert find_cycle({"a": {"b"}, "b": set()}) is None


def test_no_import_circle_in_either_package():
    # A package's __init__ re-exporting its own modules is not a circle of the design: leave out
    # the edges from a package to the modules inside it.
    graph = {
        name: {d for d in deps if not (SOURCES[name][1] and d.startswith(name + "."))}
        for name, deps in GRAPH.items()
    }
    cycle = find_cycle(graph)
    assert cycle is None, "import circle: " + " -> ".join(cycle)


def test_every_core_module_is_in_a_layer():
    loose = [n for n in SOURCES if n.startswith("tactile_core.") and layer_of(n) is None]
    assert loose == [], f"modules outside the layers of test_architecture.LAYERS: {loose}"


def test_layers_only_import_downwards():
    wrong = []
    for name, deps in GRAPH.items():
        own = layer_of(name)
        if own is None:
            continue
        for dep in deps:
            if dep == "tactile_core" or dep.startswith("tactile_tuner"):
                wrong.append(f"{name} imports {dep}")
            elif (layer := layer_of(dep)) is not None and layer > own:
                wrong.append(f"{name} (layer {own}) imports {dep} (layer {layer})")
    assert wrong == [], "\n".join(sorted(wrong))


def test_the_core_never_imports_qt_or_the_tuner():
    wrong = []
    for name in SOURCES:
        if name.startswith("tactile_core"):
            for dep in imports_of(name):
                if dep.split(".")[0] in (*QT, "tactile_tuner"):
                    wrong.append(f"{name} imports {dep}")
    assert wrong == []


def test_the_core_loaded_in_a_fresh_interpreter_pulls_in_neither_qt_nor_the_tuner():
    # What the import graph above cannot see: a module that imports Qt through a plug-in, an
    # entry point or importlib. Every core module imported, from outside the source tree.
    code = (
        "import sys, importlib, pkgutil, tactile_core;"
        "[importlib.import_module(m.name) for m in"
        " pkgutil.walk_packages(tactile_core.__path__, 'tactile_core.')];"
        f"bad = [m for m in sys.modules if m.split('.')[0] in {(*QT, 'tactile_tuner', 'app')!r}];"
        "print(bad); sys.exit(1 if bad else 0)"
    )
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd="/",
                            timeout=120)  # fmt: skip
    assert result.returncode == 0, result.stdout + result.stderr


@pytest.mark.parametrize("name", sorted(SOURCES))
def test_no_module_is_longer_than_a_person_holds_in_their_head(name):
    lines = len(SOURCES[name][0].read_text().splitlines())
    assert lines <= MAX_LINES, f"{name} has {lines} lines (at most {MAX_LINES}): split it"


def test_test_modules_stay_short_too():
    long = {
        p.name: n
        for p in (ROOT / "tests").glob("*.py")
        if (n := len(p.read_text().splitlines())) > MAX_LINES
    }
    assert long == {}


#: Packages that are private by name but are the house's shared floor, imported from anywhere.
SHARED_FLOOR = ("tactile_core._shared", "tactile_core._version")


def private_owner(dep: str) -> str | None:
    """The package whose private module ``dep`` is (``tactile_core.device`` for
    ``tactile_core.device._wire_read``), or None for a public module."""
    if dep.startswith(SHARED_FLOOR):
        return None
    parts = dep.split(".")
    for i, part in enumerate(parts[1:], start=1):
        if part.startswith("_") and not part.startswith("__"):
            return ".".join(parts[:i])
    return None


def test_private_owner_names_the_package_of_a_private_module():
    assert private_owner("tactile_core.device._wire_read") == "tactile_core.device"
    assert (
        private_owner("tactile_core.rendering.methods._layout") == "tactile_core.rendering.methods"
    )
    assert private_owner("tactile_core.device.wire") is None
    assert private_owner("tactile_core._shared.validate") is None


def test_private_modules_are_imported_only_inside_their_package():
    # A private name imported across packages is a public name in disguise: promote it (list it
    # in the package's __init__ or a public module) instead.
    wrong = []
    for name, deps in GRAPH.items():
        for dep in deps:
            owner = private_owner(dep)
            if owner is not None and not (name == owner or name.startswith(owner + ".")):
                wrong.append(f"{name} imports {dep}")
    assert wrong == [], "\n".join(sorted(wrong))
