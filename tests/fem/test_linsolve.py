"""Linear solvers: PARDISO (symmetric and non-symmetric paths) against SuperLU."""

import numpy as np
import pytest

from softcrawl.fem import linsolve
from softcrawl.fem import reference_models as RM
from softcrawl.fem.linsolve import LinearSolver, StepSolver, pardiso_available


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


def _skewed(K, c, seed=2):
    """K plus c times a random skew-symmetric matrix on K's pattern (its symmetric part is K's)."""
    r = np.random.default_rng(seed).standard_normal(K.data.size) * np.abs(K.data).max()
    out = K.copy()
    out.data = K.data + c * (r - r[K.pattern._transpose])
    out.pattern = K.pattern
    return out


@pytest.mark.skipif(not pardiso_available(), reason="pypardiso not installed")
def test_the_symmetric_part_preconditions_a_nearly_symmetric_tangent(tangent):
    """A friction tangent is K_sym plus a small skew part: the symmetric part's LDL^T
    factorisation and GMRES on K reach the asked accuracy without an LU of K, and the answer is
    SuperLU's; a predictor's `substitute` is K^{-1} b to SUBSTITUTE_RTOL."""
    _, K, b = tangent
    K2 = _skewed(K, 1e-4)
    split = StepSolver("pardiso", symmetric=False, split=True)
    x = split.solve(K2, b, 1e-8, min_krylov=0)
    assert split.part_factorizations == 1 and split.split_fallbacks == 0
    assert split.krylov_iterations >= 2  # GMRES did work: the factor is not K2's
    assert np.linalg.norm(K2 @ x - b) <= 1e-8 * np.linalg.norm(b)
    ref = LinearSolver("superlu")
    ref.factor(K2)
    assert np.linalg.norm(x - ref.solve(b)) <= 1e-6 * np.linalg.norm(x)
    y = split.substitute(b)
    assert np.linalg.norm(K2 @ y - b) <= StepSolver.SUBSTITUTE_RTOL * np.linalg.norm(b) * 1.0001


@pytest.mark.skipif(not pardiso_available(), reason="pypardiso not installed")
def test_a_strongly_nonsymmetric_tangent_falls_back_to_lu(tangent):
    """When the skew part dominates, GMRES on the symmetric part's factors gives up and K itself
    is factorised: the answer is still accurate and the fallback is counted."""
    _, K, b = tangent
    K2 = _skewed(K, 3.0)
    split = StepSolver("pardiso", symmetric=False, split=True)
    x = split.solve(K2, b, 1e-8, min_krylov=0)
    assert split.split_fallbacks == 1 and split.factorizations == 2
    assert np.linalg.norm(K2 @ x - b) <= 1e-8 * np.linalg.norm(b)
    # one factorisation per solver: the symmetric part's factors were freed for K's LU
    assert [h for h, owner in linsolve._OWNER.items() if owner is split.direct] == [(11, True)]


@pytest.mark.skipif(not pardiso_available(), reason="pypardiso not installed")
def test_switching_between_the_symmetric_part_and_lu_keeps_both_analyses(tangent, monkeypatch):
    """A fallback to LU frees the symmetric part's factors, not its analysis: going back and
    forth analyses each handle once, and every solve is accurate."""
    import pypardiso

    _, K, b = tangent
    phases = []
    original = pypardiso.PyPardisoSolver.set_phase
    monkeypatch.setattr(
        pypardiso.PyPardisoSolver, "set_phase", lambda s, p: (phases.append(p), original(s, p))
    )
    linsolve._ANALYSED.clear()
    split = StepSolver("pardiso", symmetric=False, split=True)
    for c in (1e-4, 3.0, 1e-4, 3.0, 1e-4):
        K2 = _skewed(K, c)
        x = split.solve(K2, b, 1e-10, min_krylov=0)
        assert np.linalg.norm(K2 @ x - b) <= 1e-10 * np.linalg.norm(b)
    assert (split.part_factorizations, split.split_fallbacks) == (5, 2)
    assert phases.count(11) == 2 and phases.count(22) == 7


@pytest.mark.skipif(not pardiso_available(), reason="pypardiso not installed")
def test_after_release_every_solver_analyses_again(tangent, monkeypatch):
    """`release_factorisations` frees the handles' analyses too (PARDISO's phase -1), so a kept
    analysis must not be trusted afterwards: the next factorisation on the same pattern analyses
    and solves accurately (before, it skipped the analysis the handle no longer had)."""
    import pypardiso

    _, K, b = tangent
    K2 = _skewed(K, 1e-4)
    phases = []
    original = pypardiso.PyPardisoSolver.set_phase
    monkeypatch.setattr(
        pypardiso.PyPardisoSolver, "set_phase", lambda s, p: (phases.append(p), original(s, p))
    )
    linsolve._ANALYSED.clear()
    for part in (False, True):
        LinearSolver("pardiso").factor(K2, symmetric=False, part=part)
        linsolve.release_factorisations()
        phases.clear()
        split = StepSolver("pardiso", symmetric=False, split=part)
        x = split.solve(K2, b, 1e-10, min_krylov=0)
        assert phases.count(11) == 1
        assert np.linalg.norm(K2 @ x - b) <= 1e-10 * np.linalg.norm(b)
