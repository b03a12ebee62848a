"""Time the parts of one assembly on the solver benchmark's ~19k-DOF tube (bench/solver_bench.py).

    python bench/assembly_bench.py [--repeat 7] [--state state.npy]
    SOFTCRAWL_THREADS=1 python bench/assembly_bench.py    # assembly on one thread

The state is the converged one at 4 kPa (saved to --state and reused, so runs compare on the same
x). Each part is timed best-of --repeat, round robin (the machine is shared: the minimum is
the cleanest figure), and one PARDISO symmetric factorisation + solve for scale.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parent))


def build_model():
    """The solver bench's ~19k-DOF tube (`solver_bench.tube_model`)."""
    from solver_bench import MESHES, linear_mesh, tube_model

    return tube_model(*linear_mesh(MESHES["~20k DOF"]))


def best_of(fn, repeat):
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return min(times)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--state", default=None, help="npy file of the state (created if missing)")
    args = ap.parse_args(argv)
    from softcrawl.fem.linsolve import LinearSolver
    from softcrawl.fem.path import load_path

    model = build_model()
    P = 0.004
    if args.state and os.path.exists(args.state):
        x = np.load(args.state)
    else:
        x = load_path(model, [(P, 0.0)]).steps[-1].x
        if args.state:
            np.save(args.state, x)
    print(
        f"cpus={os.cpu_count()} load={os.getloadavg()[0]:.2f} elements={model.dx.shape[0]} "
        f"dofs={model.n_dofs} SOFTCRAWL_THREADS={os.environ.get('SOFTCRAWL_THREADS', '-')}"
    )
    parts = {}
    solid, chamber = model.solid, model.chambers[0]
    stress = solid.stress(x)
    parts["solid.stress"] = lambda: solid.stress(x)
    values = model.pattern.new_values()
    blocks = model.pattern.views(values)
    parts["solid.element_residual"] = lambda: solid.element_residual(stress)
    parts["solid.element_tangent"] = lambda: solid.element_tangent(stress, blocks)
    parts["new_values"] = model.pattern.new_values
    parts["chamber.load(tangent)"] = lambda: chamber.load(x, True)
    parts["pattern scatter"] = lambda: model.pattern.assemble_values(values)

    def fresh(fn):  # forget the state remembered from the last call
        def run():
            model._memo = None
            return fn()

        return run

    parts["residual"] = fresh(lambda: model.residual(x, P))
    parts["residual_and_tangent"] = fresh(lambda: model.residual_and_tangent(x, P))
    parts["  same x as a residual"] = lambda: model.residual_and_tangent(x, P)
    R, K = model.residual_and_tangent(x, P)
    solver = LinearSolver()
    solver.factor(K)

    def solve():
        solver.factor(K)
        solver.solve(R[model.free_dofs])

    parts["factor+solve"] = solve
    best = dict.fromkeys(parts, np.inf)
    for _ in range(args.repeat):  # round robin: every part sees the same load
        for name, fn in parts.items():
            best[name] = min(best[name], best_of(fn, 1))
    for name, t in best.items():
        print(f"{name:<24}{1e3 * t:9.1f} ms")


if __name__ == "__main__":
    main()
