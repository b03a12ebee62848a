"""Inertia (`fem.inertia`, docs/decisions/089-inertia.md): the HRZ-lumped mass against its closed
form, backward Euler's exact momentum balance and first-order centre-of-mass motion under a
constant force, an oscillator against backward Euler's recursion and, as dt shrinks, against the
exact cosine, the quasi-static limit, and bad input."""

import numpy as np
import pytest
import skfem

from softcrawl.fem.axial_link import AxialLink
from softcrawl.fem.contact_stages import Stage, run_stages
from softcrawl.fem.discretisation import Discretisation
from softcrawl.fem.errors import SolverInputError
from softcrawl.fem.inertia import Inertia, lumped_masses
from softcrawl.fem.laws import NeoHookean
from softcrawl.fem.model import Dirichlet, SolidModel
from softcrawl.fem.structured import box

RHO = 1.0e-3  # t/mm^3: a unit cube of 1e-3 t, so that forces of order 1 N move it in ~0.1 s
STIFF = NeoHookean(mu=1.0e3, bulk=2.0e3)  # the block's own modes far above the oscillator's


def test_hrz_gives_a_straight_p2_tet_its_corner_and_mid_edge_shares():
    """Exact quadrature (order 4): a corner 1/36, a mid-edge node 4/27 of rho V; all positive (the
    row sums would give the corners -1/20)."""
    p = np.array([[0.0, 2.0, 0.0, 0.0], [0.0, 0.0, 3.0, 0.0], [0.0, 0.0, 0.0, 1.5]])
    mesh = skfem.MeshTet(p, np.array([[0], [1], [2], [3]]))
    space = Discretisation(mesh, "p2", intorder=4)
    m = lumped_masses(space, 2.0)
    volume = 2.0 * 3.0 * 1.5 / 6
    corners = m[space.node_dofs[:4, 0]]
    edges = m[space.node_dofs[4:, 0]]
    assert corners == pytest.approx(np.full(4, 2.0 * volume / 36), rel=1e-12)
    assert edges == pytest.approx(np.full(6, 2.0 * volume * 4 / 27), rel=1e-12)


def test_the_lumped_masses_sum_to_each_parts_mass():
    mesh = box((2.0, 1.0, 1.0), (4, 2, 2))
    left = np.flatnonzero(mesh.p[0, mesh.t].mean(axis=0) < 1.0)
    right = np.setdiff1d(np.arange(mesh.t.shape[1]), left)
    mesh = mesh.with_subdomains({"left": left, "right": right})
    space = Discretisation(mesh, "p2")
    both = lumped_masses(space, {"left": 1e-9, "right": 3e-9})
    assert both.sum() == pytest.approx(1e-9 + 3e-9, rel=1e-12)
    assert np.all(both > 0)
    only_left = lumped_masses(space, {"left": 1e-9})
    assert only_left.sum() == pytest.approx(1e-9, rel=1e-12)
    assert np.count_nonzero(only_left == 0) > 0  # nodes of the right half only carry no mass


def _free_block(force):
    """A unit cube, nothing prescribed, pushed along x by a dead load on x1."""
    return SolidModel(
        box((1.0, 1.0, 1.0), (2, 2, 2)),
        STIFF,
        formulation="p2",
        dead_loads={"x1": (force, 0.0, 0.0)},
        extra_terms=[Inertia(RHO)],
    )


@pytest.mark.parametrize("steps", [1, 2, 4, 8])
def test_a_free_block_under_a_constant_force_keeps_momentum_exactly_and_moves_first_order(steps):
    """Over T = 0.2 s from rest: momentum M v = F T exactly; the centre of mass moves
    F T^2 / (2 M) (1 + 1/N), backward Euler's closed form (error O(dt) against the exact
    F T^2 / (2 M))."""
    F, T = 0.05, 0.2
    model = _free_block(F)
    term = model.terms[-1]
    res = run_stages(model, [Stage("push", factor=1.0, steps=steps, duration=T)], factor0=1.0)
    assert res.converged, res.message
    assert len(res.steps) == steps
    M = term.total_mass
    assert M == pytest.approx(RHO, rel=1e-12)
    assert term.momentum() == pytest.approx([F * T, 0.0, 0.0], abs=1e-9 * F * T)
    centre = (term.mass * res.x[term.dofs]).sum(axis=1) / M
    assert centre[0] == pytest.approx(F * T**2 / (2 * M) * (1 + 1 / steps), rel=1e-8)
    assert abs(centre[1]) < 1e-12 and abs(centre[2]) < 1e-12


def _oscillator(k, u0):
    """The stiff cube on sliding supports (y0, z0), its face x1 on a ground spring k along x and
    pushed by a dead load k u0 (a spring's preload would leave Newton no force scale)."""
    model = SolidModel(
        box((1.0, 1.0, 1.0), (2, 2, 2)),
        STIFF,
        formulation="p2",
        dirichlet=[Dirichlet.symmetry("y0", 1), Dirichlet.symmetry("z0", 2)],
        dead_loads={"x1": (k * u0, 0.0, 0.0)},
        extra_terms=[AxialLink("x1", None, 0, k, name="spring"), Inertia(RHO)],
    )
    spring, mass = model.terms[-2:]
    return model, spring, mass


def _backward_euler(omega, u0, dt, n):
    """(u_{j+1} - 2 u_j + u_{j-1}) / dt^2 + omega^2 u_{j+1} = omega^2 u0 (1 - (j+1) / (2 n)), from
    rest at u0: backward Euler for the load ramped to half over n steps."""
    u = [u0, u0]
    for j in range(n):
        load = (omega * dt) ** 2 * u0 * (1 - (j + 1) / (2 * n))
        u.append((2 * u[-1] - u[-2] + load) / (1 + (omega * dt) ** 2))
    return np.array(u[1:])


def _exact(omega, u0, T, t):
    """u'' + omega^2 u = omega^2 u0 (1 - t / (2 T)) from rest at u0:
    u = u0 (1 - t / (2 T)) + u0 sin(omega t) / (2 omega T)."""
    return u0 * (1 - t / (2 * T)) + u0 * np.sin(omega * t) / (2 * omega * T)


def _released(steps, T, k=1.0, u0=0.01):
    """Held at u0 quasi-statically (no duration: at rest there), then the load ramped to half over T
    (not to zero: with no load left, Newton's force scale would be the spring's alone)."""
    model, spring, mass = _oscillator(k, u0)
    stages = [Stage("hold", factor=1.0, steps=1), Stage("release", factor=0.5, steps=steps, duration=T)]
    seen = []
    res = run_stages(model, stages, on_step=lambda st: seen.append(-spring.tension(st.x) / k))
    assert res.converged, res.message
    return np.array(seen), np.sqrt(k / mass.total_mass)


def test_a_released_spring_mass_follows_backward_eulers_recursion():
    """Held at u0, its load ramped to half over T = 0.1 s (half a period) in 10 steps: the spring
    face's motion is backward Euler's recursion for omega = sqrt(k / M), to the block's own
    flexibility (1e-3 of u0), and its swing about the static path is short of the exact one: the
    scheme damps."""
    u0, T, n = 0.01, 0.1, 10
    seen, omega = _released(n, T)
    assert seen[0] == pytest.approx(u0, rel=1e-3)  # the quasi-static hold
    expected = _backward_euler(omega, u0, T / n, n)
    assert np.abs(seen[1:] - expected[1:]).max() < 1e-3 * u0
    t = np.arange(n + 1) * T / n
    path = u0 * (1 - t / (2 * T))  # the static path; the swing is the motion's distance from it
    swing, swing_exact = np.abs(seen - path).max(), np.abs(_exact(omega, u0, T, t) - path).max()
    assert 0.3 * swing_exact < swing < 0.9 * swing_exact


def test_the_oscillator_converges_to_the_exact_motion_at_first_order():
    """The error at T / 2 against the exact motion halves with the step (order 1 in dt; measured
    1.83 and 1.92)."""
    u0, T = 0.01, 0.1
    errors = []
    for n in (10, 20, 40):
        seen, omega = _released(n, T, u0=u0)
        errors.append(abs(seen[n // 2] - _exact(omega, u0, T, T / 2)))
    ratios = [errors[i] / errors[i + 1] for i in range(2)]
    assert all(1.7 < r < 2.3 for r in ratios), (errors, ratios)


def test_without_a_duration_the_term_adds_nothing_and_commits_rest():
    model = _free_block(0.0)
    term = model.terms[-1]
    x = np.random.default_rng(1).normal(size=model.n_dofs) * 1e-2
    r, K = term.arrays(x)
    assert not r.any() and not K.any()
    term.set_time_step(0.1)
    r, K = term.arrays(x)
    assert r.any()
    dx = np.random.default_rng(2).normal(size=model.n_dofs) * 1e-3
    r2, _ = term.arrays(x + dx)
    assert np.allclose(r2 - r, np.einsum("nij,jn->in", K, dx[term.dofs]), rtol=1e-12, atol=1e-15)
    term.commit(x)
    assert term.time_step is None and term.kinetic_energy() > 0  # the sub-step ended, moving
    term.commit(x)  # a quasi-static commit: at rest
    assert term.kinetic_energy() == 0.0


def test_bad_inertia_input_names_the_parameter():
    space = Discretisation(box(), "p2")
    with pytest.raises(SolverInputError, match="inertia.densities"):
        lumped_masses(space, -1.0)
    with pytest.raises(SolverInputError, match="inertia.densities"):
        lumped_masses(space, {"nowhere": 1e-9})
    term = Inertia(1e-9).build(space)
    with pytest.raises(SolverInputError, match="inertia.time_step"):
        term.set_time_step(0.0)
    with pytest.raises(SolverInputError, match="inertia.history"):
        term.set_history(np.zeros(3), np.zeros(3))
