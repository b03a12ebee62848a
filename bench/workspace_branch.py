"""The workspace's most bent point, (100, 0, 100) kPa, reached along two paths (record 084).

    python bench/workspace_branch.py [--mesh default|quick]

Path A is the workspace's: proportional from zero (its targets, 10 kPa apart). Path B passes through
(100, 25, 100) kPa first and then lowers P2 to 0, the path a warm start from that neighbouring
grid point would take. Printed for each end state: theta, the end point, the Newton iterations,
and the number of unstable modes of the tangent (`fem.stability.unstable_count`: neg(K) -
neg(K_pp), the mixed pressure block's negative pivots taken off). An elastic body has one state
per load only where it is stable; two paths may end on different equilibria, and the study must
report the one the robot pressurised from rest reaches.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from softcrawl.fem.stability import split_tangent, unstable_count
from softcrawl.studies.robot_fe.model import build_robot_model
from softcrawl.studies.robot_fe.response import simulate_robot
from softcrawl.studies.robot_fe.workspace import path_targets
from softcrawl.units import kpa_to_mpa

MATERIAL = "ecoflex-00-50@mu=0.0638"


def unstable_modes(robot, x, pressures_kpa) -> int:
    m = robot.model
    _, K = m.residual_and_tangent(x, tuple(kpa_to_mpa(p) for p in pressures_kpa), 0.0)
    K = K.tocsr()
    K = ((K + K.T) * 0.5).tocsr()  # pressure loads on closed chambers: symmetric to round-off
    iu, ip = split_tangent(K, m.free_dofs, m.n_u)
    return unstable_count(K, iu, ip)[0]


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mesh", choices=("default", "quick"), default="default")
    args = ap.parse_args(argv)
    print(f"$ python bench/workspace_branch.py --mesh {args.mesh}")
    robot = build_robot_model(None, MATERIAL, args.mesh)
    zero, end = (0.0, 0.0, 0.0), (100.0, 0.0, 100.0)
    paths = {"A: from zero": [zero, end], "B: via (100, 25, 100)": [zero, (100.0, 25.0, 100.0), end]}
    states = {}
    for name, points in paths.items():
        t0 = time.perf_counter()
        targets = path_targets(points)
        run = simulate_robot(robot, [tuple(kpa_to_mpa(p) for p in P) for P in targets])
        s = run.states[-1]
        n = unstable_modes(robot, run.path.steps[-1].x, s.pressures_kpa)
        states[name] = np.array(s.end_mm)
        print(f"{name}: {len(targets)} targets, {run.message}, {run.newton_iterations} Newton iterations, "
              f"{time.perf_counter() - t0:.0f} s; at {s.pressures_kpa} kPa theta {s.theta_deg:.4f} deg, "
              f"end {np.round(s.end_mm, 4).tolist()} mm, unstable modes {n}")  # fmt: skip
    a, b = states.values()
    print(f"end points {np.linalg.norm(a - b):.2e} mm apart")


if __name__ == "__main__":
    main()
