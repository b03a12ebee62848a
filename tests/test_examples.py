"""The scripts in examples/ run as tests (scikit-fem's habit): each in a subprocess in a temporary
folder, checked for its exit code and a printed figure; and each imports only `softcrawl`'s public
names (`sc.X` with X in `softcrawl.__all__`) besides numpy, optuna, matplotlib and a few standard
modules."""

import ast
import csv
import re
import subprocess
import sys
from pathlib import Path

import pytest

import softcrawl

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
ALLOWED = {"softcrawl", "numpy", "optuna", "matplotlib", "sys", "pathlib", "argparse"}


def _run(name: str, *args: str, cwd: Path) -> str:
    res = subprocess.run(
        [sys.executable, str(EXAMPLES / name), *args], cwd=cwd, capture_output=True, text=True
    )
    assert res.returncode == 0, res.stdout[-2000:] + res.stderr[-2000:]
    return res.stdout


def _public_uses(tree: ast.Module) -> tuple[list[str], list[str]]:
    """(imported modules that are not allowed, softcrawl names used that are not public)."""
    bad_modules, bad_names, aliases = [], [], set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for a in node.names:
                if a.name.split(".")[0] not in ALLOWED:
                    bad_modules.append(a.name)
                elif a.name.startswith("softcrawl"):
                    if a.name != "softcrawl":
                        bad_names.append(a.name)  # a submodule: not the public API
                    aliases.add(a.asname or a.name)
        elif isinstance(node, ast.ImportFrom):
            module = node.module or ""
            if node.level or module.split(".")[0] not in ALLOWED:
                bad_modules.append(module or ".")
            elif module.startswith("softcrawl"):
                public = softcrawl.__all__ if module == "softcrawl" else ()
                bad_names += [f"{module}.{a.name}" for a in node.names if a.name not in public]
    for node in ast.walk(tree):
        if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) and node.value.id in aliases:
            if node.attr not in softcrawl.__all__:
                bad_names.append(f"{node.value.id}.{node.attr}")
    return bad_modules, bad_names


def test_the_examples_are_there():
    assert {p.name for p in EXAMPLES.glob("*.py")} == {"actuator_ramp.py", "custom_sweep.py", "crawl.py"}


@pytest.mark.parametrize("name", ["actuator_ramp.py", "custom_sweep.py", "crawl.py"])
def test_examples_use_only_the_public_api(name):
    tree = ast.parse((EXAMPLES / name).read_text())
    doc = ast.get_docstring(tree)
    assert doc and f"python examples/{name}" in doc, "a module docstring that says how to run it"
    bad_modules, bad_names = _public_uses(tree)
    assert not bad_modules, f"imports beyond softcrawl, numpy, optuna, matplotlib: {bad_modules}"
    assert not bad_names, f"not in softcrawl.__all__: {bad_names}"


def test_the_import_check_catches_private_use():
    code = "import os\nimport softcrawl as sc\nfrom softcrawl.studies import cli\nsc.simulate_epsa\nsc._LAZY"
    bad_modules, bad_names = _public_uses(ast.parse(code))
    assert bad_modules == ["os"]
    assert bad_names == ["softcrawl.studies.cli", "sc._LAZY"]


def test_actuator_ramp(tmp_path):
    """~4 s: the Table 1 ePSA on the quick mesh, 0-40 kPa."""
    out = _run("actuator_ramp.py", cwd=tmp_path)
    rows = {float(m[1]): float(m[2]) for m in re.finditer(r"^\s+([\d.]+)\s+[\d.]+\s+([\d.-]+)\s+", out, re.M)}
    assert sorted(rows) == [0.0, 10.0, 20.0, 30.0, 40.0]
    assert rows[0.0] == 0.0 and 0.0 < rows[10.0] < rows[20.0] < rows[30.0] < rows[40.0]


def test_custom_sweep(tmp_path):
    """~10 s: six TPE trials of quick-mesh simulations; the trials' table and the best design."""
    out = _run("custom_sweep.py", str(tmp_path / "out"), cwd=tmp_path)
    assert re.search(r"^best: r0 = [\d.]+ mm, N = \d+: extension [\d.]+ mm", out, re.M)
    with open(tmp_path / "out" / "trials.csv", newline="") as fh:
        trials = list(csv.DictReader(fh))
    assert len(trials) == 6 and all(t["state"] == "COMPLETE" for t in trials)
    assert all(float(t["extension_mm"]) > 0 for t in trials)


@pytest.mark.slow
def test_crawl(tmp_path):
    """Measured 225 and 284 s (137-140 s CPU) on a loaded 2-core machine: the quick crawl, one
    inflate cycle in the 70 mm pipe with the identified feet (mu = 0.3, record 070); the stride of
    the quick crawl study's point at 70 mm, mu = 0.3 (results/crawl/rubber-70a-quick/summary.csv:
    15.9823 mm)."""
    out = _run("crawl.py", cwd=tmp_path)
    stride = re.search(r"^cycle 1: stride ([\d.+-]+) mm, speed ([\d.+-]+) mm/s", out, re.M)
    assert stride, out[-2000:]
    assert float(stride[1]) == pytest.approx(15.982, abs=2e-3)
