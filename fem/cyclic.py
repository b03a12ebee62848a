r"""Stability of a state with cyclic symmetry, one circumferential harmonic at a time.

Setting. A mesh made of N identical sectors about the z axis (the rotation R by Delta = 2 pi / N
maps the mesh, its boundary conditions and its loads onto themselves) and a state invariant
under R (an axisymmetric insertion: u = u_r(rho, z) e_r + u_z(rho, z) e_z, p = p(rho, z), a
cylindrical wall about z). The symmetric tangent K on the free dofs (`fem.stability`) then
commutes with the rotation, and its inertia splits by harmonic.

Orbits (`cyclic_symmetry`). A node X of sector 0 has N images R^s X, s = 0..N-1: node (j, s).
A node's sector is s = floor(theta / Delta) (a node on the plane between two sectors goes to the
higher one, within the tolerance), its image in sector 0 is R^{-s} X, and the images are matched
within `tol` (a KD-tree). Refused, naming the parameter: a node without all its N images (the
mesh is not made of N sectors), a node on the axis (its own image: not handled), an orbit whose
nodes are neither all free nor all held in all three components (a boundary condition that is
not cyclic, or that holds one Cartesian component only).

Cylindrical frame. The displacement dofs of node (j, s) are rotated into (u_r, u_theta, u_z) at
phi = theta_j + s Delta, pressures are left as they are (a scalar), and the dofs are ordered by
(sector s, local dof a): T is orthogonal, K' = T^T K T, and
    K'[(s, a), (t, b)] = C_{t-s}[a, b],   C_{-m} = C_m^T  (K symmetric).
This is checked, not assumed: every stored entry of K' is compared with block row 0's, and the
largest difference relative to max |K| is `CyclicStability.circulant_error` (above
`CIRCULANT_TOL`: refused, the state or the loads are not cyclic).

Harmonics. With omega = exp(i 2 pi / N), the unitary transform v_s = omega^{n s} phi / sqrt(N)
block-diagonalises K': (K' v)_s = omega^{n s} H_n phi / sqrt(N),
    H_n = sum_m C_m omega^{n m},   n = 0..N-1,
each of one sector's size, Hermitian (C_{-m} = C_m^T), H_{N-n} = conj(H_n) (same inertia),
H_0 and H_{N/2} (N even) real. By Sylvester's law of inertia
    In(K) = In(K') = sum_{n=0}^{N-1} In(H_n) = sum_{n=0}^{floor(N/2)} mult_n In(H_n),
mult_n = 1 for n = 0 and n = N/2, 2 otherwise.

Unstable modes per harmonic. For the P2-P1 tangent K = [[A, B^T], [B, -C]] the pressure dofs
are only reordered, so the pressure block of K' is -C reordered: block-circulant, and negative
definite. Its harmonic blocks are the pressure blocks (H_n)_pp: the transform is unitary and
acts on the pressure dofs alone, so each (H_n)_pp is a compression of a negative definite matrix
by orthonormal columns, negative definite. Haynsworth's additivity then holds in each harmonic:
In(H_n) = In((H_n)_pp) + In(S_n), S_n = A_n + B_n^H C_n^{-1} B_n, and S_n is the harmonic n block
of the displacement stiffness S = A + B^T C^{-1} B (the transform block-diagonalises A, B and C,
hence the Schur complement). So harmonic n has neg(H_n) - neg((H_n)_pp) = neg(S_n) unstable modes,
and their sum with multiplicities is `fem.stability`'s neg(K) - neg(K_pp).

Real form. A Hermitian H = X + i Y (X symmetric, Y antisymmetric) acts on (Re phi, Im phi) as
the real symmetric E(H) = [[X, -Y], [Y, X]], which has each eigenvalue of H twice, with
eigenvectors (phi_r, phi_i) and (-phi_i, phi_r). So In(H) = In(E) / 2 (an odd count is refused),
and `fem.stability.stability` on E (PARDISO's LDL^T, shift-invert Lanczos on its Schur
complement; order [Re u, Im u, Re p, Im p]) gives each harmonic's count and its lowest
eigenvalues of S_n in pairs: one of each pair is kept, as phi = x_r + i x_i.

Modes in the mesh (`CyclicSymmetry.mode_on_free_dofs`). A mode phi of S_n is the wave
u'_(s, a) = Re(omega^{n s} phi_a) (and its partner Im(...), the same eigenvalue for 0 < n < N/2)
in the cylindrical frame, mapped back through T. A wave of L lobes has omega^{n s} = exp(i L s
Delta), so it lies in harmonic n = L mod N, counted here as min(n, N - n): waves shorter than
two sectors (L > N/2, carried by the P2 midside nodes) appear at n = N - L.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

from softcrawl.fem.errors import SolverInputError
from softcrawl.fem.stability import Inertia, asymmetry, split_tangent, stability, unstable_count

#: Default matching tolerance of a node's images, as a share of the mesh's extent.
REL_TOL = 1e-7
#: Largest |K'[(s, a), (t, b)] - C_{t-s}[a, b]| / max |K| accepted as block-circulant.
CIRCULANT_TOL = 1e-7
#: A tangent is symmetric when |K - K^T| / |K| is below this (as `fem.stability`).
SYMMETRY_TOL = 1e-9


@dataclass(frozen=True)
class CyclicSymmetry:
    """The sector structure of a mesh's free dofs (module docstring): the free dofs in the order
    (sector, local dof), and the orthogonal T (rows: K's rows; columns: that order)."""

    sectors: int
    m_u: int  # displacement dofs per sector (3 per free node orbit: u_r, u_theta, u_z)
    m_p: int  # pressure dofs per sector
    T: sp.csr_matrix

    @property
    def m(self) -> int:
        return self.m_u + self.m_p

    def mode_on_free_dofs(self, phi: np.ndarray, n: int, part: str = "real") -> np.ndarray:
        """The wave Re (or Im) of omega^{n s} phi over the sectors (phi: one sector's
        displacement dofs, cylindrical frame) as a unit vector on K's rows (pressures zero)."""
        N = self.sectors
        wave = np.exp(2j * np.pi * n * np.arange(N) / N)[:, None] * phi[None, :]
        wave = wave.real if part == "real" else wave.imag
        full = np.zeros((N, self.m))
        full[:, : self.m_u] = wave
        v = self.T @ full.reshape(-1)
        norm = np.linalg.norm(v)
        return v / norm if norm > 0 else v


def _sector_images(nodes: np.ndarray, N: int, tol: float):
    """(sector of each node, its image in sector 0 (3, n), its angle)."""
    rho = np.hypot(nodes[0], nodes[1])
    theta = np.mod(np.arctan2(nodes[1], nodes[0]), 2.0 * np.pi)
    delta = 2.0 * np.pi / N
    s = np.floor((theta + tol / rho) / delta).astype(np.int64) % N
    c, si = np.cos(s * delta), np.sin(s * delta)
    image = np.stack([c * nodes[0] + si * nodes[1], -si * nodes[0] + c * nodes[1], nodes[2]])
    return s, image, theta


def _orbits(nodes: np.ndarray, N: int, tol: float) -> np.ndarray:
    """(n_orbits, N) node numbers: node_of[j, s] is the image of orbit j in sector s."""
    rho = np.hypot(nodes[0], nodes[1])
    if np.any(rho < tol):
        raise SolverInputError("nodes", f"{int(np.sum(rho < tol))} nodes lie on the axis: not handled")
    s, image, _ = _sector_images(nodes, N, tol)
    pairs = cKDTree(image.T).query_pairs(tol, output_type="ndarray")
    n = nodes.shape[1]
    graph = sp.coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    n_orb, label = connected_components(graph, directed=False)
    counts = np.bincount(label, minlength=n_orb)
    node_of = np.full((n_orb, N), -1)
    node_of[label, s] = np.arange(n)
    complete = (counts == N) & np.all(node_of >= 0, axis=1)
    if not complete.all():
        bad = int(np.sum(counts[~complete]))
        raise SolverInputError(
            "sectors",
            f"the mesh is not made of {N} identical sectors: {bad} nodes lack a rotated image "
            f"within {tol:.3g} mm",
        )
    return node_of


def cyclic_symmetry(
    nodes: np.ndarray,
    sectors: int,
    free_dofs: np.ndarray,
    n_u: int,
    pressure_vertex: np.ndarray | None = None,
    tol: float | None = None,
) -> CyclicSymmetry:
    """The sector structure of the free dofs (module docstring). nodes: (3, n_nodes) reference
    positions (displacement dof 3 node + i); pressure_vertex: the node of each pressure dof
    (dof n_u + q); free_dofs: the dofs that are K's rows, in that order."""
    N = int(sectors)
    if N < 2:
        raise SolverInputError("sectors", f"needs at least 2 sectors, got {sectors}")
    nodes = np.asarray(nodes, dtype=float)
    tol = REL_TOL * float(np.ptp(nodes, axis=1).max()) if tol is None else tol
    node_of = _orbits(nodes, N, tol)
    free_dofs = np.asarray(free_dofs)
    n_p = 0 if pressure_vertex is None else len(pressure_vertex)
    pos = np.full(n_u + n_p, -1)
    pos[free_dofs] = np.arange(free_dofs.size)
    # displacement orbits: (orbit, sector, component) -> row of K
    rows_u = pos[3 * node_of[:, :, None] + np.arange(3)]
    free_u = np.all(rows_u >= 0, axis=(1, 2))
    if np.any(~free_u & np.any(rows_u >= 0, axis=(1, 2))):
        raise SolverInputError(
            "free_dofs", "some node orbits are partly held: the boundary conditions are not cyclic"
        )
    rows_u = rows_u[free_u]
    _, _, theta = _sector_images(nodes, N, tol)
    phi = theta[node_of[free_u, 0]][:, None] + 2.0 * np.pi * np.arange(N) / N  # (orbits, N)
    rows_p = _pressure_orbits(node_of, pressure_vertex, pos[n_u:] if n_p else pos[:0])
    m_u, m_p = 3 * rows_u.shape[0], rows_p.shape[0]
    m = m_u + m_p
    if m * N != free_dofs.size:
        raise SolverInputError("free_dofs", f"{free_dofs.size} free dofs are not {N} sectors of {m}")
    sector_start = m * np.arange(N)[:, None]  # column of (sector, local) = sector_start + local
    c, s = np.cos(phi).T, np.sin(phi).T  # (N, orbits)
    j3 = 3 * np.arange(rows_u.shape[0])
    r_idx, c_idx, vals = [], [], []
    # e_r = (cos, sin, 0), e_theta = (-sin, cos, 0), e_z: T[row of (node, x_i), col of (node, e_c)] = e_c[i]
    for comp, (wx, wy, wz) in enumerate([(c, s, 0 * c), (-s, c, 0 * c), (0 * c, 0 * c, 1 + 0 * c)]):
        cols = sector_start + (j3 + comp)[None, :]
        for i, w in enumerate((wx, wy, wz)):
            keep = w != 0
            r_idx.append(rows_u[:, :, i].T[keep])
            c_idx.append(cols[keep])
            vals.append(w[keep])
    if m_p:
        r_idx.append(rows_p.T.reshape(-1))
        c_idx.append((sector_start + m_u + np.arange(m_p)[None, :]).reshape(-1))
        vals.append(np.ones(m_p * N))
    n_free = free_dofs.size
    T = sp.csr_matrix(
        (np.concatenate(vals), (np.concatenate(r_idx), np.concatenate(c_idx))), shape=(n_free, n_free)
    )
    return CyclicSymmetry(N, m_u, m_p, T)


def _pressure_orbits(node_of: np.ndarray, pressure_vertex, pos_p: np.ndarray) -> np.ndarray:
    """(orbits, N) rows of K of the free pressure dofs; the k-th pressure dof of a vertex (dof
    order) is matched with the k-th of its images."""
    if pressure_vertex is None or len(pressure_vertex) == 0:
        return np.zeros((0, node_of.shape[1]), dtype=int)
    n_nodes = int(node_of.max()) + 1
    orbit = np.full(n_nodes, -1)
    sector = np.full(n_nodes, -1)
    orbit[node_of] = np.arange(node_of.shape[0])[:, None]
    sector[node_of] = np.arange(node_of.shape[1])[None, :]
    v = np.asarray(pressure_vertex)
    order = np.argsort(v, kind="stable")
    rank = np.empty(len(v), dtype=int)
    first = np.searchsorted(v[order], v[order], side="left")
    rank[order] = np.arange(len(v)) - first
    keys = orbit[v] * (rank.max() + 1) + rank
    uniq, key_index = np.unique(keys, return_inverse=True)
    rows = np.full((len(uniq), node_of.shape[1]), -2)
    rows[key_index, sector[v]] = pos_p
    if np.any(rows == -2):
        raise SolverInputError("pressure_vertex", "the pressure dofs are not the same in every sector")
    held = rows < 0
    if np.any(held.any(axis=1) & ~held.all(axis=1)):
        raise SolverInputError("free_dofs", "some pressure orbits are partly held: not cyclic")
    return rows[~held.all(axis=1)]


@dataclass(frozen=True)
class Harmonic:
    """One harmonic block H_n: its inertia, its pressure block's, the unstable count neg(S_n) and
    the lowest eigenvalues of S_n found with their modes phi (one sector, cylindrical frame)."""

    n: int
    multiplicity: int  # 1 for n = 0 and n = N/2, else 2 (n and N - n)
    tangent: Inertia
    pressure_block: Inertia | None
    n_unstable: int
    eigenvalues: np.ndarray  # (k,) ascending
    modes: np.ndarray  # (m_u, k) complex


@dataclass(frozen=True)
class CyclicStability:
    """Per-harmonic stability of a cyclic state and its totals (module docstring)."""

    harmonics: tuple[Harmonic, ...]
    circulant_error: float
    asymmetry: float

    @property
    def n_unstable(self) -> int:
        return sum(h.multiplicity * h.n_unstable for h in self.harmonics)

    def _total(self, field: str) -> Inertia | None:
        parts = [getattr(h, field) for h in self.harmonics]
        if any(p is None for p in parts):
            return None
        w = [h.multiplicity for h in self.harmonics]
        return Inertia(
            *(
                sum(k * getattr(p, a) for k, p in zip(w, parts))
                for a in ("positive", "negative", "zero", "perturbed")
            )
        )

    @property
    def tangent(self) -> Inertia:
        return self._total("tangent")

    @property
    def pressure_block(self) -> Inertia | None:
        return self._total("pressure_block")


def harmonic_blocks(K, sym: CyclicSymmetry) -> tuple[dict[int, sp.csr_matrix], float]:
    """The blocks C_m of block row 0 of K' = T^T K T (nonzero ones only) and the largest
    difference of a stored entry of K' from its block row 0 counterpart, relative to max |K'|
    (block rows are compared one at a time, a structural entry missing in one counts too)."""
    N, m = sym.sectors, sym.m
    Kp = (sym.T.T @ sp.csr_matrix(K) @ sym.T).tocsr()
    scale = float(np.abs(Kp.data).max(initial=0.0)) or 1.0

    def shifted(s):  # block row s as (a, (t - s) mod N, b) keys and values
        R = Kp[s * m : (s + 1) * m].tocoo()
        t, b = np.divmod(R.col, m)
        return (R.row.astype(np.int64) * N + (t - s) % N) * m + b, R.data

    key0, val0 = shifted(0)
    order = np.argsort(key0)
    key0, val0 = key0[order], val0[order]
    error = 0.0
    for s in range(1, N):
        key, val = shifted(s)
        hit = np.searchsorted(key0, key).clip(max=max(key0.size - 1, 0))
        match = key0[hit] == key if key0.size else np.zeros(key.size, dtype=bool)
        ref = np.where(match, val0[hit] if key0.size else 0.0, 0.0)
        seen = np.zeros(key0.size, dtype=bool)
        seen[hit[match]] = True
        error = max(
            error, float(np.abs(val - ref).max(initial=0.0)), float(np.abs(val0[~seen]).max(initial=0.0))
        )
    row0 = sp.csr_matrix((val0, (key0 // (N * m), key0 % (N * m))), shape=(m, N * m))
    blocks = {}
    for d in range(N):
        C = row0[:, d * m : (d + 1) * m]
        if C.nnz:
            blocks[d] = C.tocsr()
    return blocks, error / scale


def harmonic_matrix(blocks: dict[int, sp.csr_matrix], n: int, N: int) -> sp.csr_matrix:
    """H_n = sum_m C_m omega^{n m} (complex, Hermitian)."""
    return sum(C * np.exp(2j * np.pi * n * d / N) for d, C in blocks.items()).tocsr()


def real_form(H, m_u: int) -> sp.csr_matrix:
    """E(H) = [[X, -Y], [Y, X]] in the order [Re u, Im u, Re p, Im p] (module docstring)."""
    X, Y = sp.csr_matrix(H.real), sp.csr_matrix(H.imag)
    E = sp.bmat([[X, -Y], [Y, X]]).tocsr()
    m = H.shape[0]
    m_p = m - m_u
    perm = np.concatenate(
        [np.arange(m_u), m + np.arange(m_u), m_u + np.arange(m_p), m + m_u + np.arange(m_p)]
    )
    return E[perm][:, perm].tocsr()


def _half(i: Inertia | None) -> Inertia | None:
    """The inertia of H from that of its real form E(H) (every count doubled)."""
    return None if i is None else Inertia(i.positive // 2, i.negative // 2, i.zero // 2, i.perturbed)


def _phase(vec: np.ndarray) -> np.ndarray:
    """Each column times the unit complex number that makes its largest entry real and positive
    (a mode of a real H_n, n = 0 or N/2, becomes a real vector)."""
    if vec.size == 0:
        return vec
    big = vec[np.argmax(np.abs(vec), axis=0), np.arange(vec.shape[1])]
    return vec * (np.abs(big) / np.where(big == 0, 1.0, big))[None, :]


def cyclic_stability(
    K, sym: CyclicSymmetry, modes: bool = True, method: str | None = None
) -> CyclicStability:
    """Inertia, unstable count and (modes=True) lowest eigenvalues per harmonic n = 0..N/2 of the
    symmetric tangent K on the free dofs of `sym` (module docstring)."""
    K = sp.csr_matrix(K)
    skew = asymmetry(K)
    if skew > SYMMETRY_TOL:
        raise SolverInputError("K", f"the tangent is not symmetric ({skew:.2e}): no energy, no inertia test")
    blocks, error = harmonic_blocks((K + K.T) * 0.5, sym)
    if error > CIRCULANT_TOL:
        raise SolverInputError(
            "K", f"the tangent is not block-circulant over the sectors ({error:.2e}): the state is not cyclic"
        )
    N, m_u = sym.sectors, sym.m_u
    out = []
    for n in range(N // 2 + 1):
        E = real_form(harmonic_matrix(blocks, n, N), m_u)
        ids = np.arange(E.shape[0])
        if modes:
            st = stability(E, ids, 2 * m_u, method=method)
            lam, vec = st.eigenvalues[::2], _phase(st.modes[:m_u, ::2] + 1j * st.modes[m_u:, ::2])
            whole, block, n2 = st.tangent, st.pressure_block, st.n_unstable
        else:
            n2, whole, block = unstable_count(E, *split_tangent(E, ids, 2 * m_u), method)
            lam, vec = np.zeros(0), np.zeros((m_u, 0), dtype=complex)
        if n2 % 2 or whole.negative % 2 or whole.positive % 2:
            raise ArithmeticError(f"harmonic {n}: the real form's inertia is not even ({whole}): round-off")
        mult = 1 if (n == 0 or 2 * n == N) else 2
        out.append(Harmonic(n, mult, _half(whole), _half(block), n2 // 2, lam, vec))
    return CyclicStability(tuple(out), error, skew)
