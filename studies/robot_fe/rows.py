"""The Table 1 rows that the robot-level studies decide (`studies.table1_row`), read from their
committed decision.json, never recomputed:

    foot radius d      RESULTS/robot-foot-radius/<material>/decision.json (`rules.foot_radius_rule`)
    connecting rings   RESULTS/robot-rings/<material>/decision.json (`rules.ring_rule`)
"""

from __future__ import annotations

from pathlib import Path

from softcrawl.studies.epsa import rules
from softcrawl.studies.robot_fe.rules import decision_from_json
from softcrawl.studies.table1_row import StudyRow, material_of, pick_run
from softcrawl.studies.table1_row import fmt_value as _fmt

RING_RULE = (
    "fewest rings that combine the three ePSAs into one arc (splay, arc-fit RMS) without losing "
    "bending or extension against the best combined count (studies/robot_fe/rules.py)"
)
FOOT_RADIUS_RULE = (
    "best bending at P = (100, 40, 60) kPa among the d whose central channel holds an 8 mm camera "
    "(studies/robot_fe/rules.py)"
)


def robot_study_row(results: str | Path, parameter: str) -> StudyRow:
    """The "rings" or "foot_radius" row from the robot study's decision.json."""
    study, rule = {"rings": ("rings", RING_RULE), "foot_radius": ("foot-radius", FOOT_RADIUS_RULE)}[parameter]
    source = pick_run(results, f"robot-{study}/*/decision.json")
    material, quick = material_of(source)
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


def rings_rows(results: str | Path) -> dict[str, StudyRow]:
    """The rings study's Table 1 row (its declaration's ``table1``)."""
    return {"rings": robot_study_row(results, "rings")}


def foot_radius_rows(results: str | Path) -> dict[str, StudyRow]:
    """The foot-radius study's Table 1 row (its declaration's ``table1``)."""
    return {"foot_radius": robot_study_row(results, "foot_radius")}
