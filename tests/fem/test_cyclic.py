"""fem.cyclic: the per-harmonic inertia of a block-circulant tangent built from chosen harmonic
blocks H_n (known Schur-complement spectra), on a synthetic mesh of N rotated sectors whose
nodes are shuffled and whose displacements are Cartesian (the code must find the orbits and
rotate them itself). The check on a real revolved foot is tests/studies/skirt/test_cyclic_foot.py."""

import numpy as np
import pytest

from softcrawl.errors import InputError
from softcrawl.fem.cyclic import cyclic_stability, cyclic_symmetry
from softcrawl.fem.stability import inertia

RNG = np.random.default_rng(7)
N_ORBITS, HELD_ORBIT, P_ORBITS = 4, 1, (0, 2)


def _unitary(m, real, rng):
    Z = rng.standard_normal((m, m)) + (0 if real else 1j * rng.standard_normal((m, m)))
    Q, _ = np.linalg.qr(Z)
    return Q


def _harmonic(lam, m_p, real, rng):
    """H = [[A, B^H], [B, -C]] with C HPD and Schur complement A + B^H C^-1 B of eigenvalues lam."""
    m_u = len(lam)
    Q = _unitary(m_u, real, rng)
    S = Q @ np.diag(lam) @ Q.conj().T
    B = rng.standard_normal((m_p, m_u)) + (0 if real else 1j * rng.standard_normal((m_p, m_u)))
    G = rng.standard_normal((m_p, m_p))
    C = G @ G.T + m_p * np.eye(m_p)
    A = S - B.conj().T @ np.linalg.solve(C, B)
    H = np.block([[A, B.conj().T], [B, -C]])
    return 0.5 * (H + H.conj().T)


def _synthetic(N, spectra, rng):
    """Nodes, free dofs, pressure vertices and the Cartesian K of a mesh of N sectors whose
    harmonic blocks have the Schur spectra `spectra[n]` (n = 0..N//2)."""
    delta = 2 * np.pi / N
    rho, z = 1.0 + rng.random(N_ORBITS), rng.standard_normal(N_ORBITS)
    theta0 = delta * np.r_[0.0, 0.1 + 0.8 * rng.random(N_ORBITS - 1)]  # orbit 0 on the sector plane
    free_orbits = [j for j in range(N_ORBITS) if j != HELD_ORBIT]
    m_u, m_p = 3 * len(free_orbits), len(P_ORBITS)
    m = m_u + m_p
    H = {}
    for n in range(N // 2 + 1):
        real = n == 0 or 2 * n == N
        H[n] = _harmonic(np.asarray(spectra[n], float), m_p, real, rng)
        H[N - n] = H[n].conj() if n else H[n]
    w = np.exp(2j * np.pi / N)
    C = [sum(H[n] * w ** (-n * d) for n in range(N)).real / N for d in range(N)]
    Kcyl = np.block([[C[(t - s) % N] for t in range(N)] for s in range(N)])  # (s, a) x (t, b)
    # the mesh: node (j, s) gets a shuffled number; displacement dof 3 node + i, then pressures
    perm = rng.permutation(N_ORBITS * N)
    node = perm.reshape(N_ORBITS, N)
    phi = theta0[:, None] + delta * np.arange(N)
    nodes = np.zeros((3, N_ORBITS * N))
    nodes[0, node], nodes[1, node], nodes[2, node] = (
        rho[:, None] * np.cos(phi),
        rho[:, None] * np.sin(phi),
        z[:, None],
    )
    pressure_vertex = node[list(P_ORBITS)].T.reshape(-1)[::-1]  # in an order of their own
    n_u = 3 * N_ORBITS * N
    # Cartesian dof of each (sector, local) entry and the 3x3 rotations
    R = np.zeros((n_u + len(pressure_vertex), N * m))
    for s in range(N):
        for k, j in enumerate(free_orbits):
            c, si = np.cos(phi[j, s]), np.sin(phi[j, s])
            frame = np.array([[c, -si, 0], [si, c, 0], [0, 0, 1]])  # columns e_r, e_theta, e_z
            R[3 * node[j, s] : 3 * node[j, s] + 3, s * m + 3 * k : s * m + 3 * k + 3] = frame
        for k, j in enumerate(P_ORBITS):
            q = int(np.flatnonzero(pressure_vertex == node[j, s])[0])
            R[n_u + q, s * m + m_u + k] = 1.0
    held = 3 * node[HELD_ORBIT][:, None] + np.arange(3)
    free = np.setdiff1d(np.arange(R.shape[0]), held.reshape(-1))
    K = (R @ Kcyl @ R.T)[np.ix_(free, free)]
    return nodes, free, n_u, pressure_vertex, 0.5 * (K + K.T)


@pytest.mark.parametrize("N", [6, 5])
def test_per_harmonic_inertia_of_a_synthetic_block_circulant_tangent(N):
    rng = np.random.default_rng(N)
    m_u = 3 * (N_ORBITS - 1)
    base = np.linspace(0.5, 3.0, m_u)
    spectra = {n: base + n for n in range(N // 2 + 1)}
    spectra[2] = np.r_[-0.7, -0.2, base[2:]]  # two unstable modes in harmonic 2 (and 2 in N - 2)
    spectra[N // 2] = np.r_[-0.4, base[1:]]  # one in N // 2 (its own conjugate when N is even)
    nodes, free, n_u, pv, K = _synthetic(N, spectra, rng)
    sym = cyclic_symmetry(nodes, N, free, n_u, pv)
    cs = cyclic_stability(K, sym, method="dense")
    expected = {n: int(np.sum(np.asarray(spectra[n]) < 0)) for n in range(N // 2 + 1)}
    assert {h.n: h.n_unstable for h in cs.harmonics} == expected
    for h in cs.harmonics:
        assert h.multiplicity == (1 if h.n == 0 or 2 * h.n == N else 2)
        assert h.pressure_block.negative == len(P_ORBITS)
        assert h.eigenvalues[0] == pytest.approx(min(spectra[h.n]), abs=1e-8)
    whole = inertia(K, "dense")
    assert (cs.tangent.positive, cs.tangent.negative) == (whole.positive, whole.negative)
    assert cs.n_unstable == sum(h.multiplicity * expected[h.n] for h in cs.harmonics)
    assert cs.circulant_error < 1e-12


def test_a_mode_maps_back_to_an_eigenvector_of_the_schur_complement():
    N = 6
    rng = np.random.default_rng(1)
    base = np.linspace(0.5, 3.0, 9)
    spectra = {n: base + n for n in range(4)}
    spectra[2] = np.r_[-0.7, base[1:]]
    nodes, free, n_u, pv, K = _synthetic(N, spectra, rng)
    sym = cyclic_symmetry(nodes, N, free, n_u, pv)
    h = cyclic_stability(K, sym, method="dense").harmonics[2]
    is_u = free < n_u
    A, B, C = K[np.ix_(is_u, is_u)], K[np.ix_(~is_u, is_u)], -K[np.ix_(~is_u, ~is_u)]
    S = A + B.T @ np.linalg.solve(C, B)
    for part in ("real", "imag"):
        v = sym.mode_on_free_dofs(h.modes[:, 0], 2, part)[is_u]
        assert np.linalg.norm(S @ v - h.eigenvalues[0] * v) < 1e-8


def test_a_mesh_that_is_not_cyclic_is_refused():
    nodes, free, n_u, pv, K = _synthetic(6, {n: np.linspace(1, 2, 9) for n in range(4)}, RNG)
    moved = nodes.copy()
    moved[2, 5] += 1e-3
    with pytest.raises(InputError, match="sectors"):
        cyclic_symmetry(moved, 6, free, n_u, pv)
    with pytest.raises(InputError, match="sectors"):
        cyclic_symmetry(nodes, 4, free, n_u, pv)  # the wrong sector count
    axis = np.c_[nodes, [0.0, 0.0, 0.5]]
    with pytest.raises(InputError, match="axis"):
        cyclic_symmetry(axis, 6, free, n_u, pv)


def test_a_tangent_that_is_not_block_circulant_is_refused():
    nodes, free, n_u, pv, K = _synthetic(6, {n: np.linspace(1, 2, 9) for n in range(4)}, RNG)
    sym = cyclic_symmetry(nodes, 6, free, n_u, pv)
    K2 = K.copy()
    K2[0, 0] += 1e-3 * np.abs(K).max()
    with pytest.raises(InputError, match="block-circulant"):
        cyclic_stability(K2, sym, method="dense")
