"""Linear-solver alternatives on a real Newton matrix of the robot (issue 15: the direct solve
dominates an iteration at this size, so measure the alternatives).

    python bench/robot_linear.py [--mesh quick|default]

The tangent at a converged bent state (P = (0, 20, 30) kPa) of the tied robot, mixed u-p with
per-material pressure fields (symmetric indefinite). Candidates:
  * PARDISO (the default): numeric factorisation + solve per Newton iteration (the symbolic
    analysis runs once per pattern);
  * reuse of the factorisation (modified Newton): a solve only, against the extra iterations a
    frozen tangent costs (measured here on the same step: iterations to 1e-8 with the tangent
    of the first iteration);
  * GMRES preconditioned with an incomplete LU (scipy spilu), the iterative option that needs no
    new dependency (the saddle-point matrix rules out plain CG and AMG on the whole system).
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import scipy.sparse.linalg as spla


def main() -> None:
    from softcrawl.fem.linsolve import LinearSolver
    from softcrawl.fem.path import load_path
    from softcrawl.studies.robot_fe.model import build_robot_model
    from softcrawl.studies.robot_fe.response import ROBOT_NEWTON

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mesh", default="quick")
    args = ap.parse_args()
    robot = build_robot_model(None, mesh=args.mesh)
    model = robot.model
    P = (0.0, 0.02, 0.03)
    x = load_path(model, [(P, 0.0)], options=ROBOT_NEWTON).steps[-1].x
    P2 = (0.0, 0.024, 0.036)  # the next load step from there
    R, K = model.residual_and_tangent(x, P2, 0.0)
    b = -R[model.free_dofs]
    print(f"robot linear bench: {args.mesh} mesh, {K.shape[0]} free DOFs, nnz {K.nnz}")

    ls = LinearSolver("pardiso")
    t = time.perf_counter()
    ls.factor(K)
    first = time.perf_counter() - t
    t = time.perf_counter()
    ls.factor(K)
    fac = time.perf_counter() - t
    t = time.perf_counter()
    dx = ls.solve(b)
    sol = time.perf_counter() - t
    res = np.linalg.norm(K @ dx - b) / np.linalg.norm(b)
    print(f"  PARDISO: analysis+factor {first:.2f} s, factor {fac:.2f} s, solve {sol:.3f} s")
    print(f"  (residual {res:.1e})")

    # modified Newton: the tangent of the first iteration kept for the whole step
    xi, its = x.copy(), 0
    free = model.free_dofs
    scale = np.linalg.norm(b)
    r = 1.0
    from softcrawl.fem.solid import InvertedElement

    try:
        while r >= 1e-8 and its < 40:
            xi[free] += ls.solve(-model.residual(xi, P2, 0.0)[free])
            r = np.linalg.norm(model.residual(xi, P2, 0.0)[free]) / scale
            its += 1
        print(f"  reuse of the factorisation: {its} iterations to 1e-8, solve {sol:.3f} s each")
    except InvertedElement:
        print(f"  reuse of the factorisation: diverges (an element inverts after {its} iterations)")

    t = time.perf_counter()
    try:
        ilu = spla.spilu(K.tocsc(), drop_tol=1e-5, fill_factor=20)
        t_ilu = time.perf_counter() - t
        M = spla.LinearOperator(K.shape, ilu.solve)
        count = [0]
        t = time.perf_counter()
        y, info = spla.gmres(
            K,
            b,
            M=M,
            rtol=1e-10,
            restart=200,
            maxiter=20,
            callback=lambda _: count.__setitem__(0, count[0] + 1),
        )
        t_gm = time.perf_counter() - t
        res = np.linalg.norm(K @ y - b) / np.linalg.norm(b)
        print(f"  GMRES + ILU(1e-5): ILU {t_ilu:.2f} s, GMRES {t_gm:.2f} s, {count[0]} its, info {info}")
        print(f"  (residual {res:.1e})")
    except RuntimeError as exc:  # a singular pivot in the incomplete factorisation
        print(f"  GMRES + ILU(1e-5): ILU failed after {time.perf_counter() - t:.2f} s ({exc})")


if __name__ == "__main__":
    main()
