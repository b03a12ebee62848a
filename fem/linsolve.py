"""Sparse direct solvers for the Newton systems, with a measured default.

Candidates (measured by `bench/solver_bench.py`, docs/decisions/013-pardiso.md): MKL PARDISO through
`pypardiso` (a PyPI wheel that brings MKL) and scipy's SuperLU. SuperLU is the pure-scipy
fallback; it runs with the MMD_AT_PLUS_A ordering and SymmetricMode, which suit the structurally
symmetric FE matrices (COLAMD, or no SymmetricMode, is 2x-60x slower). `default_solver()` picks
PARDISO when it imports and SuperLU otherwise; `SOFTCRAWL_SOLVER=superlu` forces the fallback.

The sparsity pattern of a model never changes (`fem.pattern`), so `LinearSolver` runs PARDISO's
symbolic analysis (ordering, ~40 % of a factorisation) once per pattern and only the numeric
factorisation per Newton step. For the non-symmetric type (11) the analysis depends on the
pattern alone (iparm 11 and 13, scaling and matching, are off), so it is kept across solvers: a
new `LinearSolver` on the same pattern (each `run_stages` call of a crawl makes one) reuses the
handle's analysis; the symmetric indefinite type (-2) scales and matches by the values of the
matrix analysed, so each solver analyses its own first matrix, as before (a reuse there would move
results, within the tolerance but not bit for bit). Solves take one or several right-hand sides
(volume control needs two per step).

A non-symmetric tangent (friction's stick and slip, in the foot and crawl models) is nearly
symmetric: its skew part lives on the contact points. `StepSolver(split=True)` (Newton's default,
`NewtonOptions.symmetric_part`) factorises its symmetric part S = (K + K^T) / 2 by PARDISO's
symmetric indefinite LDL^T (without scaling and matching, so the analysis is the pattern's and is
kept) and solves K x = b by GMRES preconditioned with S^{-1}: about half the flops and memory of
K's LU (47.9 against 91.7 GFlop on the quick crawl's 79,872 unknowns), for 1 to 3 GMRES
iterations where the skew part is small (1 where K is symmetric). When GMRES on S^{-1} would not
converge within `StepSolver.MAX_KRYLOV` iterations, K itself is factorised by LU (counted as a
fallback); a solver holds one factorisation at a time, and switching frees the other's factors,
not its analysis (docs/decisions/080-symmetric-part.md).

Symmetry is known from the load types (`fem.model.SolidModel.symmetric_tangent`), so no matrix
is tested for it per Newton step. `StepSolver` is what Newton uses: it factorises the current
tangent, or, when it measures that to be cheaper, runs GMRES on it preconditioned by the last
factorisation (`fem.krylov`): the factorisation costs ~18x a substitution on the default ePSA
mesh and ~60x at 165k DOFs, so Krylov iterations on an older factorisation save wall time when
few are enough. The number of Krylov iterations allowed is half the cost ratio of a
factorisation to an iteration (`LinearSolver.cost_ratio`, from PARDISO's flop count), at most
`StepSolver.MAX_KRYLOV`; GMRES gives up early when its rate so far cannot reach the asked
accuracy within them, and the current tangent is then factorised (the Krylov time is lost: the
rule bounds the loss to half a factorisation).
"""

from __future__ import annotations

import functools
import os
import sys
import time
import zlib
from pathlib import Path

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from softcrawl.fem.krylov import gmres

SOLVERS = ("pardiso", "superlu")

#: PARDISO reports the flops of a factorisation and the nonzeros of its factors; their ratio
#: divided by this is the measured wall-time ratio of a factorisation to a substitution (with
#: the matrix product of a Krylov iteration). Measured since the empty rows are pinned (no
#: iterative refinement in the substitutions): 645 / 35 ~ 18 on the default ePSA mesh (22k
#: DOFs, measured 17-22) and 2029 / 35 ~ 58 at h = 2.5 mm (165k DOFs, measured 64); it was 90
#: when each substitution refined twice. A ratio from counts, not from timings, keeps a solve
#: reproducible: the same run takes the same iterations on an idle and on a loaded machine.
FLOPS_PER_RATIO = 35.0


#: OpenMP spin time of MKL's threads after a parallel region (ms), unless the user sets
#: KMP_BLOCKTIME. Intel's default, 200 ms, keeps both MKL threads spinning on the 2 cores after
#: each factorisation while the assembly that follows runs: measured (default mesh, loaded
#: machine) the process used 0.08-0.11 s of CPU for an assembly right after a factorisation
#: against 0.045-0.05 s with 0; the factorisation itself took the same time
#: (docs/decisions/017-solver-pass2.md).
KMP_BLOCKTIME_MS = "0"


def _prepare_mkl() -> None:
    """Environment for MKL before pypardiso loads it: the OpenMP spin time above, and the path
    of MKL's runtime library. pypardiso looks for it by a recursive glob over the whole Python
    environment (~0.25 s per solver object, and importing pypardiso makes one) unless
    PYPARDISO_MKL_RT names it; pip installs it in <prefix>/lib. The user's settings win."""
    os.environ.setdefault("KMP_BLOCKTIME", KMP_BLOCKTIME_MS)
    if os.environ.get("PYPARDISO_MKL_RT"):
        return
    found = sorted(Path(sys.prefix, "lib").glob("libmkl_rt.so*"), key=lambda p: len(p.name))
    if found:
        os.environ["PYPARDISO_MKL_RT"] = str(found[0])


def pardiso_available() -> bool:
    _prepare_mkl()
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


@functools.lru_cache(maxsize=3)
def _pardiso_handle(mtype: int, matched: bool = True):
    """One PARDISO handle per matrix type (and, for the symmetric indefinite type, with or
    without scaling and matching) and process (creating one searches the disk for MKL)."""
    _prepare_mkl()
    import pypardiso

    ps = pypardiso.PyPardisoSolver(mtype=mtype)
    ps.set_iparm(1, 1)  # user-set iparm
    ps.set_iparm(2, 2)  # METIS nested-dissection ordering
    ps.set_iparm(18, -1)  # report the nonzeros of the factors
    ps.set_iparm(19, -1)  # and the factorisation's Mflop (`LinearSolver.cost_ratio`)
    if mtype == -2:  # symmetric indefinite
        ps.set_iparm(10, 8)  # pivot perturbation 1e-8
        if matched:  # a symmetric tangent, maybe a mixed u-p saddle point
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
        self.cost_ratio = None  # time of a factorisation / time of a substitution, if known
        self.part = False  # the factorisation held is of a matrix's symmetric part (`factor`)

    def factor(self, A: sp.csr_matrix, symmetric: bool | None = None, part: bool = False) -> None:
        """Factorise A. A symmetric matrix (`symmetric`, or when None a matrix from
        `fem.pattern.Pattern.assemble` that is symmetric to `SYMMETRY_TOL`) goes to PARDISO's
        symmetric indefinite factorisation (about half the work of LU); any other to the
        non-symmetric one. With `part`, the symmetric part (A + A^T) / 2 of a pattern's matrix is
        factorised instead (symmetric indefinite, without scaling and matching: the analysis is
        then the pattern's alone and is kept across solvers, as for LU), a preconditioner for
        GMRES on A (`StepSolver`)."""
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
        if part and pattern is None:
            raise ValueError("the symmetric part is factorised for a matrix of a fem.pattern.Pattern")
        if symmetric is None and not part:
            symmetric = pattern is not None and pattern.asymmetry(A) < SYMMETRY_TOL
        if symmetric and pattern is None:
            raise ValueError("a symmetric factorisation needs a matrix of a fem.pattern.Pattern")
        handle = (-2, not part) if (symmetric or part) else (11, True)
        M = pattern.symmetric_part_upper(A) if part else pattern.upper(A) if symmetric else A
        for other, owner in list(_OWNER.items()):
            if owner is self and other != handle:
                # one factorisation per solver: free the other handle's factors (PARDISO's phase
                # 0), not its analysis, which a return to that handle reuses where it may
                _pardiso_handle(*other).free_memory(everything=False)
                del _OWNER[other]
        ps = _pardiso_handle(*handle)
        if not M.has_sorted_indices:
            M.sort_indices()
        key = (handle, M.shape[0], M.nnz, zlib.crc32(M.indptr), zlib.crc32(M.indices))
        dummy = np.zeros(M.shape[0])
        if _OWNER.get(handle) is not self or self._analysed_pattern != key:
            if handle != (-2, True) and _ANALYSED.get(handle, (None,))[0] == key:
                # the handle holds this pattern's analysis, made by another solver: without
                # scaling and matching it depends on the pattern alone (module docstring)
                self.cost_ratio = _ANALYSED[handle][1]
            else:
                ps.free_memory(everything=True)
                ps.set_phase(11)  # symbolic analysis, once per pattern
                ps._call_pardiso(M, dummy)
                # factorisation / substitution cost, from the flop count (module docstring)
                self.cost_ratio = float(ps.iparm[18]) * 1e6 / max(float(ps.iparm[17]), 1.0) / FLOPS_PER_RATIO
                _ANALYSED[handle] = (key, self.cost_ratio)
            self._analysed_pattern = key
            _OWNER[handle] = self
        ps.set_phase(22)  # numeric factorisation
        ps._call_pardiso(M, dummy)
        self._A, self._handle = M, handle
        self.symmetric = bool(symmetric)
        self.part = part

    def holds_factor(self) -> bool:
        if self.name == "superlu":
            return self._lu is not None
        return self._A is not None and _OWNER.get(self._handle) is self

    def solve(self, b: np.ndarray) -> np.ndarray:
        if self.name == "superlu":
            return self._lu.solve(np.asarray(b, dtype=float))
        ps = _pardiso_handle(*self._handle)
        ps.set_phase(33)
        return ps._call_pardiso(self._A, np.asfortranarray(b, dtype=float))


_OWNER: dict = {}  # handle (matrix type, matched) -> the LinearSolver whose factorisation it holds
_ANALYSED: dict = {}  # handle -> (pattern key, cost ratio) of the analysis it holds


def release_factorisations() -> None:
    """Free the memory of PARDISO's process-wide handles (their factors); a solver that held
    one analyses its pattern again at its next `factor`. For a caller that factorises another
    large matrix next (`fem.stability`)."""
    for handle in set(_OWNER) | set(_ANALYSED):  # a kept analysis too (`LinearSolver.factor`)
        _pardiso_handle(*handle).free_memory(everything=True)
    for owner in _OWNER.values():
        owner._analysed_pattern, owner._A = None, None
    _OWNER.clear()
    _ANALYSED.clear()  # nothing is analysed any more: the next factor of any solver analyses


class StepSolver:
    """The linear solves of Newton's method on one model (module docstring): `solve(K, B, rtol,
    weights)` returns X with ||W (K X - B)|| <= rtol ||W B|| per column, by a factorisation of K
    (of its symmetric part, with GMRES, for a `split` non-symmetric tangent) or by GMRES
    preconditioned with the last factorisation. Counts and times everything."""

    #: A GMRES attempt costs at most this many substitutions (docs/decisions/017-solver-pass2.md).
    MAX_KRYLOV = 20
    #: The accuracy of `substitute` when the factorisation held is of the symmetric part (an
    #: exact substitution's relative residual is ~1e-12).
    SUBSTITUTE_RTOL = 1e-10

    def __init__(self, name: str | None, symmetric: bool, reuse: bool = True, split: bool = False) -> None:
        self.direct = LinearSolver(name)
        self.symmetric = symmetric
        self.reuse = reuse
        self.split = split and not symmetric and self.direct.name == "pardiso"
        self.factorizations = 0
        self.part_factorizations = 0  # of the symmetric part, among `factorizations`
        self.split_fallbacks = 0  # symmetric parts that did not precondition: K factorised after
        self.substitutions = 0
        self.krylov_iterations = 0
        self.seconds = 0.0
        self.last_factored = False  # the last solve factorised its matrix (no GMRES on an older one)
        self._factored = None  # the matrix whose factorisation (or symmetric part's) is held

    def solve(self, K, B, rtol: float, weights=None, min_krylov: int = 2) -> np.ndarray:
        """X with ||W (K X - B)|| <= rtol ||W B||. The last factorisation is tried first when
        GMRES may take at least `min_krylov` iterations within half the measured time of a
        factorisation (0: never)."""
        t0 = time.perf_counter()
        try:
            X = None
            if self.reuse and min_krylov > 0 and self.factorizations > 0:
                X = self._reused(K, B, rtol, weights, min_krylov)
            self.last_factored = X is None
            return self._factored_solve(K, B, rtol, weights) if X is None else X
        finally:
            self.seconds += time.perf_counter() - t0

    def _factored_solve(self, K, B, rtol, weights):
        """A new factorisation: of K's symmetric part with GMRES on K (`split`, module
        docstring), of K itself when that GMRES does not converge."""
        if self.split and getattr(K, "pattern", None) is not None:
            self.direct.factor(K, part=True)
            self.factorizations += 1
            self.part_factorizations += 1
            self._factored = K
            X = self._krylov(K, B, rtol, weights, self.MAX_KRYLOV)
            if X is not None:
                return X
            self.split_fallbacks += 1
        self.direct.factor(K, self.symmetric)
        self.factorizations += 1
        self._factored = K
        self.substitutions += 1
        return self.direct.solve(B)

    def substitute(self, B) -> np.ndarray:
        """K0^{-1} B with the last factorised matrix K0: one forward and back substitution, or
        GMRES on K0 to `SUBSTITUTE_RTOL` when the factorisation held is of its symmetric part."""
        t0 = time.perf_counter()
        try:
            if self.direct.part:
                X = self._krylov(self._factored, B, self.SUBSTITUTE_RTOL, None, self.MAX_KRYLOV)
                if X is not None:
                    return X
                self.split_fallbacks += 1
                self.direct.factor(self._factored, self.symmetric)
                self.factorizations += 1
            return self._substitute(B)
        finally:
            self.seconds += time.perf_counter() - t0

    def holds_factor(self) -> bool:
        """Whether the last factorisation is still in the solver (PARDISO's handle is shared by
        the solvers of a process: another solver's factorisation replaces it)."""
        return self.factorizations > 0 and self.direct.holds_factor()

    def _reused(self, K, B, rtol, weights, min_krylov):
        """GMRES per column with the last factorisation, within the time of half a
        factorisation (`LinearSolver.cost_ratio`; 2 iterations when it is unknown); None when
        that is not enough."""
        ratio = self.direct.cost_ratio
        budget = int(min(self.MAX_KRYLOV, 0.5 * ratio)) if ratio else 2
        if budget < min_krylov:
            return None
        return self._krylov(K, B, rtol, weights, budget)

    def _krylov(self, K, B, rtol, weights, budget):
        """GMRES per column of B on K, preconditioned by the factorisation held; None when a
        column does not converge within `budget` iterations."""
        columns = B.reshape(B.shape[0], -1)
        out = np.empty_like(columns)
        for j in range(columns.shape[1]):
            res = gmres(
                lambda v: K @ v,
                self._substitute,
                columns[:, j],
                rtol=rtol,
                max_iter=budget,
                weights=weights,
                abandon=True,
            )
            self.krylov_iterations += res.iterations
            if not res.converged:
                return None
            out[:, j] = res.x
        return out.reshape(B.shape)

    def _substitute(self, b):
        self.substitutions += 1
        return self.direct.solve(b)
