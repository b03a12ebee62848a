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
