"""The Table 1 rows that the robot-level and foot studies decide: groove height h, foot radius d
and the number of connecting rings.

Each row is read from its study's committed outputs under the results folder, never recomputed:

    groove height h    RESULTS/groove/<material>/summary.csv -> `studies.foot.groove_rule.decide`
    foot radius d      RESULTS/robot-foot-radius/<material>/decision.json (`robot_rules.foot_radius_rule`)
    connecting rings   RESULTS/robot-rings/<material>/decision.json (`robot_rules.ring_rule`)

A full run is preferred over a `-quick` one of the same study. These rows do not depend on the
silicone of the ePSA tables: each names the material its own study used (the foot's Shore 70A
rubber for the groove, the calibrated silicone of the robot studies), so `table1` computes them
once and shows them in every material's table. A study that is missing gives a "pending" row that
says which command produces it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from softcrawl.studies.epsa import rules

QUICK_SUFFIX = "-quick"
GROOVE_RULE = (
    "largest h >= 0.5 mm whose p99 strain after the drag stays <= 10 % at every mu, with the friction "
    "checked to be almost independent of h (studies/foot/groove_rule.py)"
)
RING_RULE = (
    "fewest rings that combine the three ePSAs into one arc (splay, arc-fit RMS) without losing "
    "bending or extension against the best combined count (studies/robot_fe/rules.py)"
)
FOOT_RADIUS_RULE = (
    "best bending at P = (100, 40, 60) kPa among the d whose central channel holds an 8 mm camera "
    "(studies/robot_fe/rules.py)"
)


@dataclass(frozen=True)
class StudyRow:
    """One Table 1 row decided by a robot-level or foot study."""

    selection: rules.Selection
    material: str  #: the material the study ran with ("-" when there is no study)
    source: Path | None  #: the file the decision was read from
    quick: bool  #: the study ran on its quick mesh
    evidence_lines: tuple[str, ...] = ()  #: Markdown of the evidence, where the rule writes its own


def _pick(results: str | Path, pattern: str) -> Path | None:
    """The full run's file matching `pattern`, else the quick run's, else None."""
    found = sorted(Path(results).glob(pattern))
    full = [p for p in found if not p.parent.name.endswith(QUICK_SUFFIX)]
    return (full or found or [None])[0]


def _material_of(source: Path | None) -> tuple[str, bool]:
    if source is None:
        return "-", False
    name = source.parent.name
    quick = name.endswith(QUICK_SUFFIX)
    return (name[: -len(QUICK_SUFFIX)] if quick else name), quick


def _fmt(value) -> str:
    if isinstance(value, float):
        return "n/a" if not math.isfinite(value) else f"{value:.4g}"
    return "n/a" if value is None else str(value)


def groove_row(results: str | Path) -> StudyRow:
    from softcrawl.studies.foot.groove_rule import decide_from_results, markdown

    decision, source = decide_from_results(results)
    lines = tuple(markdown(decision, source))
    material, quick = _material_of(source)
    if decision.value is None:
        why = f"{decision.reason} (run `softcrawl study groove --out DIR`)"
        return StudyRow(rules.pending("groove_height", why), material, source, quick, lines)
    evidence = tuple(
        f"h = {e['h_mm']:g}: mu = {e['mu']:g}, plateau / mu N {_fmt(e['plateau_over_mu_n'])}, "
        f"strain p99 {_fmt(e['strain_p99'])}, von Mises p99 {_fmt(e['von_mises_p99_mpa'])} MPa"
        for e in decision.evidence
    )
    reason = decision.reason if decision.status == "decided" else f"fallback: {decision.reason}"
    selection = rules.Selection(
        "groove_height", float(decision.value), GROOVE_RULE, evidence, "selected", reason
    )
    return StudyRow(selection, material, source, quick, lines)


def robot_study_row(results: str | Path, parameter: str) -> StudyRow:
    """The "rings" or "foot_radius" row from the robot study's decision.json."""
    from softcrawl.studies.robot_fe.rules import decision_from_json

    study, rule = {"rings": ("rings", RING_RULE), "foot_radius": ("foot-radius", FOOT_RADIUS_RULE)}[parameter]
    source = _pick(results, f"robot-{study}/*/decision.json")
    material, quick = _material_of(source)
    if source is None:
        why = (
            f"no robot-{study} study under the results folder (run `softcrawl study {study} --out {results}`)"
        )
        return StudyRow(rules.pending(parameter, why), material, None, False)
    decision = decision_from_json(source)
    key = {"rings": "n_rings", "foot_radius": "d"}[parameter]
    evidence = tuple(
        f"{key} = {_fmt(e.get(key))}: " + ", ".join(f"{k} {_fmt(v)}" for k, v in e.items() if k != key)
        for e in decision.evidence
    )
    if decision.value is None:
        selection = rules.Selection(parameter, None, rule, evidence, "undetermined", decision.reason)
    else:
        selection = rules.Selection(
            parameter, float(decision.value), rule, evidence, "selected", decision.reason
        )
    return StudyRow(selection, material, source, quick)


def study_rows(results: str | Path) -> dict[str, StudyRow]:
    """Every Table 1 row decided by a robot-level or foot study, keyed by Table 1 parameter."""
    return {
        "groove_height": groove_row(results),
        "foot_radius": robot_study_row(results, "foot_radius"),
        "rings": robot_study_row(results, "rings"),
    }
