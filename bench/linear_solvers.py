"""Linear solvers on real Newton matrices of the Table 1 ePSA, from the default mesh up to ~170k DOFs.

For each mesh size the ePSA is solved to 20 kPa and its tangent is assembled at 40 kPa (a loaded,
large-strain state). Candidates:

- MKL PARDISO (pypardiso), the default: symbolic analysis, numeric factorisation, one solve; its
  memory is the peak PARDISO reports (iparm 15-17).
- GMRES with the block preconditioner of bench/krylov_amg.py (smoothed-aggregation AMG on the
  displacement block, pressure mass matrix / mu for the Schur complement), to 1e-8; memory is the
  tracemalloc peak of the AMG set-up and the solve (numpy arrays only: a lower bound).
  pyamg is not a dependency of the project (it did not win, docs/decisions/013-pardiso.md):
  `pip install pyamg` to run this candidate.
- scipy's SuperLU (MMD_AT_PLUS_A, SymmetricMode) on the default mesh only (the fallback; minutes
  and gigabytes beyond it).

scikit-umfpack ships no wheel (it builds against SuiteSparse headers) and is not a candidate.

    python bench/linear_solvers.py                    # default mesh (22k DOFs)
    python bench/linear_solvers.py --mesh-size 5,3.3,2.5
"""

from __future__ import annotations

import argparse
import sys
import time
import tracemalloc
from pathlib import Path

import numpy as np
from child import in_child

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parent))


def newton_matrix(mesh_size):
    """(model, K, b) of the Table 1 ePSA: converged at 20 kPa, tangent and residual at 40 kPa."""
    from softcrawl.fem.path import load_path
    from softcrawl.geometry.design import EPSADesign
    from softcrawl.studies.epsa.model import MeshSettings, build_model

    design = EPSADesign()
    model, _, _ = build_model(design, "ecoflex-00-50", MeshSettings.from_size(mesh_size, design), False)
    x = load_path(model, [(0.02, 0.0)]).steps[-1].x
    R, K = model.residual_and_tangent(x, 0.04)
    return model, K, -R[model.free_dofs]


def pardiso(K, b):
    from softcrawl.fem.linsolve import LinearSolver, _pardiso_handle

    ls = LinearSolver("pardiso")
    t = time.perf_counter()
    ls.factor(K, True)
    first = time.perf_counter() - t
    t = time.perf_counter()
    ls.factor(K, True)
    factor = time.perf_counter() - t
    t = time.perf_counter()
    x = ls.solve(b)
    solve = time.perf_counter() - t
    iparm = _pardiso_handle(-2).iparm
    memory_mb = (max(iparm[14], iparm[15] + iparm[16])) / 1024
    return x, {"analysis+factor s": first, "factor s": factor, "solve s": solve, "memory MB": memory_mb}


def amg_gmres(model, K, b):
    from krylov_amg import BlockPreconditioner

    from softcrawl.fem.krylov import gmres

    tracemalloc.start()
    t = time.perf_counter()
    M = BlockPreconditioner(model, K)
    setup = time.perf_counter() - t
    t = time.perf_counter()
    res = gmres(lambda v: K @ v, M, b, rtol=1e-8, max_iter=300)
    solve = time.perf_counter() - t
    peak = tracemalloc.get_traced_memory()[1] / 2**20
    tracemalloc.stop()
    return res.x, {
        "setup s": setup,
        "solve s": solve,
        "iterations": res.iterations,
        "converged": res.converged,
        "operator complexity": M.complexity,
        "memory MB": peak,
    }


def superlu(K, b):
    from softcrawl.fem.linsolve import LinearSolver

    ls = LinearSolver("superlu")
    t = time.perf_counter()
    ls.factor(K, True)
    x = ls.solve(b)
    return x, {"factor+solve s": time.perf_counter() - t}


def compare(mesh_size, queue):
    model, K, b = newton_matrix(mesh_size)
    out = {"DOFs": model.n_dofs, "free": K.shape[0], "nnz": K.nnz}
    x_ref, out["PARDISO"] = pardiso(K, b)
    try:
        x, out["AMG-GMRES"] = amg_gmres(model, K, b)
        out["AMG-GMRES"]["rel. diff"] = float(np.linalg.norm(x - x_ref) / np.linalg.norm(x_ref))
    except ImportError:  # pyamg is not a dependency (it lost): `pip install pyamg` to measure it
        out["AMG-GMRES"] = {"skipped": "pip install pyamg"}
    if model.n_dofs < 40_000:
        x, out["SuperLU"] = superlu(K, b)
        out["SuperLU"]["rel. diff"] = float(np.linalg.norm(x - x_ref) / np.linalg.norm(x_ref))
    queue.put(out)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mesh-size", default="5", help="comma list of element sizes (mm)")
    args = ap.parse_args(argv)
    for h in (float(v) for v in args.mesh_size.split(",")):
        out = in_child(compare, h)
        if "error" in out:
            print(f"h = {h} mm: {out['error']}")
            continue
        print(f"h = {h} mm: {out.pop('DOFs')} DOFs, {out.pop('free')} free, nnz {out.pop('nnz')}")
        for name, figures in out.items():
            text = ", ".join(
                f"{k} {v:.3g}" if isinstance(v, float) else f"{k} {v}" for k, v in figures.items()
            )
            print(f"  {name:<10} {text}")


if __name__ == "__main__":
    main()
