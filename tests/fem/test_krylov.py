"""GMRES on the last factorisation (fem.krylov, fem.linsolve.StepSolver) and the tangent
predictor (fem.newton.NewtonSolver.load_tangent)."""

import numpy as np
import scipy.sparse as sp

from softcrawl.fem import reference_models as RM
from softcrawl.fem.krylov import gmres
from softcrawl.fem.laws import NeoHookean
from softcrawl.fem.linsolve import StepSolver
from softcrawl.fem.model import ChamberSpec, Dirichlet, SolidModel
from softcrawl.fem.newton import NewtonOptions, NewtonSolver
from softcrawl.fem.path import load_path
from softcrawl.fem.structured import tube_sector


def test_gmres_with_a_nearby_factorisation_reaches_the_weighted_tolerance():
    rng = np.random.default_rng(1)
    n = 200
    A = sp.random(n, n, density=0.05, random_state=2) + 10 * sp.eye(n)
    A0 = (A + 0.05 * sp.diags(rng.standard_normal(n))).tocsc()  # the "old" matrix
    lu = sp.linalg.splu(A0)
    b = rng.standard_normal(n)
    w = np.r_[np.full(100, 1.0), np.full(100, 1e3)]  # two blocks on very different scales
    res = gmres(lambda v: A @ v, lu.solve, b, rtol=1e-10, max_iter=30, weights=w)
    assert res.converged and res.iterations <= 6  # observed 5
    assert np.linalg.norm(w * (A @ res.x - b)) <= 1e-10 * np.linalg.norm(w * b) * 1.01
    exact = sp.linalg.spsolve(A.tocsc(), b)
    assert np.linalg.norm(res.x - exact) <= 5e-11 * np.linalg.norm(exact)  # observed 1.4e-11
    # too few iterations: reported as not converged, never as a solution
    short = gmres(lambda v: A @ v, lu.solve, b, rtol=1e-14, max_iter=1, weights=w)
    assert not short.converged and short.relative_residual > 1e-14


def test_step_solver_reuses_the_last_factorisation_on_a_nearby_tangent():
    model = RM.tube_model(3.0, 9.0, n_radial=3, n_angle=4)
    x = model.initial_state()
    x[: model.n_u] = 1e-2 * np.random.default_rng(0).standard_normal(model.n_u)
    x = model.apply_dirichlet(x, 0.0)
    _, K0 = model.residual_and_tangent(x, 0.01)
    _, K1 = model.residual_and_tangent(1.01 * x, 0.0101)  # a nearby state and load
    b = np.random.default_rng(1).standard_normal(K0.shape[0])
    solver = StepSolver(None, model.symmetric_tangent)
    solver.solve(K0, b, 1e-8)
    # this small system's factorisation costs ~ a substitution (no reuse): pretend a large one
    solver.direct.cost_ratio = 20.0
    X = solver.solve(K1, b, 1e-8, min_krylov=2)
    assert solver.factorizations == 1 and solver.krylov_iterations > 0
    assert np.linalg.norm(K1 @ X - b) <= 1e-8 * np.linalg.norm(b) * 1.01
    solver.solve(K1, b, 1e-8, min_krylov=0)  # reuse forbidden: a new factorisation
    assert solver.factorizations == 2


def test_load_tangent_is_the_derivative_of_the_equilibrium_path():
    """dx/dP from K dx/dP = q at a converged state against central differences of converged
    states at P +- dP (second order: the difference error is ~dP^2; observed 9.4e-9)."""
    model = RM.tube_model(3.0, 9.0, n_radial=3, n_angle=4)
    P, dP = 0.3 * RM.MU, 1e-4 * RM.MU
    states = [
        load_path(model, [(p, 0.0)], options=NewtonOptions(tol=1e-12)).steps[-1].x
        for p in (P - dP, P, P + dP)
    ]
    solver = NewtonSolver(model, NewtonOptions())
    v = solver.load_tangent(states[1], np.array([P, 0.0]), np.array([1.0, 0.0]))
    fd = (states[2] - states[0]) / (2 * dP)
    u = slice(0, model.n_u)
    assert np.linalg.norm(v[u] - fd[u]) <= 3e-8 * np.linalg.norm(fd[u])  # observed 9.4e-9


def test_the_symmetry_of_the_tangent_follows_the_load_types():
    """The plane-strain tube's chamber (caps held in z, cap flux dropped) is conservative: a
    symmetric tangent. With the top cap free the dropped cap flux is no longer zero, the load is
    not the derivative of the volume, and the tangent is not symmetric: LU, not LDL^T."""
    assert RM.tube_model(3.0, 9.0, n_radial=2, n_angle=3).symmetric_tangent
    mesh = tube_sector(3.0, 9.0, height=1.0, n_radial=2, n_angle=3, n_height=1, geometric=True)
    bcs = [Dirichlet.symmetry("sym_x", 0), Dirichlet.symmetry("sym_y", 1), Dirichlet.symmetry("bottom", 2)]
    open_top = SolidModel(
        mesh,
        NeoHookean.nearly_incompressible(0.03, 1000.0),
        dirichlet=bcs,
        chambers=ChamberSpec(("inner",), (1, 1, 0)),
    )
    assert not open_top.symmetric_tangent
    x = open_top.apply_dirichlet(1e-2 * np.random.default_rng(0).standard_normal(open_top.n_dofs), 0.0)
    _, K = open_top.residual_and_tangent(x, 0.01)
    assert open_top.pattern.asymmetry(K) > 1e-6


def test_load_tangent_after_newton_uses_the_last_factorisation():
    """Right after a converged Newton step whose last iteration factorised the tangent, the
    predictor's tangent solve is one substitution with that factorisation (no assembly, no
    factorisation, no GMRES); it matches the slope from a fresh assembly at the converged state
    (the factorised tangent is one quadratic update behind: observed 1.8e-8 relative)."""
    model = RM.tube_model(3.0, 9.0, n_radial=3, n_angle=4)
    P = 0.3 * RM.MU
    L, d = np.array([P, 0.0]), np.array([1.0, 0.0])
    solver = NewtonSolver(model, NewtonOptions())
    x, record = solver.load_step(model.initial_state(), P, 0.0)
    assert record.iterations >= 2
    lin = solver.linear
    counts = (lin.factorizations, lin.krylov_iterations, lin.substitutions + 1)
    v = solver.load_tangent(x, L, d)
    assert (lin.factorizations, lin.krylov_iterations, lin.substitutions) == counts
    fresh = NewtonSolver(model, NewtonOptions()).load_tangent(x.copy(), L, d)
    u = slice(0, model.n_u)
    assert np.linalg.norm(v[u] - fresh[u]) <= 6e-8 * np.linalg.norm(fresh[u])


def test_gmres_abandons_a_solve_that_cannot_converge_within_its_iterations():
    """A preconditioner far from the matrix: the residual falls ~10x more slowly than 20
    iterations need for 1e-8; with `abandon` GMRES stops at the third iteration and reports no
    convergence, without it runs all 20. A good preconditioner is never abandoned."""
    rng = np.random.default_rng(3)
    n = 300
    A = sp.diags(np.linspace(1.0, 1e4, n)).tocsr()
    b = rng.standard_normal(n)
    full = gmres(lambda v: A @ v, lambda v: v, b, rtol=1e-8, max_iter=20)
    short = gmres(lambda v: A @ v, lambda v: v, b, rtol=1e-8, max_iter=20, abandon=True)
    assert not full.converged and full.iterations == 20
    assert not short.converged and short.iterations == 3
    assert short.relative_residual > 1e-8
    near = A + sp.diags(1e-3 * rng.standard_normal(n) * np.linspace(1.0, 1e4, n))
    inverse = 1.0 / near.diagonal()
    good = gmres(lambda v: A @ v, lambda v: inverse * v, b, rtol=1e-8, max_iter=20, abandon=True)
    assert good.converged and good.iterations <= 4
