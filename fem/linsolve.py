"""Sparse direct solvers for the Newton systems, with a measured default.

Candidates (measured by `bench/solver_bench.py`, docs/DESIGN.md section 7): MKL PARDISO through
`pypardiso` (a PyPI wheel that brings MKL) and scipy's SuperLU. SuperLU is the pure-scipy
fallback; it runs with the MMD_AT_PLUS_A ordering and SymmetricMode, which suit the structurally
symmetric FE matrices (COLAMD, or no SymmetricMode, is 2x-60x slower). `default_solver()` picks
PARDISO when it imports and SuperLU otherwise; `SOFTCRAWL_SOLVER=superlu` forces the fallback.

The sparsity pattern of a model never changes (`fem.pattern`), so `LinearSolver` runs PARDISO's
symbolic analysis (ordering, ~40 % of a factorisation) once per pattern and only the numeric
factorisation per Newton step. Solves take one or several right-hand sides (volume control needs
two per step).
"""

from __future__ import annotations

import functools
import os
import zlib

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

SOLVERS = ("pardiso", "superlu")


def pardiso_available() -> bool:
    try:
        import pypardiso  # noqa: F401
    except Exception:  # noqa: BLE001 - a broken MKL install fails in many ways; fall back to SuperLU
        return False
    return True


def default_solver() -> str:
    forced = os.environ.get("SOFTCRAWL_SOLVER")
    if forced:
        if forced not in SOLVERS:
            raise ValueError(f"SOFTCRAWL_SOLVER={forced!r} is not one of {SOLVERS}")
        return forced
    return "pardiso" if pardiso_available() else "superlu"


#: Relative asymmetry below which a tangent is treated as symmetric. Hyperelastic, mixed u-p,
#: fiber and closed-chamber pressure tangents are symmetric to round-off (~1e-16): the pressure
#: load P dV/du of a closed (or symmetrically cut) chamber is conservative.
SYMMETRY_TOL = 1e-11


@functools.lru_cache(maxsize=2)
def _pardiso_handle(mtype: int):
    """One PARDISO handle per matrix type and process (creating one searches the disk for MKL)."""
    import pypardiso

    ps = pypardiso.PyPardisoSolver(mtype=mtype)
    ps.set_iparm(1, 1)  # user-set iparm
    ps.set_iparm(2, 2)  # METIS nested-dissection ordering
    if mtype == -2:  # symmetric indefinite (mixed u-p saddle point)
        ps.set_iparm(10, 8)  # pivot perturbation 1e-8
        ps.set_iparm(11, 1)  # scaling and weighted matching: advised for
        ps.set_iparm(13, 1)  # saddle-point systems
    return ps


class LinearSolver:
    """`factor(A)` then `solve(b)`; b of shape (n,) or (n, k)."""

    def __init__(self, name: str | None = None):
        self.name = name or default_solver()
        if self.name not in SOLVERS:
            raise ValueError(f"unknown linear solver {self.name!r}; choose one of {SOLVERS}")
        self._A = None
        self._lu = None
        self._analysed_pattern = None

    def factor(self, A: sp.csr_matrix) -> None:
        """Factorise A. A matrix from `fem.pattern.Pattern.assemble` that is symmetric (to
        `SYMMETRY_TOL`) goes to PARDISO's symmetric indefinite factorisation (about half the
        work of LU); any other to the non-symmetric one."""
        pattern = getattr(A, "pattern", None)
        A = A if sp.isspmatrix_csr(A) else sp.csr_matrix(A)
        if self.name == "superlu":
            self._lu = spla.splu(
                A.tocsc(),
                permc_spec="MMD_AT_PLUS_A",
                options=dict(SymmetricMode=True),
                diag_pivot_thresh=0.01,
            )
            return
        symmetric = pattern is not None and pattern.asymmetry(A) < SYMMETRY_TOL
        mtype = -2 if symmetric else 11
        M = pattern.upper(A) if symmetric else A
        ps = _pardiso_handle(mtype)
        if not M.has_sorted_indices:
            M.sort_indices()
        key = (mtype, M.shape[0], M.nnz, zlib.crc32(M.indptr), zlib.crc32(M.indices))
        dummy = np.zeros(M.shape[0])
        if _OWNER.get(mtype) is not self or self._analysed_pattern != key:
            ps.free_memory(everything=True)
            ps.set_phase(11)  # symbolic analysis, once per pattern
            ps._call_pardiso(M, dummy)
            self._analysed_pattern = key
            _OWNER[mtype] = self
        ps.set_phase(22)  # numeric factorisation
        ps._call_pardiso(M, dummy)
        self._A, self._mtype = M, mtype
        self.symmetric = symmetric

    def solve(self, b: np.ndarray) -> np.ndarray:
        if self.name == "superlu":
            return self._lu.solve(np.asarray(b, dtype=float))
        ps = _pardiso_handle(self._mtype)
        ps.set_phase(33)
        return ps._call_pardiso(self._A, np.asfortranarray(b, dtype=float))


_OWNER: dict = {}  # matrix type -> the LinearSolver whose analysis the handle holds
