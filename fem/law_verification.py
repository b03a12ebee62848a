"""Verification of the strain-stiffening laws (Yeoh, Gent) against the thick-tube theory for any
W(I1) (`fem.tube_theory`, docs/decisions/010-verification.md); `fem.verification.CASES` lists them.

- yeoh-tube, gent-tube: the 1/4 plane-strain tube A = 3, B = 9 mm, pressure-controlled to the
  analytic pressures of inner stretches 1.5 and 2.5 (Gent: 1.5 and 2.2, its Jm = 10 locks near 3);
  inner and outer radii against eq. (1) of `fem.tube_theory`, relative to the radial displacement.
  The constants make the stiffening large there (Psi' at the inner wall grows 3-6x), so a wrong
  Psi'' or Psi' fails the case.
- yeoh-closed-tube, gent-closed-tube: the same slice with closed ends. The analytic closed-end
  state (la, lz(la)) is imposed by the top face's axial displacement and the chamber volume
  (volume control: the pressure is an unknown), for inner stretches through the limit point. The
  FE pressure against eq. (1), the FE axial force of the wall against the cap load P pi a^2 / 4
  (the closed-end condition, eq. (2)), and the limit pressure (parabola through the three FE
  states around the largest pressure) against the analytic maximum. The laws: the full-range
  Yeoh fit of the shipped Ecoflex 00-50 data (limit at la = 2.64) and Gent with Jm = 30 (limit at
  la = 2.93; Jm = 15 has none).
"""

from __future__ import annotations

import numpy as np

from softcrawl.fem import tube_theory as tt
from softcrawl.fem.case_result import CaseResult
from softcrawl.fem.laws import Gent, Yeoh
from softcrawl.fem.path import load_path, volume_path
from softcrawl.fem.reference_models import mean_radius, tube_model
from softcrawl.units import mpa_to_kpa

INNER, OUTER = 3.0, 9.0
#: Strongly stiffening laws for the plane-strain cases (K/mu = 1000).
YEOH_STIFF = Yeoh.nearly_incompressible(0.015, 0.002, 5e-5)
GENT_STIFF = Gent.nearly_incompressible(0.03, 10.0)
#: Laws with a closed-end limit point: the Ecoflex 00-50 full-range Yeoh fit and Gent Jm = 30.
YEOH_FIT = Yeoh.nearly_incompressible(0.01259, 9.149e-5, 0.0)
GENT_LIMIT = Gent.nearly_incompressible(0.03, 30.0)


def plane_strain_tube_test(name, law, stretches, n_radial=6, n_angle=8, tolerance=0.01) -> CaseResult:
    model = tube_model(INNER, OUTER, n_radial, n_angle, law=law)
    pressures = [tt.pressure(law, la, INNER, OUTER) for la in stretches]
    res = load_path(model, [(P, 0.0) for P in pressures])
    details = {"law": repr(law), "dofs": model.n_dofs, "message": res.message}
    if not res.converged or len(res.steps) != len(pressures):
        return CaseResult(name, np.inf, tolerance, details)
    worst = 0.0
    for step, la in zip(res.steps, stretches):
        a = la * INNER
        b = np.sqrt(a * a + OUTER**2 - INNER**2)
        fe_a, fe_b = mean_radius(model, step.x, "inner"), mean_radius(model, step.x, "outer")
        ea, eb = abs(fe_a - a) / (a - INNER), abs(fe_b - b) / (b - OUTER)
        details[f"la={la}"] = {"P_kPa": mpa_to_kpa(step.pressure), "inner_err": ea, "outer_err": eb}
        worst = max(worst, ea, eb)
    return CaseResult(name, worst, tolerance, details)


def closed_tube_test(name, law, stretches, n_radial=6, n_angle=8, tolerance=0.01) -> CaseResult:
    """See the module docstring; `stretches` must bracket the analytic limit point."""
    states = [(la, *tt.closed_end_pressure(law, la, INNER, OUTER)) for la in stretches]
    la_lim, p_lim = tt.closed_end_limit(law, INNER, OUTER)
    lz_max = max(lz for *_, lz in states)
    model = tube_model(INNER, OUTER, n_radial, n_angle, law=law, top_stretch=lz_max)
    V0 = model.chamber_volume(model.initial_state())
    details = {"law": repr(law), "dofs": model.n_dofs, "analytic_limit": (la_lim, mpa_to_kpa(p_lim))}
    worst, fe = 0.0, []
    for la, P, lz in states:
        factor = (lz - 1.0) / (lz_max - 1.0)
        res = volume_path(model, V0 * lz * np.linspace(1.0, la * la, 5)[1:], factor=factor)
        if not res.converged:
            details[f"la={la}"] = res.message
            return CaseResult(name, np.inf, tolerance, details)
        x, P_fe = res.steps[-1].x, res.steps[-1].pressure
        a = mean_radius(model, x, "inner")
        cap = P_fe * np.pi * a * a / 4.0
        axial = model.reaction(x, "top", P_fe, factor)[2]
        e_p, e_n = abs(P_fe - P) / p_lim, abs(axial - cap) / cap
        details[f"la={la}"] = {
            "P_kPa": mpa_to_kpa(P_fe),
            "analytic_kPa": mpa_to_kpa(P),
            "lz": lz,
            "axial_err": e_n,
        }
        worst = max(worst, e_p, e_n)
        fe.append((la, P_fe))
    k = int(np.argmax([p for _, p in fe]))
    if not 0 < k < len(fe) - 1:
        details["limit"] = "the FE pressures have no interior maximum"
        return CaseResult(name, np.inf, tolerance, details)
    (x0, y0), (x1, y1), (x2, y2) = fe[k - 1 : k + 2]
    coef = np.polyfit([x0, x1, x2], [y0, y1, y2], 2)
    fe_lim = float(np.polyval(coef, -coef[1] / (2 * coef[0])))
    details["fe_limit_kPa"] = mpa_to_kpa(fe_lim)
    worst = max(worst, abs(fe_lim - p_lim) / p_lim)
    return CaseResult(name, worst, tolerance, details)


def yeoh_tube_test() -> CaseResult:
    return plane_strain_tube_test("yeoh-tube", YEOH_STIFF, (1.5, 2.5))


def gent_tube_test() -> CaseResult:
    return plane_strain_tube_test("gent-tube", GENT_STIFF, (1.5, 2.2))


def yeoh_closed_tube_test() -> CaseResult:
    return closed_tube_test("yeoh-closed-tube", YEOH_FIT, (1.5, 2.0, 2.4, 2.6, 2.8, 3.2))


def gent_closed_tube_test() -> CaseResult:
    return closed_tube_test("gent-closed-tube", GENT_LIMIT, (1.5, 2.0, 2.6, 2.9, 3.2, 3.6))


CASES = {
    "yeoh-tube": yeoh_tube_test,
    "gent-tube": gent_tube_test,
    "yeoh-closed-tube": yeoh_closed_tube_test,
    "gent-closed-tube": gent_closed_tube_test,
}
