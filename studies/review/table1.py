"""Reproduce the paper's Table 1 from the study outputs with the rules of ``studies.epsa.rules``.

Reads RESULTS/chamber-radius/<material>/curves.csv and RESULTS/fiber-turns/<material>/curves.csv
(as written by ``softcrawl study``; a folder ``<material>-quick`` holds a --quick run and is used
only when the full run of that material is absent; --mesh-size runs, ``<material>-h<size>``, are
not used) and writes RESULTS/table1.md: for every material
one table with a row per Table 1 parameter (paper value, our value, rule, material, agreement and
why), the evidence of each rule, and a last section saying which selections depend on the material.

Nothing here knows the paper's answers except to compare with them: change the study data and the
selected values follow.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from softcrawl.fem.laws import NeoHookean
from softcrawl.materials import get_material
from softcrawl.paper import TABLE1
from softcrawl.studies import registry
from softcrawl.studies.declaration import resolve
from softcrawl.studies.epsa import rules
from softcrawl.studies.epsa.linearity import linearity_claim
from softcrawl.studies.review.table1_summary import (
    closing,
    markdown_cell,
    paper_note,
    robot_evidence,
    summary_table,
)
from softcrawl.studies.sweeps.tables import read_csv
from softcrawl.studies.table1_row import StudyRow

#: The paper's Table 1: parameter key -> (label, value, unit) (`softcrawl.paper`).
PAPER_TABLE1 = TABLE1
#: The ePSA rows decided per silicone from the studies' curves.csv: Table 1 parameter -> the
#: results folder of the study that declares it (`rule`, with no `table1` of its own).
STUDY_DIRS = {p: s.folder for s in registry.studies() if s.table1 is None for p in s.rule}
QUICK_SUFFIX = "-quick"


@dataclass(frozen=True)
class MaterialRun:
    """The study data of one material: which CSV each rule read."""

    material: str
    sources: dict[str, Path | None]  #: parameter -> curves.csv used (None: no data)

    def quick(self, parameter: str) -> bool:
        src = self.sources.get(parameter)
        return src is not None and src.parent.name.endswith(QUICK_SUFFIX)


def find_materials(results: str | Path) -> list[str]:
    """Materials that have at least one ePSA study under ``results``."""
    names = set()
    for sub in STUDY_DIRS.values():
        for curves in sorted(Path(results).glob(f"{sub}/*/curves.csv")):
            name = curves.parent.name
            if re.search(r"-h[0-9.]+$", name):  # a --mesh-size run: not used by table1
                continue
            names.add(name[: -len(QUICK_SUFFIX)] if name.endswith(QUICK_SUFFIX) else name)
    return sorted(names)


def material_run(results: str | Path, material: str) -> MaterialRun:
    sources = {}
    for param, sub in STUDY_DIRS.items():
        full = Path(results) / sub / material / "curves.csv"
        quick = Path(results) / sub / (material + QUICK_SUFFIX) / "curves.csv"
        sources[param] = full if full.exists() else quick if quick.exists() else None
    return MaterialRun(material, sources)


def select_all(run: MaterialRun, robot_rows: dict | None = None) -> dict[str, rules.Selection]:
    """Apply every rule of one material's study data; the robot-level and foot rows come from
    `study_rows` (the same for every silicone; read once by `render`)."""
    out = {
        "length": rules.input_parameter(
            "length", PAPER_TABLE1["length"][1], "paper Section V-A: l0 = 100 mm in the FE model"
        ),
        "outer_radius": rules.input_parameter(
            "outer_radius", PAPER_TABLE1["outer_radius"][1], "paper Section V-A: R = 9 mm in the FE model"
        ),
    }
    selectors = {"chamber_radius": rules.select_chamber_radius, "fiber_turns": rules.select_fiber_turns}
    for param, select in selectors.items():
        src = run.sources.get(param)
        if src is None:
            out[param] = rules.Selection(
                param,
                None,
                _rule_text(param),
                (),
                "undetermined",
                f"no {STUDY_DIRS[param]} study for this material "
                f"(run `softcrawl study {STUDY_DIRS[param]} --material "
                f"{run.material}`)",
            )
        elif param == "chamber_radius":
            out[param] = select(read_csv(src), mu=_mu(run.material))
        else:
            rows = read_csv(src)
            out[param] = select(rows)
            out["linearity"] = linearity_claim(rows)
    out |= {param: row.selection for param, row in (robot_rows or {}).items()}
    return out


def study_rows(results: str | Path) -> dict[str, StudyRow]:
    """The Table 1 rows of every study that declares its own (`Study.table1`), in Table 1 order."""
    rows: dict[str, StudyRow] = {}
    for study in registry.studies():
        if study.table1 is not None:
            rows |= resolve(study.table1)(results)
    return {p: rows[p] for p in PAPER_TABLE1 if p in rows} | rows


def _rule_text(param: str) -> str:
    return {"chamber_radius": rules.CHAMBER_RADIUS_RULE, "fiber_turns": rules.FIBER_TURNS_RULE}[param]


def agreement(param: str, sel: rules.Selection) -> tuple[str, str]:
    """(agree | disagree | undetermined | pending | input, why)."""
    paper = PAPER_TABLE1[param][1]
    if sel.status == "pending":
        return "pending", sel.reason
    if sel.status == "input":
        return "agree (input)", sel.reason
    if sel.value is None:
        return "undetermined", sel.reason
    if abs(sel.value - paper) < 1e-9:
        return "agree", sel.reason
    return (
        "disagree",
        f"{sel.reason}; the paper's {paper:g} is excluded or not preferred by "
        f"the rule: {_why_not(sel, paper)}{paper_note(param, sel)}",
    )


def _why_not(sel: rules.Selection, paper: float) -> str:
    keys = {"chamber_radius": "r", "fiber_turns": "N", "groove_height": "h", "rings": "n_rings"}
    key = (keys | {"foot_radius": "d"}).get(sel.parameter, sel.parameter)
    found = [line for line in sel.evidence if line.startswith(f"{key} = {paper:g}:")]
    return "; ".join(found) if found else f"no result for {key} = {paper:g}"


def _mu(material: str) -> float | None:
    """mu of a Neo-Hookean material (its limit pressures scale with mu at fixed K/mu), else None:
    for Yeoh and Gent the scaling with the initial modulus alone does not hold."""
    try:
        m = get_material(material)
        return float(m.mu) if isinstance(m.law, NeoHookean) else None
    except Exception:  # noqa: BLE001 - a material unknown to materials
        return None


def _material_label(material: str) -> str:
    """The material's name and its law with constants (every row names its material law)."""
    try:
        return f"{material} ({get_material(material).law_label})"
    except Exception:  # noqa: BLE001 - unknown (e.g. a calibrated material file)
        return material


def render(results: str | Path, materials: Sequence[str]) -> str:
    """The Markdown of table1.md."""
    lines = [
        "# Table 1 reproduction",
        "",
        "Generated by `softcrawl table1` from the study outputs under "
        f"`{results}` with the rules of `studies/epsa/rules.py` (thresholds: target pressure "
        f"{rules.TARGET_PRESSURE_KPA:g} kPa, fluctuation tolerance "
        f"{rules.FLUCTUATION_REL_TOL:.0%} / {rules.FLUCTUATION_SIGN_CHANGES} trend changes, "
        f"similar extension {rules.SIMILAR_EXTENSION_REL:.0%}). The paper's values are those of its Table 1. "
        "Studies on the default mesh (h = 5 mm) unless marked (quick mesh).",
        "",
    ]
    if not materials:
        lines += [
            "No study results found: run `softcrawl study chamber-radius` and "
            "`softcrawl study fiber-turns` first (see README).",
            "",
        ]
    robot_rows = study_rows(results)
    selections = {}
    for material in materials:
        run = material_run(results, material)
        sel = select_all(run, robot_rows)
        selections[material] = sel
        label = _material_label(material)
        lines += [
            f"## Material {label}",
            "",
            "| parameter | paper | ours | rule | material | agreement | reason |",
            "|---|---|---|---|---|---|---|",
        ]
        for param, (name, paper, unit) in PAPER_TABLE1.items():
            s = sel[param]
            ours = "-" if s.value is None else f"{s.value:g} {unit}".strip()
            verdict, why = agreement(param, s)
            mat = label if param in STUDY_DIRS else robot_rows[param].material if param in robot_rows else "-"
            if (param in STUDY_DIRS and run.quick(param)) or (
                param in robot_rows and robot_rows[param].quick
            ):
                mat += " (quick mesh)"
            lines.append(
                f"| {name} | {paper:g} {unit} | {ours} | {markdown_cell(s.rule)} | "
                f"{markdown_cell(mat)} | {verdict} | {markdown_cell(why)} |"
            )
        lines += [""]
        for param in STUDY_DIRS:
            src = run.sources.get(param)
            lines += [f"Evidence, {PAPER_TABLE1[param][0]} (`{src if src is not None else 'no data'}`):", ""]
            lines += [f"- {e}" for e in sel[param].evidence] or ["- (none)"]
            lines += [""]
    if materials:
        quick = {m for m in materials if any(material_run(results, m).quick(p) for p in STUDY_DIRS)}
        lines[4:4] = summary_table(results, materials, selections, quick)
        lines += robot_evidence(robot_rows, PAPER_TABLE1)
        lines += closing(results, materials, selections)
    if len(materials) > 1:
        lines += ["## Dependence on the material", ""]
        for param in STUDY_DIRS:
            values = {m: selections[m][param].value for m in materials}
            shown = ", ".join(f"{m}: {'-' if v is None else f'{v:g}'}" for m, v in values.items())
            known = {v for v in values.values() if v is not None}
            if len(known) > 1:
                verdict = "**depends on the material**"
            elif len(known) == 1 and None not in values.values():
                verdict = "the same for every material studied"
            else:
                verdict = "cannot tell (undetermined for some material)"
            lines.append(f"- {PAPER_TABLE1[param][0]}: {shown} -> {verdict}")
        lines.append("")
    elif len(materials) == 1:
        lines += [
            "Only one material was studied, so the dependence of the selection on the "
            "material is not known; run the studies with another `--material` and "
            "regenerate.",
            "",
        ]
    return "\n".join(lines)


def write_table1(
    results: str | Path, out: str | Path | None = None, materials: Sequence[str] | None = None
) -> Path:
    """Write ``table1.md`` into ``out`` (default: the results folder)."""
    materials = list(materials) if materials else find_materials(results)
    path = Path(out if out is not None else results) / "table1.md"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(render(results, materials))
    return path
