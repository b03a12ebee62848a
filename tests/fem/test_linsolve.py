"""Linear solvers: PARDISO (symmetric and non-symmetric paths) against SuperLU."""

import numpy as np
import pytest

from softcrawl.fem import reference_models as RM
from softcrawl.fem.linsolve import LinearSolver, pardiso_available


@pytest.fixture(scope="module")
def tangent():
    model = RM.tube_model(3.0, 9.0, n_radial=3, n_angle=4)
    x = model.initial_state()
    x[: model.n_u] = 1e-2 * np.random.default_rng(0).standard_normal(model.n_u)
    x = model.apply_dirichlet(x, 0.0)
    R, K = model.residual_and_tangent(x, 0.01)
    return model, K, R[model.free_dofs]


def test_closed_chamber_tangent_is_symmetric(tangent):
    """The follower load of a symmetrically cut chamber is conservative: K is symmetric."""
    model, K, _ = tangent
    assert model.pattern.asymmetry(K) < 1e-13


@pytest.mark.skipif(not pardiso_available(), reason="pypardiso not installed")
def test_pardiso_symmetric_and_unsymmetric_paths_agree_with_superlu(tangent):
    model, K, b = tangent
    ref = LinearSolver("superlu")
    ref.factor(K)
    x_ref = ref.solve(b)
    sym = LinearSolver("pardiso")
    sym.factor(K)
    assert sym.symmetric
    assert np.linalg.norm(sym.solve(b) - x_ref) <= 1e-9 * np.linalg.norm(x_ref)
    # break the symmetry on one structurally symmetric pair: the LU path must be taken
    K2 = K.copy()
    K2.pattern = K.pattern
    i = K2.indptr[5] + 1
    K2.data[i] *= 1.5
    lu = LinearSolver("pardiso")
    lu.factor(K2)
    assert not lu.symmetric
    ref.factor(K2)
    x2 = ref.solve(b)
    assert np.linalg.norm(lu.solve(b) - x2) <= 1e-9 * np.linalg.norm(x2)


@pytest.mark.skipif(not pardiso_available(), reason="pypardiso not installed")
def test_a_new_solver_on_the_same_nonsymmetric_pattern_keeps_the_analysis(tangent, monkeypatch):
    """The non-symmetric analysis depends on the pattern alone: a second solver on it (a crawl's
    next phase) does not analyse again and solves bit for bit as after an analysis of its own;
    another pattern is analysed."""
    import pypardiso

    from softcrawl.fem import linsolve

    model, K, b = tangent
    K2 = K.copy()
    K2.pattern = K.pattern
    K2.data[K2.indptr[5] + 1] *= 1.5  # non-symmetric
    K3 = K2.copy()
    K3.pattern = K.pattern
    K3.data *= 1.0 + 1e-3 * np.random.default_rng(1).random(K3.data.size)
    phases = []
    original = pypardiso.PyPardisoSolver.set_phase
    monkeypatch.setattr(
        pypardiso.PyPardisoSolver, "set_phase", lambda s, p: (phases.append(p), original(s, p))
    )
    linsolve._ANALYSED.clear()
    first = LinearSolver("pardiso")
    first.factor(K2)
    second = LinearSolver("pardiso")
    second.factor(K3)
    x_kept = second.solve(b)
    assert phases.count(11) == 1 and second.cost_ratio == first.cost_ratio
    linsolve._ANALYSED.clear()
    fresh = LinearSolver("pardiso")
    fresh.factor(K3)
    assert phases.count(11) == 2
    assert np.array_equal(fresh.solve(b), x_kept)
