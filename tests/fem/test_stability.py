"""`fem.stability`: the inertia of symmetric matrices whose eigenvalues are known, and the
unstable count and lowest modes of a saddle-point matrix against its Schur complement."""

import numpy as np
import pytest
import scipy.sparse as sp

from softcrawl.fem.errors import SolverInputError
from softcrawl.fem.linsolve import pardiso_available
from softcrawl.fem.stability import inertia, stability

METHODS = ["dense", *(["pardiso"] if pardiso_available() else [])]


def _known(n_neg, n_zero, n_pos, seed=0):
    rng = np.random.default_rng(seed)
    n = n_neg + n_zero + n_pos
    Q, _ = np.linalg.qr(rng.standard_normal((n, n)))
    lam = np.concatenate([-np.linspace(0.5, 3.0, n_neg), np.zeros(n_zero), np.linspace(0.1, 4.0, n_pos)])
    A = Q @ np.diag(lam) @ Q.T
    return 0.5 * (A + A.T)


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize(("n_neg", "n_pos"), [(0, 12), (1, 11), (7, 23), (15, 5)])
def test_inertia_counts_the_known_eigenvalue_signs(method, n_neg, n_pos):
    A = sp.csr_matrix(_known(n_neg, 0, n_pos, seed=n_neg))
    got = inertia(A, method)
    assert (got.negative, got.positive, got.zero) == (n_neg, n_pos, 0)


def test_dense_inertia_sees_a_zero_eigenvalue():
    got = inertia(_known(3, 1, 6), "dense")
    assert (got.negative, got.zero, got.positive) == (3, 1, 6)


def _saddle(n=40, m=10, shift=0.0, seed=3):
    rng = np.random.default_rng(seed)
    A = sp.random(n, n, density=0.2, random_state=rng)
    A = (A + A.T) + sp.eye(n) * shift
    B = sp.random(m, n, density=0.4, random_state=rng)
    C = sp.diags(rng.uniform(0.01, 0.05, m))
    K = sp.bmat([[A, B.T], [B, -C]]).tocsr()
    S = A.toarray() + B.T.toarray() @ np.linalg.solve(C.toarray(), B.toarray())
    return K, S


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("shift", [0.5, 2.0, 6.0])
def test_unstable_count_is_the_schur_complements_negative_count(method, shift):
    K, S = _saddle(shift=shift)
    lam = np.linalg.eigvalsh(S)
    st = stability(K, np.arange(K.shape[0]), n_u=40, method=method)
    assert st.pressure_block.negative == 10  # -C is negative definite
    assert st.n_unstable == int(np.sum(lam < 0))
    assert st.n_unstable == st.tangent.negative - 10
    n = max(st.n_unstable, 1)
    assert st.eigenvalues[:n] == pytest.approx(lam[:n], rel=1e-7, abs=1e-9)  # the lowest, all found
    # the lowest mode is S's eigenvector (up to sign)
    v = st.modes[:, 0]
    assert np.linalg.norm(S @ v - st.eigenvalues[0] * v) < 1e-6 * np.linalg.norm(S, 2)


def test_a_displacement_only_matrix_has_no_pressure_block():
    A = sp.csr_matrix(_known(4, 0, 16))
    st = stability(A, np.arange(20), n_u=20)
    assert st.pressure_block is None and st.n_unstable == 4


def test_a_non_symmetric_tangent_is_refused_naming_it():
    A = sp.csr_matrix(_known(1, 0, 9) + np.triu(np.ones((10, 10)), 1))
    with pytest.raises(SolverInputError, match="K"):
        stability(A, np.arange(10), n_u=10)
