"""The provenance section of the design review: every committed result with the command that
makes it, computed from the files (each run's spec.json, the command lines of results/**/README.md),
and the material, mesh and winding each command runs with. tests/studies/review/test_report.py
parses every command with the CLI's own parser, so that one that no longer parses fails."""

from __future__ import annotations

import json
import re
from pathlib import Path

from softcrawl import __version__
from softcrawl.studies import registry
from softcrawl.studies.html import esc, table
from softcrawl.studies.review.report_sections import CALIBRATE, VERIFY, _study_names, study_command

#: The commands that mesh something (the others have no mesh column).
MESHED = ("epsa", "study", "robot", "crawl", "calibrate", "mesh")
#: The commands whose --material is the actuator's body (default: the studies' Ecoflex 00-50).
ACTUATOR_COMMANDS = ("epsa", "calibrate")


def command_material(command: str) -> dict:
    """What a provenance command line runs with: the material (the command's default when it names
    none: a study's declared default, the actuator commands' Ecoflex 00-50 preset), the mesh and
    the winding. Read from the words, not by the CLI's parser (review may not import the CLI:
    tests/test_architecture.py); tests/studies/review/test_report.py parses every command."""
    import shlex

    words = shlex.split(command)
    verb = words[1] if len(words) > 1 else ""
    study = registry.get(words[2]) if verb == "study" and len(words) > 2 else None

    def option(name):
        for k, w in enumerate(words):
            if w == name and k + 1 < len(words):
                return words[k + 1]
            if w.startswith(name + "="):
                return w.split("=", 1)[1]
        return None

    material = option("--material")
    if material is None and study is not None:
        material = study.default_material
    if material is None and verb in ACTUATOR_COMMANDS:
        material = registry.get("fiber-turns").default_material
    takes_fibers = verb == "epsa" or (study is not None and "fibers" in study.options)
    return {
        "material": material or "-",
        "mesh": "quick" if "--quick" in words else ("default" if verb in MESHED else "-"),
        "winding": (option("--fibers") or "sheet") if takes_fibers else "-",
    }


def provenance_rows(results: Path) -> list[dict]:
    """Every committed result with the command that makes it, computed from the files: each run
    folder's spec.json, the command lines of every results/**/README.md, the calibration, Table 1."""
    rows = []
    names = _study_names()
    for spec_path in sorted(results.rglob("spec.json")):
        spec = json.loads(spec_path.read_text())
        settings = spec.get("settings", {})
        folder = spec_path.parent.relative_to(results).parts[0]
        name = names.get(folder, re.sub(r"-ecoflex.*|-dragon.*", "", spec.get("name", "")))
        quick = bool(settings.get("quick")) or settings.get("mesh") == "quick"
        command = study_command(name, settings.get("material"), quick, settings)
        rows.append({"result": str(spec_path.parent.relative_to(results)), "command": command})
    for readme in sorted(results.rglob("README.md")):
        for line in readme.read_text().splitlines():
            if line.strip().startswith("softcrawl "):
                command = line.split("  #")[0].split(" # ")[0].strip()
                rows.append({"result": str(readme.parent.relative_to(results)), "command": command})
    if (results / "calibration" / "calibration.json").exists():
        rows.append({"result": "calibration", "command": CALIBRATE})
    if (results / "verify" / "verify.json").exists():
        rows.append({"result": "verify", "command": VERIFY})
    if (results / "table1.md").exists():
        rows.append({"result": "table1.md", "command": "softcrawl table1 --out results/"})
    return [row | command_material(row["command"]) for row in rows]


def provenance(results: Path) -> str:
    return (
        f"<p>Every run written by softcrawl {esc(__version__)} and later records the softcrawl version "
        "and git commit in its <code>summary.json</code> (<code>provenance</code>); earlier results "
        "do not.</p>"
        + table(provenance_rows(results))
        + "<p>Redraw the study figures from their tables: <code>softcrawl replot results</code>.</p>"
    )
