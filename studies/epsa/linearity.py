"""The paper's linearity claim, checked against the unreinforced actuator (Section V-A, Fig. 9(b)).

"winding of the fiber wires brings the relationship between the ePSA length and the input air
pressure closer to a linear relationship": the nonlinearity of a length-pressure curve is the RMS
distance of its points (0 kPa included) from their least-squares line, divided by the extension
at the highest compared pressure; a fibered design is closer to linear than the unreinforced one
(N = 0) when its nonlinearity is below N = 0's over the pressures both computed (at least
``LINEARITY_MIN_POINTS`` pressure levels, 0 kPa included). A checked claim, not a selection
criterion: no absolute threshold (an R^2 >= 0.99 would not be the paper's).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from softcrawl.studies.epsa.rules import DesignCurve, Selection, design_curves

#: "closer to a linear relationship" is compared with the unreinforced actuator over at least
#: this many pressure levels (0 kPa included): fewer points are always on a line.
LINEARITY_MIN_POINTS = 3


def nonlinearity(curve: DesignCurve, up_to_kpa: float | None = None) -> float | None:
    """RMS distance of (0, L0) and the computed (p, L) points with p <= `up_to_kpa` from their
    least-squares line, over the extension at the highest of those pressures (module docstring);
    None with fewer than ``LINEARITY_MIN_POINTS`` points or no extension."""
    pts = [(0.0, curve.length0)] + [
        (p, x) for p, x in zip(curve.pressures, curve.lengths) if up_to_kpa is None or p <= up_to_kpa + 1e-9
    ]
    if len(pts) < LINEARITY_MIN_POINTS:
        return None
    n = len(pts)
    mx, my = sum(p for p, _ in pts) / n, sum(x for _, x in pts) / n
    sxx = sum((p - mx) ** 2 for p, _ in pts)
    slope = sum((p - mx) * (x - my) for p, x in pts) / sxx
    rms = (sum((x - my - slope * (p - mx)) ** 2 for p, x in pts) / n) ** 0.5
    extension = abs(pts[-1][1] - curve.length0)
    return rms / extension if extension > 0 else None


def linearity_claim(rows: Sequence[Mapping[str, Any]]) -> Selection:
    """Paper: fibers bring length-pressure "closer to a linear relationship" than without. For
    every fibered design, its nonlinearity against N = 0's over the pressures both computed.
    ``value`` is the fraction of fibered designs closer to linear (1.0: the claim holds)."""
    rule = (
        "each fibered design's nonlinearity below the unreinforced (N = 0) one's over their common pressures"
    )
    curves = design_curves(rows, "fiber_turns")
    bare = curves.get(0.0)
    if bare is None or not bare.pressures:
        return Selection("linearity", None, rule, (), "undetermined", "no unreinforced (N = 0) curve")
    evidence, closer = [], []
    for n, c in sorted(curves.items()):
        if n == 0.0 or not c.pressures:
            continue
        common = min(max(c.pressures), max(bare.pressures))
        mine, ref = nonlinearity(c, common), nonlinearity(bare, common)
        if mine is None or ref is None:
            evidence.append(
                f"N = {n:g}: fewer than {LINEARITY_MIN_POINTS} common points up to {common:g} kPa"
            )
            continue
        closer.append(mine < ref)
        evidence.append(
            f"N = {n:g}: nonlinearity {mine:.3g} vs N = 0 {ref:.3g} up to {common:g} kPa -> "
            f"{'closer to linear' if mine < ref else 'not closer to linear'}"
        )
    if not closer:
        return Selection("linearity", None, rule, tuple(evidence), "undetermined", "no comparable curves")
    share = sum(closer) / len(closer)
    verdict = "holds" if share == 1.0 else "does not hold for every design"
    return Selection("linearity", share, rule, tuple(evidence), reason=f"the paper's claim {verdict}")
