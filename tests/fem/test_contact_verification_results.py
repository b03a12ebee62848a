"""What the `softcrawl verify` contact cases report (fem.contact_verification), beyond passing: each
case's name, tolerance and details against the closed form it is checked on, and a staged solve
that does not converge reported as an infinite error with the solver's message (a scripted
`run_stages`, no solve)."""

import numpy as np
import pytest

from softcrawl.fem import contact_verification as cv
from softcrawl.fem.contact_stages import StagedResult


def test_the_press_case_reports_its_pressure_and_penetration_errors():
    r = cv.press_test()
    assert (r.name, r.tolerance) == ("contact-press", 5e-3)
    d = r.details
    assert set(d) == {"pressure_error", "penetration_over_penalty", "uzawa_solves"}
    assert r.error == max(d["pressure_error"], d["penetration_over_penalty"]) < 5e-3
    assert d["pressure_error"] < 1e-6  # homogeneous compression: p at every point
    # the Uzawa loop brings the penetration well under the pure penalty one, p / eps_N
    assert 0 < d["penetration_over_penalty"] < 1e-3
    assert len(d["uzawa_solves"]) >= 2 and all(n >= 1 for n in d["uzawa_solves"])


def test_the_area_case_reports_nansons_area_and_the_mean_pressure():
    r = cv.area_test()
    assert (r.name, r.tolerance) == ("contact-area", 1e-8)
    d = r.details
    assert d["area_current_exact"] == pytest.approx(1.5 * 1.2**2, rel=1e-15)
    assert d["mean_pressure_exact"] == pytest.approx(0.15 / 1.2**2, rel=1e-15)
    assert d["area_current"] == pytest.approx(2.16, rel=1e-10)
    assert d["mean_pressure"] == pytest.approx(0.15 / 1.44, rel=1e-10)
    assert d["area_reference"] == pytest.approx(1.5, rel=1e-12)
    assert d["normal_force"] == pytest.approx(0.15 * 1.5, rel=1e-10)
    e = d["errors"]
    assert set(e) == {"area_current", "mean_pressure", "area_reference"}
    assert e["area_current"] == abs(d["area_current"] / d["area_current_exact"] - 1.0)
    assert e["mean_pressure"] == abs(d["mean_pressure"] / d["mean_pressure_exact"] - 1.0)
    assert e["area_reference"] == abs(d["area_reference"] / 1.5 - 1.0)
    assert r.error == max(e.values())


def test_the_stick_case_reports_the_shear_it_balances():
    r = cv.stick_test()
    assert (r.name, r.tolerance) == ("contact-stick", 5e-3)
    d = r.details
    assert d["shear"] == pytest.approx(0.5 * 0.3 * 0.02 * 2.0, rel=1e-15)
    assert d["friction_x"] == pytest.approx(-d["shear"], rel=5e-3)
    assert d["slip_fraction"] == 0.0
    assert r.error == pytest.approx(abs(d["friction_x"] + d["shear"]) / d["shear"], rel=1e-12)


def _unconverged(monkeypatch):
    def run_stages(model, stages, **kw):
        x = model.initial_state()
        return StagedResult((), False, "stage 'x' diverged (scripted)", 0.0, 0, 0.0, 0.0, x)

    monkeypatch.setattr(cv, "run_stages", run_stages)


# the drag case forms its error before it looks at convergence: 0 / 0 at the undeformed state here
@pytest.mark.filterwarnings("ignore:invalid value encountered:RuntimeWarning")
@pytest.mark.parametrize("case", ["contact-area", "contact-drag", "contact-stick"])
def test_a_staged_solve_that_does_not_converge_is_an_infinite_error(monkeypatch, case):
    _unconverged(monkeypatch)
    r = cv.CASES[case]()
    assert r.name == case and r.error == np.inf and not r.passed
    assert r.tolerance == {"contact-area": 1e-8, "contact-drag": 5e-3, "contact-stick": 5e-3}[case]
    if case == "contact-area":
        assert r.details == {"message": "stage 'x' diverged (scripted)"}


@pytest.mark.parametrize(
    "residuals, order",
    [
        ([1.0, 1e-1, 1e-2, 1e-4, 1e-8], 2.0),  # quadratic: the last triple
        ([1.0, 1e-1, 1e-2, 1e-3], 1.0),  # r_k = 1e-2 is in the asymptotic range (inclusive)
        ([1e-1, 1e-2, 1e-4, 1e-11], 2.0),  # a residual at the floor is dropped
        ([1.0, 1e-2, 1e-4], 1.0),  # the first triple counts (linear here)
        ([1e-3, 1e-1, 1e-2, 1e-4], 2.0),  # r_k below its predecessor, not below the one before
        ([1e-1, 1e-2, 1e-2, 1e-4], 0.0),  # a stalled residual is no triple of its own
        ([1.0, 0.5, 0.1], float("nan")),  # nothing at or below 1e-2
        ([1e-3, 1e-2, 1e-1], float("nan")),  # rising
        ([1.0], float("nan")),
    ],
)
def test_convergence_order_by_hand(residuals, order):
    got = cv.convergence_order(residuals)
    if np.isnan(order):
        assert np.isnan(got)
    else:
        assert got == pytest.approx(order, rel=1e-12, abs=1e-15)


def test_the_drag_block_carries_its_contact_and_drag_settings():
    model = cv._drag_block(100.0, 0.5, 0.01, 0.05)
    spec = model.contacts[0].spec
    assert (spec.penalty, spec.smoothing, spec.slip_band, spec.mu) == (100.0, 0.01, 0.05, 0.0)
    X = model.mesh.p
    assert np.allclose(X.max(axis=1), [2.0, 1.0, 1.0]) and np.allclose(X.min(axis=1), 0.0)
    assert model.mesh.t.shape[1] == 6 * 4 * 2 * 2  # 4 x 2 x 2 hexahedra of six tetrahedra
