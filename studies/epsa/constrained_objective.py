"""The objective and constraints of the actuator optimiser (`studies.epsa.optimiser`).

`evaluate_constrained` is the optimiser's evaluator: the ePSA evaluator's curve and metrics, the
thread length as the value to minimise, and three constraints (<= 0 feasible) in the trial's
attributes, which the sweep engine hands to optuna (`SearchSpec.constrained`).
"""

from __future__ import annotations

import functools
import json
from collections.abc import Mapping
from typing import Any

from softcrawl.studies.epsa.evaluator import evaluate_epsa, response_at
from softcrawl.studies.epsa.rules import SIMILAR_EXTENSION_REL, TARGET_PRESSURE_KPA
from softcrawl.studies.sweeps.spec import Evaluation

#: The most-turned design of the N study (paper Fig. 9: N = 50), the extension reference.
REFERENCE_TURNS = 50
#: Bound on |dR| / R0 at the target pressure: 5 % of the outer radius (0.45 mm for R0 = 9 mm).
#: The paper states no number ("relatively small radial expansion"); a 5 % bulge is what a
#: crawler in a pipe a few mm wider than the robot can afford. Stated, not tuned.
MAX_RADIUS_CHANGE_REL = 0.05


def evaluate_constrained(params: Mapping[str, Any], fixed: Mapping[str, Any], settings: Mapping[str, Any]):
    """Thread length (mm) and the constraints of `studies.epsa.optimiser`'s
    docstring. A diverged solve stays a failed trial (numerical, not physical)."""
    result = evaluate_epsa(params, fixed, dict(settings) | {"objectives": "sweep"})
    attrs = dict(result.attrs)
    metrics = attrs.get("metrics", {})
    if not result.ok and not metrics.get("converged", False):
        return result
    rows = attrs["rows"]
    thread = float(metrics["fiber_length_mm"])
    length0, radius0 = next(
        ((r["length_mm"], r["outer_radius_mm"]) for r in rows if r.get("status") == "reference"),
        (attrs["design"]["length"], attrs["design"]["outer_radius"]),
    )
    target = max(float(p) for p in settings.get("pressures_kpa", (TARGET_PRESSURE_KPA,)))
    at = response_at(rows, target)
    limit = metrics.get("limit_pressure_kpa")
    if at is None or (limit is not None and limit < target):
        reached = max([r["pressure_kpa"] for r in rows if r.get("status") == "converged"], default=0.0)
        attrs["constraints"] = [max((target - reached) / target, 1e-3), 1.0, 1.0]
        return Evaluation(ok=True, values=(thread,), attrs=attrs)
    ext, dr = at["length_mm"] - length0, abs(at["outer_radius_mm"] - radius0)
    ref = reference_extension(float(params["chamber_radius"]), json.dumps(dict(settings), sort_keys=True))
    c_ext = 1.0 if ref is None else abs(ext - ref) / abs(ref) - SIMILAR_EXTENSION_REL
    attrs["constraints"] = [0.0, dr / radius0 - MAX_RADIUS_CHANGE_REL, c_ext]
    metrics["reference_extension_mm"] = ref
    return Evaluation(ok=True, values=(thread,), attrs=attrs)


@functools.lru_cache(maxsize=16)
def reference_extension(
    chamber_radius: float, settings_json: str, turns: int = REFERENCE_TURNS
) -> float | None:
    """Extension at the target of the REFERENCE_TURNS design of this radius (None if it does
    not withstand the target), with the trial's own simulator and settings (cached per process)."""
    settings = json.loads(settings_json) | {"objectives": "pareto"}
    params = {"chamber_radius": chamber_radius, "fiber_turns": turns}
    result = evaluate_epsa(params, {}, settings)
    return float(result.values[0]) if result.ok else None
