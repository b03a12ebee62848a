r"""The Table 1 row "foot groove height h" from the groove study (paper Section V-B, Fig. 10(a)).

The paper's reasons, quoted:
  - "under the same pressure, the sliding friction of the groove is almost independent of the
    groove height";
  - "the stress and deformation increase with increase in the groove height";
  - "Considering the weight and service life of the flexible foot, we choose h = 1 mm";
  - (Section II-B) "If the height is too large, the foot cannot withstand the large strain. On the
    contrary, if the height is too small, the foot cannot change direction flexibly."

As a rule with named, stated inputs (`GrooveRuleInputs`):
  1. friction check: the plateau friction over mu N varies across the candidate heights by less
     than `friction_spread` (relative), for every friction coefficient of the study;
  2. growth check: the 99th-percentile von Mises stress and the deformation rise with h
     (reported as found, not assumed);
  3. choice: grooves are cut into the skirt, so a deeper groove is a lighter foot, while the
     strain that limits service life grows with h. The rule takes the largest candidate
     h >= `min_height` (the paper's "too small cannot change direction flexibly", for which the
     FE has no criterion: a stated input) whose 99th-percentile max principal strain after the
     drag stays at or below `strain_limit` for every friction coefficient. A candidate whose drag
     did not complete at some mu (its lands rolled over their leading corners, or the solve
     diverged) is not allowed: the foot "cannot withstand" that load. None qualifies: the
     smallest candidate >= min_height, flagged.

`strain_limit` is an assumption (the printed Shore 70A rubber has no fatigue data here); the
percentile, not the raw maximum, is used because the groove corners are singular. The inputs are
fixed before the study is read and are not tuned to the paper's h = 1 mm.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass, field
from pathlib import Path

from softcrawl.studies.epsa import rules
from softcrawl.studies.table1_row import StudyRow, fmt_value, material_of

PAPER_H = 1.0


@dataclass(frozen=True)
class GrooveRuleInputs:
    candidates: tuple[float, ...] = (0.5, 1.0, 1.5, 2.0)  # mm, the groove study's grid
    friction_spread: float = 0.05  # "almost independent": relative spread of plateau / (mu N)
    strain_limit: float = 0.10  # service life: p99 max principal strain after 5 mm of drag
    min_height: float = 0.5  # mm, "too small cannot change direction flexibly" (stated)


@dataclass(frozen=True)
class GrooveDecision:
    value: float | None  # chosen h (mm); None: no evidence
    status: str  # "decided", "fallback" or "pending"
    reason: str
    friction_independent: bool | None
    stress_rises: bool | None
    deformation_rises: bool | None
    evidence: list = field(default_factory=list)  # one dict per (h, mu)

    @property
    def agrees_with_paper(self) -> bool | None:
        return None if self.value is None else abs(self.value - PAPER_H) < 1e-9


def _num(row, key) -> float:
    try:
        return float(row.get(key, "nan"))
    except (TypeError, ValueError):
        return float("nan")


def _rising(values) -> bool:
    return all(b > a for a, b in zip(values[:-1], values[1:]))


def decide(rows, inputs: GrooveRuleInputs = GrooveRuleInputs()) -> GrooveDecision:
    """The decision from groove-study summary rows (dicts with groove_height, mu, trial_status,
    plateau_over_mu_n, von_mises_mpa_p99, max_principal_strain_p99, deformation_max_mm)."""
    ok = [
        r
        for r in rows
        if r.get("trial_status") == "completed" and _num(r, "groove_height") in inputs.candidates
    ]
    if not ok:
        return GrooveDecision(None, "pending", "no completed groove-study point", None, None, None)
    by_mu: dict[float, list] = {}
    for r in ok:
        by_mu.setdefault(_num(r, "mu"), []).append(r)
    evidence, indep, stress_up, deform_up = [], True, True, True
    for mu, group in sorted(by_mu.items()):
        group.sort(key=lambda r: _num(r, "groove_height"))
        ratios = [_num(r, "plateau_over_mu_n") for r in group]
        spread = (max(ratios) - min(ratios)) / max(abs(sum(ratios) / len(ratios)), 1e-30)
        indep &= spread <= inputs.friction_spread
        stress_up &= _rising([_num(r, "von_mises_mpa_p99") for r in group])
        deform_up &= _rising([_num(r, "deformation_max_mm") for r in group])
        for r in group:
            evidence.append(
                {
                    "h_mm": _num(r, "groove_height"),
                    "mu": mu,
                    "plateau_over_mu_n": _num(r, "plateau_over_mu_n"),
                    "von_mises_p99_mpa": _num(r, "von_mises_mpa_p99"),
                    "strain_p99": _num(r, "max_principal_strain_p99"),
                    "deformation_mm": _num(r, "deformation_max_mm"),
                }
            )
    mus = sorted(by_mu)
    allowed = []
    for h in sorted(inputs.candidates):
        if h < inputs.min_height:
            continue
        strains = [e["strain_p99"] for e in evidence if e["h_mm"] == h]
        if len(strains) == len(mus) and all(math.isfinite(s) and s <= inputs.strain_limit for s in strains):
            allowed.append(h)
    checks = (
        f"friction {'almost independent of' if indep else 'NOT independent of'} h (spread <= "
        f"{inputs.friction_spread:g}); stress {'rises' if stress_up else 'does NOT rise'} and deformation "
        f"{'rises' if deform_up else 'does NOT rise'} with h"
    )
    if allowed:
        h = max(allowed)
        reason = (
            f"largest h >= {inputs.min_height:g} mm (lightest foot) with p99 strain <= "
            f"{inputs.strain_limit:g} "
            f"at mu = {', '.join(f'{m:g}' for m in mus)}; {checks}"
        )
        return GrooveDecision(h, "decided", reason, indep, stress_up, deform_up, evidence)
    h = min(c for c in inputs.candidates if c >= inputs.min_height)
    reason = f"no candidate keeps p99 strain <= {inputs.strain_limit:g}: smallest allowed h; {checks}"
    return GrooveDecision(h, "fallback", reason, indep, stress_up, deform_up, evidence)


def groove_summary(results) -> Path | None:
    """RESULTS/groove/<material>/summary.csv (the full run; the -quick run only without it)."""
    found = sorted(Path(results).glob("groove/*/summary.csv"))
    full = [p for p in found if not p.parent.name.endswith("-quick")]
    return (full or found or [None])[0]


def decide_from_results(
    results, inputs: GrooveRuleInputs = GrooveRuleInputs()
) -> tuple[GrooveDecision, Path | None]:
    path = groove_summary(results)
    if path is None:
        return GrooveDecision(
            None, "pending", "no groove study under the results folder", None, None, None
        ), None
    with open(path, newline="") as handle:
        return decide(list(csv.DictReader(handle)), inputs), path


def markdown(decision: GrooveDecision, source: Path | None) -> list[str]:
    """Lines for results/table1.md: the decision and its evidence table."""
    lines = [
        f"Groove height h: {decision.value if decision.value is not None else 'pending'} mm "
        f"({decision.status}; paper {PAPER_H:g} mm). {decision.reason}.",
        f"Source: {source}" if source else "Source: none",
        "",
        "| h (mm) | mu | plateau / mu N | von Mises p99 (MPa) | strain p99 | deformation (mm) |",
        "|---|---|---|---|---|---|",
    ]
    for e in decision.evidence:
        lines.append(
            f"| {e['h_mm']:g} | {e['mu']:g} | {e['plateau_over_mu_n']:.4f} | {e['von_mises_p99_mpa']:.3f} | "
            f"{e['strain_p99']:.3f} | {e['deformation_mm']:.3f} |"
        )
    return lines


#: The rule in words, as Table 1 shows it.
GROOVE_RULE = (
    "largest h >= 0.5 mm whose p99 strain after the drag stays <= 10 % at every mu, with the friction "
    "checked to be almost independent of h (studies/foot/groove_rule.py)"
)


def table1_rows(results: str | Path) -> dict[str, StudyRow]:
    """The groove study's Table 1 row, groove height h, from RESULTS/groove/<material>/summary.csv
    (its declaration's ``table1``)."""
    decision, source = decide_from_results(results)
    lines = tuple(markdown(decision, source))
    material, quick = material_of(source)
    if decision.value is None:
        why = f"{decision.reason} (run `softcrawl study groove --out DIR`)"
        return {
            "groove_height": StudyRow(rules.pending("groove_height", why), material, source, quick, lines)
        }
    evidence = tuple(
        f"h = {e['h_mm']:g}: mu = {e['mu']:g}, plateau / mu N {fmt_value(e['plateau_over_mu_n'])}, "
        f"strain p99 {fmt_value(e['strain_p99'])}, von Mises p99 {fmt_value(e['von_mises_p99_mpa'])} MPa"
        for e in decision.evidence
    )
    reason = decision.reason if decision.status == "decided" else f"fallback: {decision.reason}"
    selection = rules.Selection(
        "groove_height", float(decision.value), GROOVE_RULE, evidence, "selected", reason
    )
    return {"groove_height": StudyRow(selection, material, source, quick, lines)}
