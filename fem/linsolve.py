"""Sparse direct solvers for the Newton systems, with a measured default.

Candidates (measured by `bench/solver_bench.py`, DESIGN.md section 7): MKL PARDISO through
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
    except Exception:  # pragma: no cover - depends on the machine
        return False
    return True


def default_solver() -> str:
    forced = os.environ.get("SOFTCRAWL_SOLVER")
    if forced:
        if forced not in SOLVERS:
            raise ValueError(f"SOFTCRAWL_SOLVER={forced!r} is not one of {SOLVERS}")
        return forced
    return "pardiso" if pardiso_available() else "superlu"


@functools.lru_cache(maxsize=1)
def _pardiso_handle():
    """One PARDISO handle per process: creating one searches the disk for MKL (seconds)."""
    import pypardiso

    ps = pypardiso.PyPardisoSolver(mtype=11)   # real non-symmetric (follower load, mixed u-p)
    ps.set_iparm(1, 1)                         # user-set iparm
    ps.set_iparm(2, 2)                         # METIS nested-dissection ordering
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
        A = A if sp.isspmatrix_csr(A) else sp.csr_matrix(A)
        if self.name == "superlu":
            self._lu = spla.splu(A.tocsc(), permc_spec="MMD_AT_PLUS_A",
                                 options=dict(SymmetricMode=True), diag_pivot_thresh=0.01)
            return
        ps = _pardiso_handle()
        if not A.has_sorted_indices:
            A.sort_indices()
        key = (A.shape[0], A.nnz, zlib.crc32(A.indptr), zlib.crc32(A.indices))
        dummy = np.zeros(A.shape[0])
        if _pardiso_handle.owner is not self or self._analysed_pattern != key:
            ps.free_memory(everything=True)
            ps.set_phase(11)                    # symbolic analysis, once per pattern
            ps._call_pardiso(A, dummy)
            self._analysed_pattern = key
            _pardiso_handle.owner = self
        ps.set_phase(22)                        # numeric factorisation
        ps._call_pardiso(A, dummy)
        self._A = A

    def solve(self, b: np.ndarray) -> np.ndarray:
        if self.name == "superlu":
            return self._lu.solve(np.asarray(b, dtype=float))
        ps = _pardiso_handle()
        ps.set_phase(33)
        return ps._call_pardiso(self._A, np.asfortranarray(b, dtype=float))


_pardiso_handle.owner = None


def spsolve(A, b, solver: str | None = None) -> np.ndarray:
    s = LinearSolver(solver)
    s.factor(A)
    return s.solve(b)
