"""The package layering of docs/DESIGN.md ("Layout"), checked on the source: who may import whom,
no import cycles between modules, no module over 400 lines, no pyvista or optuna in `fem`, and
every module loaded under one name only."""

import ast
import importlib
import pkgutil
import re
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
#: Layer -> (folder, module prefix). `softcrawl.core` is the package root's own modules (errors,
#: checks, files, jsonio, units, paper); the root's `__init__` (the public API) may import everything.
LAYERS = {
    "softcrawl.core": (ROOT / "softcrawl", "softcrawl"),
    "softcrawl.analytic": (ROOT / "softcrawl" / "analytic", "softcrawl.analytic"),
    "softcrawl.materials": (ROOT / "softcrawl" / "materials", "softcrawl.materials"),
    "softcrawl.geometry": (ROOT / "geometry", "softcrawl.geometry"),
    "softcrawl.fem": (ROOT / "fem", "softcrawl.fem"),
    "softcrawl.studies": (ROOT / "studies", "softcrawl.studies"),
}
PACKAGES = tuple(LAYERS)
#: The project layers each layer may import (besides itself).
ALLOWED = {
    "softcrawl.core": set(),
    "softcrawl.geometry": {"softcrawl.core"},
    "softcrawl.fem": {"softcrawl.core"},
    "softcrawl.materials": {"softcrawl.core", "softcrawl.fem"},
    "softcrawl.analytic": {"softcrawl.core"},
    "softcrawl.studies": set(PACKAGES),
}
#: Third-party packages a layer must not import.
FORBIDDEN = {"softcrawl.fem": {"pyvista", "optuna", "matplotlib"}}
MAX_LINES = 400
#: Modules still being split (each leaves this set when its split lands; it must end empty).
PENDING_SPLIT: set[str] = set()


def _layer_of_file(path: Path) -> str:
    for layer, (folder, _) in LAYERS.items():
        if layer != "softcrawl.core" and path.is_relative_to(folder):
            return layer
    return "softcrawl.core"


def _modules():
    """(layer, path) of every project module but the entry points above every layer: the public
    API (softcrawl/__init__.py) and `python -m softcrawl` (softcrawl/__main__.py)."""
    entry_points = {ROOT / "softcrawl" / "__init__.py", ROOT / "softcrawl" / "__main__.py"}
    for layer, (folder, _) in LAYERS.items():
        paths = folder.glob("*.py") if layer == "softcrawl.core" else folder.rglob("*.py")
        for path in sorted(paths):
            if path not in entry_points:
                yield layer, path


def _layer_of_name(name: str) -> str | None:
    """The layer of an imported module name, None for a third-party one."""
    parts = name.split(".")
    if parts[0] != "softcrawl":
        return None
    if len(parts) > 1 and f"softcrawl.{parts[1]}" in LAYERS:
        return f"softcrawl.{parts[1]}"
    return "softcrawl.core"


def _import_nodes(tree: ast.Module):
    """(node, the absolute module names it imports, is it at module level) of every import."""
    top = set(map(id, tree.body))
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            yield node, [a.name for a in node.names], id(node) in top
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            yield node, [node.module], id(node) in top


def _imports(path: Path):
    """(module name, is it at module level) of every import in the file."""
    for _, names, at_top in _import_nodes(ast.parse(path.read_text())):
        for name in names:
            yield name, at_top


def _module_name(path: Path) -> str:
    folder, prefix = LAYERS[_layer_of_file(path)]
    parts = path.relative_to(folder).with_suffix("").parts
    parts = parts[:-1] if parts[-1] == "__init__" else parts
    return ".".join((prefix, *parts))


@pytest.mark.parametrize("package", PACKAGES)
def test_packages_import_only_what_the_layering_allows(package):
    bad = []
    for pkg, path in _modules():
        if pkg != package:
            continue
        for name, _ in _imports(path):
            layer = _layer_of_name(name)
            if layer is not None and layer != package and layer not in ALLOWED[package]:
                bad.append(f"{path.relative_to(ROOT)} imports {name}")
            if name.split(".")[0] in FORBIDDEN.get(package, ()):
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
NO_PRIVATE_IMPORTS = ("softcrawl.analytic", "softcrawl.geometry", "softcrawl.materials")


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
                if private and _layer_of_name(node.module) is not None:
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


def test_every_module_has_one_name():
    """Importing every module of the package loads each file once, under its `softcrawl.` name: no
    bare `fem`, `geometry`, `studies`, `robot` or `materials` import name reaches sys.modules."""
    import softcrawl

    for info in pkgutil.walk_packages(softcrawl.__path__, "softcrawl."):
        if not info.name.endswith("__main__"):
            importlib.import_module(info.name)
    for name in ("softcrawl.fem", "softcrawl.geometry", "softcrawl.studies"):
        for info in pkgutil.walk_packages(importlib.import_module(name).__path__, name + "."):
            importlib.import_module(info.name)
    seen: dict[str, str] = {}
    twice = []
    for name, module in list(sys.modules.items()):
        file = getattr(module, "__file__", None)
        sources = [folder for folder, _ in LAYERS.values()]  # not ROOT: a venv may live inside it
        if not file or not any(Path(file).resolve().is_relative_to(f) for f in sources):
            continue
        key = str(Path(file).resolve())
        if key in seen and seen[key] != name:
            twice.append(f"{key}: {seen[key]} and {name}")
        seen[key] = name
        if not name.startswith("softcrawl"):
            twice.append(f"{name} is not under softcrawl ({file})")
    assert not twice, "\n".join(twice)


#: Where project imports may sit inside functions without a reason each: the command modules,
#: which import their work inside `register`/`run` so that `softcrawl --help` stays fast, and the
#: command line itself. Each command module that does says so once with `COMMAND_MARKER`.
COMMANDS = ROOT / "studies" / "commands"
CLI = ROOT / "studies" / "cli.py"
COMMAND_MARKER = "softcrawl --help stays fast"
#: The comment that keeps a project import inside a function elsewhere, on the import's lines or
#: the line above it: `# lazy: <why>`.
LAZY_REASON = re.compile(r"#\s*lazy:\s*\S")


def function_level_project_imports(source: str) -> list[tuple[int, str, bool]]:
    """(line, first line of the statement, does it carry a `# lazy: why` comment) of every import
    of a `softcrawl` module that is not at module level (inside a function, a class, an `if`)."""
    lines = source.splitlines()
    found = []
    for node, names, at_top in _import_nodes(ast.parse(source)):
        if at_top or not any(_layer_of_name(n) for n in names):
            continue
        above = lines[node.lineno - 2].strip() if node.lineno > 1 else ""
        said = any(LAZY_REASON.search(line) for line in lines[node.lineno - 1 : node.end_lineno])
        said = said or (above.startswith("#") and bool(LAZY_REASON.search(above)))
        found.append((node.lineno, lines[node.lineno - 1].strip(), said))
    return found


def _project_files():
    """Every project source file, the entry points included."""
    for layer, (folder, _) in LAYERS.items():
        yield from sorted(folder.glob("*.py") if layer == "softcrawl.core" else folder.rglob("*.py"))


def test_project_imports_are_at_module_top_or_say_why_not():
    """A module's header shows what it depends on: a project import inside a function (outside the
    command modules) is an exception that says why on its line or the line above (`# lazy: ...`)."""
    bad = [
        f"{path.relative_to(ROOT)}:{line}: {text}"
        for path in _project_files()
        if not path.is_relative_to(COMMANDS) and path != CLI
        for line, text, said in function_level_project_imports(path.read_text())
        if not said
    ]
    assert not bad, "move to the module's imports, or say why with `# lazy: ...`:\n" + "\n".join(bad)


def test_commands_that_import_inside_functions_say_why():
    bad = [
        str(path.relative_to(ROOT))
        for path in sorted(COMMANDS.glob("*.py"))
        if function_level_project_imports(path.read_text()) and COMMAND_MARKER not in path.read_text()
    ]
    assert not bad, f"say once why the work is imported inside functions ({COMMAND_MARKER!r}):\n" + (
        "\n".join(bad)
    )


@pytest.mark.parametrize(
    ("source", "expected"),
    [
        ("from softcrawl.fem import model\n", []),
        ("def f():\n    import numpy\n", []),
        ("def f():\n    from softcrawl.fem import model\n", [(2, False)]),
        ("def f():\n    import softcrawl.fem.model as m\n", [(2, False)]),
        ("class C:\n    def f(self):\n        from softcrawl import jsonio\n", [(3, False)]),
        ("def f():\n    from softcrawl import jsonio  # lazy: keeps f light\n", [(2, True)]),
        ("def f():\n    # lazy: keeps f light\n    from softcrawl import jsonio\n", [(3, True)]),
        ("def f():\n    from softcrawl.fem import (\n        model,  # lazy: light\n    )\n", [(2, True)]),
        ("def f():\n    from softcrawl import jsonio  # lazy:\n", [(2, False)]),
    ],
)
def test_the_import_scan_finds_function_level_project_imports(source, expected):
    assert [(line, said) for line, _, said in function_level_project_imports(source)] == expected


def _studies_unit(path: Path) -> str:
    """A subfolder of studies/ (a feature or shared infrastructure), or a top-level module of it."""
    parts = path.relative_to(ROOT / "studies").parts
    return parts[0] if len(parts) > 1 else parts[0].removesuffix(".py")


def test_no_cycle_between_studies_subfolders():
    """Features (epsa, foot, robot_fe, crawl, material) sit on the shared infrastructure (sweeps,
    plots, html, outcome) and under the review and the commands: imports flow one way."""
    graph: dict[str, set[str]] = {}
    for path in sorted((ROOT / "studies").rglob("*.py")):
        me = _studies_unit(path)
        for name, _ in _imports(path):
            parts = name.split(".")
            if parts[:2] == ["softcrawl", "studies"] and len(parts) > 2 and parts[2] != me:
                graph.setdefault(me, set()).add(parts[2])
    cycles = []
    for start in sorted(graph):
        stack = [(start, [start])]
        while stack:
            node, trail = stack.pop()
            for dep in sorted(graph.get(node, ())):
                if dep == start:
                    cycles.append(" -> ".join([*trail, dep]))
                elif dep not in trail:
                    stack.append((dep, [*trail, dep]))
    assert not cycles, "\n".join(sorted(set(cycles)))


#: The literal factors of a kPa <-> MPa conversion.
CONVERSION_FACTORS = (1e-3, 1e3)
#: Words (lower case, split at `_`, dots and spaces) that say a value is a pressure.
PRESSURE_WORDS = {"kpa", "mpa", "pressure", "pressures", "peak", "lim", "limit"}
#: Context names of other quantities that happen to be scaled by 1e3 (N/mm -> N/m, tonne -> kg,
#: s -> ms): a stiffness `k_...`, anything `..._per_m`, a mass `m`.
OTHER_QUANTITY = re.compile(r"^(k|m)$|^k_|_per_m$|_kg$|_ms$")
#: The one module allowed to convert.
UNITS_MODULE = ROOT / "softcrawl" / "units.py"
#: Folders scanned for bare pressure conversions.
SCANNED = ("fem", "geometry", "studies", "softcrawl", "bench")


def _words(text: str) -> set[str]:
    """Lower-case words of identifiers and literal text, plus `p`/`P` for names that start with
    it (`P`, `p_lim`, `P_fe`: the code's pressure names; `k_p` is a stiffness, not a pressure)."""
    out = set()
    for ident in re.findall(r"[A-Za-z][A-Za-z0-9_]*", text):
        parts = ident.lower().split("_")
        out.update(parts)
        if parts[0] == "p":
            out.add("<p>")
    return out


def _is_factor(node: ast.AST) -> bool:
    return (
        isinstance(node, ast.Constant)
        and type(node.value) in (int, float)
        and float(node.value) in CONVERSION_FACTORS
    )


def _context(node: ast.AST, parents: dict[int, ast.AST], source: str) -> list[str]:
    """The text of what `node` is assigned to, passed as, stored under or shown in, up to its
    statement: assignment targets, keyword names, dict keys, the literal text of an f-string, and
    the iterables of the comprehensions it is in (`p / 1e3 for p in P`)."""
    out = []
    child, parent = node, parents.get(id(node))
    while parent is not None and not isinstance(child, ast.stmt):
        if isinstance(parent, (ast.Assign, ast.AnnAssign, ast.AugAssign)) and child is parent.value:
            targets = parent.targets if isinstance(parent, ast.Assign) else [parent.target]
            out += [ast.get_source_segment(source, t) or "" for t in targets]
        elif isinstance(parent, ast.keyword) and parent.arg:
            out.append(parent.arg)
        elif isinstance(parent, ast.Dict) and child in parent.values:
            key = parent.keys[parent.values.index(child)]
            out.append("" if key is None else ast.get_source_segment(source, key) or "")
        elif isinstance(parent, ast.JoinedStr):
            out.append(" ".join(v.value for v in parent.values if isinstance(v, ast.Constant)))
        elif isinstance(parent, (ast.ListComp, ast.SetComp, ast.GeneratorExp, ast.DictComp)):
            out += [ast.get_source_segment(source, g.iter) or "" for g in parent.generators]
        child, parent = parent, parents.get(id(parent))
    return out


def bare_pressure_conversions(source: str) -> list[tuple[int, str]]:
    """(line, source) of every multiplication or division by 1e-3 or 1e3 (int or float, e.g.
    1000, 0.001) whose other operand, or whatever it is assigned to, stored under or shown in,
    names a pressure (`PRESSURE_WORDS`, or a name starting with `p`/`P`) and no other quantity."""
    tree = ast.parse(source)
    parents = {id(c): n for n in ast.walk(tree) for c in ast.iter_child_nodes(n)}
    found = []
    for node in ast.walk(tree):
        if not (isinstance(node, ast.BinOp) and isinstance(node.op, (ast.Mult, ast.Div))):
            continue
        if _is_factor(node.right):
            other = node.left
        elif _is_factor(node.left) and isinstance(node.op, ast.Mult):
            other = node.right
        else:
            continue
        around = _context(node, parents, source)
        names = {w.lower() for text in around for w in re.findall(r"[A-Za-z][A-Za-z0-9_]*", text)}
        if any(OTHER_QUANTITY.search(w) for w in names):
            continue
        words = _words(ast.get_source_segment(source, other) or "")
        for text in around:
            words |= _words(text)
        if words & (PRESSURE_WORDS | {"<p>"}):
            found.append((node.lineno, ast.get_source_segment(source, node)))
    return found


def test_pressures_are_converted_only_in_units():
    """kPa -> MPa and back go through `softcrawl.units` (`kpa_to_mpa`, `mpa_to_kpa`): a bare
    `* 1e-3`, `/ 1e3`, `* 1e3` on a pressure anywhere else is a second place that knows the rule."""
    bare = []
    for folder in SCANNED:
        for path in sorted((ROOT / folder).rglob("*.py")):
            if path == UNITS_MODULE:
                continue
            for line, text in bare_pressure_conversions(path.read_text()):
                bare.append(f"{path.relative_to(ROOT)}:{line}: {text}")
    assert not bare, "use softcrawl.units:\n" + "\n".join(bare)


@pytest.mark.parametrize(
    "line",
    [
        "P = L[:-1] * 1e3",
        "x = [(p * 1e-3, 0.0) for p in pressures_kpa]",
        "run([tuple(v / 1e3 for v in P) for P in targets])",
        "msg = f'limit at {peak * 1e3:.4g} kPa'",
        "d = {'fe_limit_kPa': fe_lim * 1000}",
        "target = TARGET_KPA * 0.001",
    ],
)
def test_the_pressure_conversion_scan_catches_a_bare_conversion(line):
    assert bare_pressure_conversions(line)


@pytest.mark.parametrize(
    "line",
    [
        "row = dict(k_p_n_per_m=float(a.k_p(p)) * 1e3)",
        "k_free = 3.0 * mu_mpa * math.pi / L * 1e3",
        "m = theoretical_load(f, mass * 1e-6, g) * 1e3",
        "value = min(max(value + rate[k] * 1e-3, 0.0), p)",
        "x = pressure_kpa / 2",
    ],
)
def test_the_pressure_conversion_scan_leaves_other_quantities(line):
    assert not bare_pressure_conversions(line)
