"""The package layering of docs/DESIGN.md section 1, checked on the source: who may import whom,
no import cycles between modules, no module over 400 lines, and no pyvista or optuna in `fem`."""

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("softcrawl", "geometry", "fem", "materials", "robot", "studies")
#: The project packages each package may import (besides itself).
ALLOWED = {
    "softcrawl": set(),
    "geometry": {"softcrawl"},
    "fem": {"softcrawl"},
    "materials": {"softcrawl", "fem"},
    "robot": {"softcrawl"},
    "studies": set(PACKAGES),
}
#: Third-party packages a package must not import.
FORBIDDEN = {"fem": {"pyvista", "optuna", "matplotlib"}}
MAX_LINES = 400
#: Modules still being split (each leaves this set when its split lands; it must end empty).
PENDING_SPLIT: set[str] = set()


def _modules():
    for package in PACKAGES:
        for path in sorted((ROOT / package).rglob("*.py")):
            yield package, path


def _imports(path: Path):
    """(module name, is it at module level) of every import in the file."""
    tree = ast.parse(path.read_text())
    top = set(map(id, tree.body))
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            names = [node.module]
        else:
            continue
        for name in names:
            yield name, id(node) in top


def _module_name(path: Path) -> str:
    parts = path.relative_to(ROOT).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


@pytest.mark.parametrize("package", PACKAGES)
def test_packages_import_only_what_the_layering_allows(package):
    bad = []
    for pkg, path in _modules():
        if pkg != package:
            continue
        for name, _ in _imports(path):
            root = name.split(".")[0]
            if root in PACKAGES and root != package and root not in ALLOWED[package]:
                bad.append(f"{path.relative_to(ROOT)} imports {name}")
            if root in FORBIDDEN.get(package, ()):
                bad.append(f"{path.relative_to(ROOT)} imports {name}")
    assert not bad, "\n".join(bad)


def test_no_import_cycles_between_modules():
    """Module-level and function-level imports alike: a cycle hidden inside a function is still
    a cycle of responsibilities."""
    names = {_module_name(p) for _, p in _modules()}
    graph = {}
    for _, path in _modules():
        me = _module_name(path)
        deps = set()
        for name, _ in _imports(path):
            while name and name not in names:
                name = name.rpartition(".")[0]
            if name and name != me and not me.startswith(name + "."):  # a package's own __init__
                deps.add(name)
        graph[me] = deps
    state, stack, cycles = {}, [], []

    def visit(node):
        state[node] = 1
        stack.append(node)
        for dep in graph.get(node, ()):
            if state.get(dep) == 1:
                cycles.append(" -> ".join(stack[stack.index(dep) :] + [dep]))
            elif dep not in state:
                visit(dep)
        stack.pop()
        state[node] = 2

    for node in sorted(graph):
        if node not in state:
            visit(node)
    assert not cycles, "\n".join(cycles)


def test_no_module_over_400_lines():
    long = []
    for _, path in _modules():
        name, n = str(path.relative_to(ROOT)), len(path.read_text().splitlines())
        if n > MAX_LINES and name not in PENDING_SPLIT:
            long.append(f"{name}: {n}")
    assert not long, "\n".join(long)


#: Packages checked for private names used across modules (the lead widens it as splits land).
NO_PRIVATE_IMPORTS = ("robot", "geometry", "materials")


def _private_uses(path: Path, modules: set[str]):
    """Private names (`_x`, not dunders) of other project modules that the file imports or uses."""
    tree = ast.parse(path.read_text())
    aliases = {}
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for a in node.names:
                if a.name in modules:
                    aliases[a.asname or a.name.split(".")[0]] = a.name
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            for a in node.names:
                private = a.name.startswith("_") and not a.name.startswith("__")
                if private and node.module.split(".")[0] in PACKAGES:
                    yield f"from {node.module} import {a.name}"
                if f"{node.module}.{a.name}" in modules:
                    aliases[a.asname or a.name] = f"{node.module}.{a.name}"
    for node in ast.walk(tree):
        if (
            isinstance(node, ast.Attribute)
            and isinstance(node.value, ast.Name)
            and node.value.id in aliases
            and node.attr.startswith("_")
            and not node.attr.startswith("__")
        ):
            yield f"{aliases[node.value.id]}.{node.attr}"


@pytest.mark.parametrize("package", NO_PRIVATE_IMPORTS)
def test_no_private_names_used_across_modules(package):
    """A helper that another module needs is public, in the module whose job it is."""
    modules = {_module_name(p) for _, p in _modules()}
    bad = [
        f"{path.relative_to(ROOT)}: {use}"
        for pkg, path in _modules()
        if pkg == package
        for use in _private_uses(path, modules)
    ]
    assert not bad, "\n".join(bad)
