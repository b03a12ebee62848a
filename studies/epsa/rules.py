"""The paper's Table 1 selection reasons (Section V-A; docs/decisions/005-table1-rules.md) as explicit rules.

Pure functions over study tables: the rows of ``curves.csv`` written by ``softcrawl study``
(one row per design and pressure; values may be strings as read from CSV). Each rule returns a
:class:`Selection` that carries the chosen value, the rule in words, the evidence per design and,
when the data cannot decide, ``value = None`` with the reason ("undetermined").

Every threshold is a named constant below, quoted with the sentence of the paper it encodes. None
was tuned to give the paper's answer: each is a round value fixed before looking at which value it
selects, and the evidence of every selection prints the numbers it compared, so a reader can see
how far each design is from every threshold (`fiber_turns_sensitivity` says which N other
tolerances would pick).

Definitions:

* **withstands** the target pressure: the evaluation completed (not diverged), its curve has a
  computed equilibrium at ``TARGET_PRESSURE_KPA``, and no limit (burst) pressure was found below
  it. A diverged evaluation does not withstand either; the evidence says it diverged, since a
  numerical failure is not proof of a physical burst.
* **fluctuating** length: the length-pressure curve, from the undeformed length at 0 kPa, either
  decreases somewhere (an increment below ``-FLUCTUATION_REL_TOL`` times the largest increment),
  or its slope alternates: the second differences of length change sign at least
  ``FLUCTUATION_SIGN_CHANGES`` times, ignoring second differences smaller than
  ``FLUCTUATION_REL_TOL`` times the largest increment. A softening curve (slope keeps rising),
  a stiffening one (slope keeps falling) or one S-bend are not fluctuating; "extension and
  expansion alternately appear as the main deformation" (paper) is.
* **differ little**: a design's extension at the target pressure is within
  ``SIMILAR_EXTENSION_REL`` of the most-turned design's.
* **closer to linear**: a claim of the paper that is checked, not a selection criterion
  (`studies.epsa.linearity`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

from softcrawl.studies.epsa.response import same_pressure

#: "it cannot withstand a pressure of more than 80 kPa" / "when the input air pressure changes
#: from 0 to 100kPa" (Section V-A, Fig. 8): the studies' highest pressure, which a design must
#: withstand (kPa).
TARGET_PRESSURE_KPA = 100.0
#: "The ePSA length with an air chamber radius of r = 4 mm or r = 2 mm fluctuates. This is
#: because the extension and expansion alternately appear as the main deformation" (Section V-A):
#: increments and trend changes smaller than this fraction of the largest length increment are
#: noise (a 20-kPa step of a smooth curve changes its increment by more than 5 % only where the
#: curve really bends).
FLUCTUATION_REL_TOL = 0.05
#: Same sentence: "alternately" needs at least two changes of the slope's trend (one change is
#: a single S-bend, which a smooth limit-point approach also shows).
FLUCTUATION_SIGN_CHANGES = 2
#: "when the number is N = 50, N = 25, or N = 20, the reinforcing effect of ePSA length is not
#: much different. Taking the fabrication process and the weight of the ePSA prototype into
#: consideration, we choose N = 20" (Section V-A): "not much different" is read as an extension
#: within 10 % of the most-turned design's (a round engineering tolerance; the evidence lists every
#: design's difference and `fiber_turns_sensitivity` the choice at 5 % and 20 %).
SIMILAR_EXTENSION_REL = 0.10
#: Chamber radius studied with fibers (paper Section V-A: r = 3 mm).
FIBER_STUDY_CHAMBER_RADIUS = 3.0


@dataclass(frozen=True)
class DesignCurve:
    """One design of a sweep, parsed from the CSV rows.

    ``pressures/lengths/radii``: the pressure-controlled equilibria (row status "converged"), in
    increasing pressure; the rules use these. ``path``: every computed state in solution order,
    including volume-controlled states past a limit point (pressure falls there), for plots.
    ``length0/radius0``: the evaluator's 0 kPa "reference" row if present (the FE's own measure
    of the undeformed actuator), else the design's length and outer radius."""

    value: float
    trial_status: str  #: completed | failed | running | waiting | missing
    reason: str
    limit_pressure: float | None
    length0: float
    radius0: float
    pressures: list[float] = field(default_factory=list)
    lengths: list[float] = field(default_factory=list)
    radii: list[float] = field(default_factory=list)
    path: list[tuple[float, float, float, str]] = field(default_factory=list)

    def at(self, pressure: float) -> tuple[float, float] | None:
        for p, length, radius in zip(self.pressures, self.lengths, self.radii):
            if same_pressure(p, pressure):
                return length, radius
        return None

    @property
    def withstands(self) -> bool:
        return (
            self.trial_status == "completed"
            and self.at(TARGET_PRESSURE_KPA) is not None
            and (self.limit_pressure is None or self.limit_pressure >= TARGET_PRESSURE_KPA)
        )

    @property
    def reached(self) -> float:
        """Highest computed pressure (kPa), 0 if none."""
        return max([p for p, *_ in self.path], default=0.0)


@dataclass(frozen=True)
class Selection:
    """Outcome of a rule. ``value`` is None when the rule could not decide (see ``reason``)."""

    parameter: str
    value: float | None
    rule: str
    evidence: tuple[str, ...] = ()
    status: str = "selected"  #: selected | undetermined | input | pending
    reason: str = ""

    @property
    def determined(self) -> bool:
        return self.value is not None


def _f(value) -> float | None:
    if value is None or value == "":
        return None
    try:
        return float(value)
    except (TypeError, ValueError):
        return None


def design_curves(rows: Sequence[Mapping[str, Any]], param: str) -> dict[float, DesignCurve]:
    """Group curve rows by the value of ``param`` (row order = the solution path)."""
    grouped: dict[float, list[Mapping[str, Any]]] = {}
    for row in rows:
        value = _f(row.get(param))
        if value is None:
            raise ValueError(f"row without a numeric {param!r}: {dict(row)}")
        grouped.setdefault(value, []).append(row)
    out = {}
    for value, group in grouped.items():
        first = group[0]
        length0, radius0 = _f(first.get("length")) or 100.0, _f(first.get("outer_radius")) or 9.0
        path = []
        for r in group:
            p, length, radius = (_f(r.get(k)) for k in ("pressure_kpa", "length_mm", "outer_radius_mm"))
            status = r.get("row_status")
            if None in (p, length, radius):
                continue
            if status == "reference":
                length0, radius0 = length, radius
            elif status in ("converged", "volume-control"):
                path.append((p, length, radius, status))
        controlled = sorted((p, x, y) for p, x, y, st in path if st == "converged")
        out[value] = DesignCurve(
            value=value,
            trial_status=str(first.get("trial_status", "")),
            reason=str(first.get("reason", "") or ""),
            limit_pressure=_f(first.get("limit_pressure_kpa")),
            length0=length0,
            radius0=radius0,
            pressures=[p for p, _, _ in controlled],
            lengths=[x for _, x, _ in controlled],
            radii=[y for _, _, y in controlled],
            path=path,
        )
    return out


def fluctuation(curve: DesignCurve) -> tuple[bool, str]:
    """(fluctuating?, explanation) by the module's definition."""
    lengths = [curve.length0] + curve.lengths
    inc = [b - a for a, b in zip(lengths, lengths[1:])]
    if len(inc) < 2:
        return False, "too few points to judge"
    scale = max(abs(d) for d in inc) or 1.0
    tol = FLUCTUATION_REL_TOL * scale
    if any(d < -tol for d in inc):
        return True, "length decreases between two pressure steps"
    second = [b - a for a, b in zip(inc, inc[1:])]
    signs = [1 if s > tol else -1 for s in second if abs(s) > tol]
    changes = sum(1 for a, b in zip(signs, signs[1:]) if a != b)
    if changes >= FLUCTUATION_SIGN_CHANGES:
        return True, f"slope of length alternates ({changes} sign changes of its trend)"
    return False, f"monotone, {changes} change(s) of slope trend"


CHAMBER_RADIUS_RULE = (
    f"among chamber radii that withstand {TARGET_PRESSURE_KPA:g} kPa without fibers (no limit "
    "point, not diverged), drop those whose length-pressure curve fluctuates, then take the one "
    f"with the smallest radial expansion at {TARGET_PRESSURE_KPA:g} kPa"
)


def select_chamber_radius(rows: Sequence[Mapping[str, Any]], mu: float | None = None) -> Selection:
    """Paper: r = 5, 6 cannot withstand > 80 kPa; r = 2, 4 fluctuate; r = 3 has a small radial
    expansion -> 3 mm. Rows: the chamber-radius study (no fibers).

    ``mu`` (MPa), the shear modulus the study ran with, only adds evidence: without fibers the
    body is a nearly incompressible Neo-Hookean solid with a fixed K/mu, so its limit pressure
    is proportional to mu, and a radius with a limit point p_lim withstands the target pressure
    for mu >= mu * target / p_lim."""
    curves = design_curves(rows, "chamber_radius")
    evidence, candidates = [], []
    for r, c in sorted(curves.items()):
        if not c.withstands:
            if c.trial_status == "completed" and c.limit_pressure is not None:
                why = f"limit point at {c.limit_pressure:.3g} kPa"
                if mu is not None and c.limit_pressure > 0:
                    why += (
                        f" (would withstand {TARGET_PRESSURE_KPA:g} kPa for mu >= "
                        f"{mu * TARGET_PRESSURE_KPA / c.limit_pressure:.3g} MPa)"
                    )
            elif c.trial_status == "failed":
                why = f"diverged/failed after {c.reached:.3g} kPa ({c.reason})"
            elif c.trial_status != "completed":
                why = f"no result ({c.trial_status})"
            else:
                why = f"no computed state at {TARGET_PRESSURE_KPA:g} kPa"
            evidence.append(f"r = {r:g}: does not withstand: {why}")
            continue
        fluct, how = fluctuation(c)
        length, radius = c.at(TARGET_PRESSURE_KPA)
        ext, rad = length - c.length0, radius - c.radius0
        if fluct:
            evidence.append(f"r = {r:g}: withstands; fluctuating: {how}")
            continue
        evidence.append(
            f"r = {r:g}: withstands; not fluctuating ({how}); extension {ext:.3g} mm, "
            f"radial expansion {rad:.3g} mm"
        )
        candidates.append((rad, r))
    if not curves:
        return Selection(
            "chamber_radius", None, CHAMBER_RADIUS_RULE, (), "undetermined", "no chamber-radius study data"
        )
    if not candidates:
        n_ok = sum(c.withstands for c in curves.values())
        why = (
            f"no studied radius withstands {TARGET_PRESSURE_KPA:g} kPa"
            if n_ok == 0
            else f"the {n_ok} radii that withstand {TARGET_PRESSURE_KPA:g} kPa all fluctuate"
        )
        return Selection("chamber_radius", None, CHAMBER_RADIUS_RULE, tuple(evidence), "undetermined", why)
    rad, r = min(candidates)
    return Selection(
        "chamber_radius",
        r,
        CHAMBER_RADIUS_RULE,
        tuple(evidence),
        reason=f"r = {r:g} mm: smallest radial expansion ({rad:.3g} mm) of "
        f"{len(candidates)} admissible radii",
    )


FIBER_TURNS_RULE = (
    f"the fewest winding turns whose extension at {TARGET_PRESSURE_KPA:g} kPa is within "
    f'{SIMILAR_EXTENSION_REL:.0%} of the most-turned design\'s ("not much different"; fewest for '
    "fabrication and weight)"
)


def _fiber_extensions(curves) -> tuple[dict[float, tuple[float, float]], list[str]]:
    """{N: (extension, radial expansion) at the target} of the designs that withstand it."""
    evidence, ok = [], {}
    for n, c in sorted(curves.items()):
        if not c.withstands:
            why = (
                f"limit point at {c.limit_pressure:.3g} kPa"
                if c.limit_pressure is not None
                else f"{c.trial_status} after {c.reached:.3g} kPa: {c.reason}".strip()
            )
            evidence.append(f"N = {n:g}: does not reach {TARGET_PRESSURE_KPA:g} kPa ({why})")
            continue
        length, radius = c.at(TARGET_PRESSURE_KPA)
        ok[n] = (length - c.length0, radius - c.radius0)
    return ok, evidence


def fewest_similar_turns(extensions: Mapping[float, float], reference: float, tolerance: float):
    """The fewest N whose extension is within `tolerance` (fraction) of `reference`'s, or None."""
    ext_ref = extensions[reference]
    close = [n for n, e in extensions.items() if abs(e - ext_ref) <= tolerance * abs(ext_ref)]
    return min(close) if close else None


def select_fiber_turns(rows: Sequence[Mapping[str, Any]]) -> Selection:
    """Paper: N = 20, 25, 50 differ little -> the fewest such turns (fabrication and weight), 20.
    Rows: the fiber-turns study (r = 3 mm). Designs that do not withstand the target are out;
    the most-turned design is the reference and must withstand it."""
    curves = design_curves(rows, "fiber_turns")
    if not curves:
        return Selection(
            "fiber_turns", None, FIBER_TURNS_RULE, (), "undetermined", "no fiber-turns study data"
        )
    ok, evidence = _fiber_extensions(curves)
    n_ref = max(curves)
    if n_ref not in ok:
        return Selection(
            "fiber_turns",
            None,
            FIBER_TURNS_RULE,
            tuple(evidence),
            "undetermined",
            f"the most-turned design N = {n_ref:g} has no result at "
            f"{TARGET_PRESSURE_KPA:g} kPa to compare with",
        )
    ext_ref = ok[n_ref][0]
    for n, (ext, rad) in sorted(ok.items()):
        rel = (ext - ext_ref) / ext_ref if ext_ref else 0.0
        close = abs(ext - ext_ref) <= SIMILAR_EXTENSION_REL * abs(ext_ref)
        evidence.append(
            f"N = {n:g}: extension {ext:.3g} mm ({rel:+.1%} vs N = {n_ref:g}), radial expansion "
            f"{rad:.3g} mm -> {'differs little' if close else 'differs'}"
        )
    chosen = fewest_similar_turns({n: e for n, (e, _) in ok.items()}, n_ref, SIMILAR_EXTENSION_REL)
    return Selection(
        "fiber_turns",
        chosen,
        FIBER_TURNS_RULE,
        tuple(evidence),
        reason=f"N = {chosen:g}: fewest turns within {SIMILAR_EXTENSION_REL:.0%} of N = {n_ref:g}",
    )


def fiber_turns_sensitivity(rows, tolerances=(0.05, 0.10, 0.20)) -> dict[float, float | None]:
    """The N the rule would pick at other tolerances (shown in the table, never used to choose)."""
    curves = design_curves(rows, "fiber_turns")
    ok, _ = _fiber_extensions(curves)
    if not curves or max(curves) not in ok:
        return {t: None for t in tolerances}
    ext = {n: e for n, (e, _) in ok.items()}
    return {t: fewest_similar_turns(ext, max(curves), t) for t in tolerances}


def input_parameter(parameter: str, value: float, source: str) -> Selection:
    """A Table 1 value the paper's FE takes as a fixed input, not a study outcome."""
    return Selection(
        parameter,
        value,
        "input of the paper's FE model, not selected by a study",
        (source,),
        status="input",
        reason="fixed input (paper Section V-A); no study selects it",
    )


def pending(parameter: str, why: str) -> Selection:
    return Selection(parameter, None, "not implemented", (), status="pending", reason=why)
