"""What optuna's "best" means in the ePSA sweeps: one objective and trial constraints per study,
so that ``optuna.load_study(...).best_trial`` is the design the study's Table 1 rule
(`studies.epsa.rules`) picks, and a rejected design is never best (decision 063).

* chamber-radius: minimise the radial expansion at 100 kPa (mm), subject to ``withstands``
  (reaches 100 kPa with no limit point below it) and ``not_fluctuating`` (the rule's
  `fluctuation` test on the design's own curve). The rule: among radii that withstand 100 kPa and
  do not fluctuate, the smallest radial expansion; so the best feasible trial is its pick.
* fiber-turns: minimise the Kevlar thread (mm; at a fixed radius it grows with N), subject to
  ``withstands`` and ``similar_extension`` (|ext - ext(N_ref)| / |ext(N_ref)| <= 10 %, N_ref the
  most-turned design of the grid, 50). The rule: the fewest turns within 10 % of N_ref's extension.
  N_ref's extension is computed by the trial itself (cached per worker process), as the optimiser
  does (`studies.epsa.constrained_objective.reference_extension`).
* identify: decides no Table 1 value (it fits k_p and f_p over every point); its objective stays
  the extension at the highest pressure, maximised, named, and "best" decides nothing.

A design that fails (diverged) is a FAIL trial and never best; a design that does not reach 100
kPa is COMPLETE but infeasible, with the radial expansion at the highest state it reached.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from softcrawl.studies.epsa.constrained_objective import reference_extension
from softcrawl.studies.epsa.evaluator import evaluate_epsa, response_at
from softcrawl.studies.epsa.rules import (
    SIMILAR_EXTENSION_REL,
    TARGET_PRESSURE_KPA,
    design_curves,
    fluctuation,
)
from softcrawl.studies.sweeps.spec import Evaluation


@dataclass(frozen=True)
class SweepObjective:
    """The optuna objective of one ePSA sweep: its metric name, direction and constraints."""

    metric: str
    direction: str
    constraints: tuple[str, ...]
    why: str


OBJECTIVES = {
    "chamber-radius": SweepObjective(
        "radial_expansion_100kpa_mm",
        "minimize",
        ("withstands_100kpa", "not_fluctuating"),
        "the chamber-radius rule: smallest radial expansion among radii that withstand 100 kPa and do "
        "not fluctuate",
    ),
    "fiber-turns": SweepObjective(
        "fiber_length_mm",
        "minimize",
        ("withstands_100kpa", "similar_extension"),
        "the fiber-turns rule: fewest turns (least thread) whose extension is within 10 % of the "
        "most-turned design's",
    ),
    "identify": SweepObjective(
        "extension_mm", "maximize", (), "identify chooses no design: best decides nothing"
    ),
}


#: The evaluator of the chamber-radius and fiber-turns sweeps (registry name, studies/epsa/study.py).
RULE_EVALUATOR = "epsa-rule"


def objective_of(name: str) -> SweepObjective:
    return OBJECTIVES[name]


def evaluate_rule_sweep(params: Mapping[str, Any], fixed: Mapping[str, Any], settings: Mapping[str, Any]):
    """The ePSA evaluator (`studies.epsa.evaluator.evaluate_epsa`) with the objective and the
    constraints of ``settings["objective"]`` (the sweep's name) in place of the extension."""

    result = evaluate_epsa(params, fixed, settings)
    if not result.ok:
        return result
    name = settings["objective"]
    attrs = dict(result.attrs)
    value, constraints, extra = score(name, params, attrs, settings)
    attrs["metrics"] = dict(attrs["metrics"]) | extra
    if constraints:
        attrs |= {"constraints": constraints, "constraint_names": list(objective_of(name).constraints)}
    return Evaluation(ok=True, values=(value,), attrs=attrs)


def _withstands(rows, limit) -> tuple[float, bool]:
    """(constraint, ok): 0 when the design reaches the target pressure with no limit point below
    it, else the missing fraction of the target (>= 1e-3)."""

    if response_at(rows, TARGET_PRESSURE_KPA) is not None and (limit is None or limit >= TARGET_PRESSURE_KPA):
        return 0.0, True
    reached = max([r["pressure_kpa"] for r in rows if r.get("status") == "converged"], default=0.0)
    return max((TARGET_PRESSURE_KPA - reached) / TARGET_PRESSURE_KPA, 1e-3), False


def _curve(rows, limit, design):
    table = [
        {"value": 0.0, "length": design["length"], "outer_radius": design["outer_radius"],
         "trial_status": "completed", "limit_pressure_kpa": limit, "row_status": r.get("status")}
        | {k: r.get(k) for k in ("pressure_kpa", "length_mm", "outer_radius_mm")}
        for r in rows
    ]  # fmt: skip
    return design_curves(table, "value")[0.0]


def score(name: str, params: Mapping[str, Any], attrs: Mapping[str, Any], settings: Mapping[str, Any]):
    """(value, constraints, extra metrics) of an evaluated design of sweep ``name``."""

    objective = OBJECTIVES[name]
    metrics = attrs["metrics"]
    if not objective.constraints:
        return float(metrics[objective.metric]), [], {}
    rows, limit = attrs["rows"], metrics.get("limit_pressure_kpa")
    c_hold, ok = _withstands(rows, limit)
    curve = _curve(rows, limit, attrs["design"])
    extra: dict[str, Any] = {"withstands_100kpa": ok}
    if ok:
        length, radius = curve.at(TARGET_PRESSURE_KPA)
        extra["extension_100kpa_mm"] = length - curve.length0
        extra["radial_expansion_100kpa_mm"] = radius - curve.radius0
    if name == "chamber-radius":
        fluct, _ = fluctuation(curve) if curve.pressures else (False, "")
        value = extra.get("radial_expansion_100kpa_mm", metrics["radial_expansion_mm"])
        return float(value), [c_hold, 1.0 if fluct else 0.0], extra | {"fluctuating": fluct}
    n_ref = int(settings["reference_turns"])  # the most-turned design of the grid (sweep_spec)
    if not ok:
        ref = None
    elif int(params["fiber_turns"]) == n_ref:
        ref = extra["extension_100kpa_mm"]
    else:
        ref = reference(float(attrs["design"]["chamber_radius"]), n_ref, settings)
    c_ext = 1.0
    if ok and ref:
        c_ext = abs(extra["extension_100kpa_mm"] - ref) / abs(ref) - SIMILAR_EXTENSION_REL
    return float(metrics["fiber_length_mm"]), [c_hold, c_ext], extra | {"reference_extension_mm": ref}


def reference(chamber_radius: float, turns: int, settings: Mapping[str, Any]) -> float | None:
    """Extension at 100 kPa of the ``turns`` design of this radius (None if it does not reach it),
    with the trial's own simulator and settings, cached per process."""

    keep = {k: v for k, v in settings.items() if k not in ("vtu_dir", "objective", "reference_turns")}
    return reference_extension(chamber_radius, json.dumps(keep, sort_keys=True), turns)
