"""Viscous slip (`fem.contact_law`, docs/decisions/088-viscous-slip.md): the share kappa, the closed
form of steady sliding, the tangent against central differences, the stage's time step reaching
the contact terms, and the FE case `contact-viscous-drag` (which fails when the law ignores the
viscosity)."""

import numpy as np
import pytest

from softcrawl.fem import contact as contact_module
from softcrawl.fem import contact_verification as cv
from softcrawl.fem.contact import ContactSpec
from softcrawl.fem.contact_law import committed_stick, evaluate, steady_slip_traction, viscous_share
from softcrawl.fem.contact_stages import Stage, run_stages
from softcrawl.fem.errors import SolverInputError
from softcrawl.fem.model import ChamberSpec, Dirichlet, SolidModel
from softcrawl.fem.rigid_surfaces import CylinderWall, Plane
from softcrawl.fem.structured import box

EPS_N, EPS_T, MU, DEPTH = 10.0, 5.0, 0.4, 0.05


def test_the_viscous_share_is_eta_over_eta_plus_eps_t_dt():
    assert viscous_share(0.0, EPS_T, 0.1) == 0.0 and viscous_share(0.2, EPS_T, None) == 0.0
    assert viscous_share(0.2, EPS_T, 0.0) == 1.0
    assert viscous_share(0.2, EPS_T, 0.04) == pytest.approx(0.2 / (0.2 + EPS_T * 0.04), rel=1e-15)


@pytest.mark.parametrize("dt", [0.01, 0.1, 1.0])
def test_a_point_dragged_steadily_reaches_mu_p_plus_eta_v_at_any_step(dt):
    """A point DEPTH into the plane z = 0, moved along x at v per second in steps of dt, its stick
    point committed after each: the traction converges to mu p_N + eta v whatever dt (the fixed
    point of backward Euler); the rate-independent law (kappa = 0) stays at mu p_N."""
    eta, v = 0.3, 0.5
    kappa = viscous_share(eta, EPS_T, dt)
    surface, lam = Plane(), np.zeros(1)
    x = np.array([[0.0, 0.0, -DEPTH]])
    stick, coulomb_stick = x.copy(), x.copy()
    for _ in range(int(40.0 / dt) + 200):
        x = x + np.array([[v * dt, 0.0, 0.0]])
        st = evaluate(x, surface, lam, stick, EPS_N, EPS_T, MU, False, kappa=kappa)
        stick = committed_stick(st, x, stick, EPS_T, MU, kappa)
        plain = evaluate(x, surface, lam, coulomb_stick, EPS_N, EPS_T, MU, False)
        coulomb_stick = committed_stick(plain, x, coulomb_stick, EPS_T, MU)
    mu_p = MU * EPS_N * DEPTH
    assert -st.friction[0, 0] == pytest.approx(steady_slip_traction(mu_p, eta, v), rel=1e-9)
    assert -plain.friction[0, 0] == pytest.approx(mu_p, rel=1e-12)


def test_in_no_time_a_point_cannot_slip():
    """kappa = 1 (dt = 0): the traction is the elastic trial however far past the cone."""
    x = np.array([[0.0, 0.0, -DEPTH]])
    stick = x - np.array([[3.0 * MU * EPS_N * DEPTH / EPS_T, 0.0, 0.0]])  # r = 3
    st = evaluate(x, Plane(), np.zeros(1), stick, EPS_N, EPS_T, MU, False, kappa=1.0)
    assert st.friction[0] == pytest.approx(st.trial[0], rel=1e-15)


@pytest.mark.parametrize(
    "surface", [Plane(normal=(0.2, 0.1, 1.0)), CylinderWall(5.0)], ids=["plane", "cylinder"]
)
@pytest.mark.parametrize("slip_band", [0.0, 0.6])
def test_the_viscous_tangent_matches_finite_differences(surface, slip_band):
    rng = np.random.default_rng(1)
    x = rng.normal(size=(60, 3)) * 0.3
    if isinstance(surface, CylinderWall):
        th = rng.uniform(0, 2 * np.pi, 60)
        x[:, :2] += 5 * np.column_stack([np.cos(th), np.sin(th)])
    stick = x + rng.normal(size=(60, 3)) * 0.05
    args = (surface, rng.uniform(0, 0.1, 60), stick, EPS_N, 7.0, MU)
    st = evaluate(x, *args, True, 0.0, slip_band, 0.3)
    assert st.slip.sum() >= 2 and (st.active & ~st.slip).sum() >= 2
    h = 1e-6
    for j in range(3):
        d = np.zeros(3)
        d[j] = h
        plus = evaluate(x + d, *args, False, 0.0, slip_band, 0.3).force
        fd = -(plus - evaluate(x - d, *args, False, 0.0, slip_band, 0.3).force) / (2 * h)
        assert np.abs(fd - st.stiffness[:, :, j]).max() < 1e-7 * np.abs(st.stiffness).max()


def test_each_sub_step_tells_the_contacts_its_time():
    """A stage with a duration gives each sub-step (s - t) x duration; one without, None."""
    mesh = box((1.0, 1.0, 1.0), (1, 1, 1))
    spec = ContactSpec(("z0",), Plane(), penalty=100.0, slip_viscosity=0.01)
    bcs = [Dirichlet.symmetry("y0", 1)]
    model = SolidModel(mesh, cv.MATERIAL, dirichlet=bcs, chambers=ChamberSpec(("z1",)), contacts=[spec])
    seen = []
    model.contacts[0].set_time_step = lambda dt: seen.append(dt)
    run_stages(model, [Stage("press", pressure=0.1, steps=2), Stage("hold", steps=4, duration=2.0)])
    assert seen == [None, None, 0.5, 0.5, 0.5, 0.5]


def test_bad_viscosity_and_duration_name_the_parameter():
    with pytest.raises(SolverInputError, match="contact.slip_viscosity"):
        ContactSpec(("z0",), Plane(), penalty=1.0, slip_viscosity=-1e-3)
    with pytest.raises(SolverInputError, match="stage.duration"):
        Stage("s", duration=0.0)


def test_the_viscous_drag_case_passes_and_fails_without_the_viscosity(monkeypatch):
    result = cv.viscous_drag_test()
    assert result.passed, (result.error, result.details)
    monkeypatch.setattr(contact_module, "viscous_share", lambda *a: 0.0)  # the law as before
    coulomb = cv.viscous_drag_test()
    assert coulomb.error > 40 * coulomb.tolerance  # 27 % off
