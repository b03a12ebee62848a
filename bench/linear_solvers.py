"""Linear-solver candidates on a real Newton matrix (the ~20k-DOF 1/8 tube of solver_bench).

Candidates that install from PyPI as wheels on a fresh Linux machine: MKL PARDISO (pypardiso)
and scipy's SuperLU (with the MMD_AT_PLUS_A ordering and SymmetricMode, and scipy's default
`spsolve` = SuperLU with COLAMD). scikit-umfpack ships no wheel (it builds against SuiteSparse
headers), so a fresh `pip install` cannot get it: it is not a candidate here.

    python bench/linear_solvers.py
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np
import scipy.sparse.linalg as spla

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parent))


def newton_matrix(cells=(5, 8, 16)):
    from solver_bench import K_OVER_MU, LENGTH, MU, A, B

    from fem.model import ChamberSpec, Dirichlet, SolidModel
    from fem.neohooke import NeoHookean
    from fem.structured import tube_sector

    mesh = tube_sector(A, B, height=LENGTH, n_radial=cells[0], n_angle=cells[1], n_height=cells[2])
    bcs = [
        Dirichlet.symmetry("sym_x", 0),
        Dirichlet.symmetry("sym_y", 1),
        Dirichlet.symmetry("bottom", 2),
        Dirichlet.symmetry("top", 2),
    ]
    model = SolidModel(
        mesh,
        NeoHookean.nearly_incompressible(MU, K_OVER_MU),
        dirichlet=bcs,
        chambers=ChamberSpec(("inner",), (1, 1, 0)),
    )
    R, K = model.residual_and_tangent(model.initial_state(), 0.004)
    return K, R[model.free_dofs]


def timed(fn, repeat=2):
    best, out = np.inf, None
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t)
    return best, out


def main():
    from fem.linsolve import LinearSolver, pardiso_available

    K, b = newton_matrix()
    print(f"matrix: n = {K.shape[0]}, nnz = {K.nnz}")
    results = {}
    if pardiso_available():
        ls = LinearSolver("pardiso")
        t_first, x_ref = timed(lambda: (ls.factor(K), ls.solve(b))[1], repeat=1)
        t_next, _ = timed(lambda: (ls.factor(K), ls.solve(b))[1])
        results["PARDISO (first: analysis + factor + solve)"] = (t_first, x_ref)
        results["PARDISO (next Newton step: factor + solve)"] = (t_next, x_ref)
    ls = LinearSolver("superlu")
    results["SuperLU MMD_AT_PLUS_A + SymmetricMode"] = timed(lambda: (ls.factor(K), ls.solve(b))[1])
    results["scipy spsolve (SuperLU, COLAMD)"] = timed(lambda: spla.spsolve(K.tocsc(), b), repeat=1)
    ref = next(iter(results.values()))[1]
    for name, (t, x) in results.items():
        err = np.linalg.norm(x - ref) / np.linalg.norm(ref)
        print(f"{name:<48} {t:8.2f} s   rel. diff {err:.1e}")


if __name__ == "__main__":
    main()
