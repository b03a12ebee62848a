"""Benchmark of the whole-robot FE model: the Table 1 robot under the paper's Fig. 11 load case.

    python bench/robot_bench.py [--mesh quick|default|fine] [--material M] [--proportional]

Sequential path (P2 = 40 and P3 = 60 kPa first, then P1 up to 100 kPa in 10 kPa targets, as the
ring study; --proportional: straight to (100, 40, 60) kPa in 5 steps). Prints the DOFs, the
Newton iterations, the model build time, the time per iteration, the share of the linear solve,
the factorisations (the Newton iterations' and the tangent predictor's, one per sub-step), the
peak RSS and the final theta, phi and tip. Targets (issue 15, idle 2-core machine): default
mesh at most 3 minutes and 4 GB.
"""

from __future__ import annotations

import argparse
import resource
import time

from softcrawl.units import kpa_to_mpa


def main() -> None:
    from softcrawl.studies.robot_fe.model import DEFAULT_MATERIAL, build_robot_model
    from softcrawl.studies.robot_fe.response import simulate_robot

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mesh", default="default")
    ap.add_argument("--material", default=DEFAULT_MATERIAL)
    ap.add_argument("--proportional", action="store_true")
    args = ap.parse_args()
    t0 = time.perf_counter()
    robot = build_robot_model(None, args.material, args.mesh)
    build_s = time.perf_counter() - t0
    if args.proportional:
        targets = [(0.02 * k, 0.008 * k, 0.012 * k) for k in range(1, 6)]
    else:
        from softcrawl.studies.robot_fe.robot_studies import LOAD_CASES_KPA

        targets = [tuple(kpa_to_mpa(p) for p in P) for P in LOAD_CASES_KPA["asymmetric"]]
    run = simulate_robot(robot, targets)
    total = time.perf_counter() - t0
    st = run.stats
    peak_gb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024**2
    last = run.states[-1]
    path = "proportional" if args.proportional else "sequential"
    print(f"robot bench: {args.mesh} mesh, {args.material}, {path}")
    print(f"  DOFs {robot.n_dofs}, model build {build_s:.1f} s")
    per_it = st.wall_s / max(st.iterations, 1)
    print(f"  Newton iterations {st.iterations}, path {st.wall_s:.1f} s, {per_it:.2f} s/it")
    share = 100 * st.solve_s / st.wall_s
    print(f"  assembly {st.assembly_s:.1f} s, linear solve {st.solve_s:.1f} s ({share:.0f} %)")
    print(
        f"  factorisations {st.factorizations} (Newton's and the predictor's tangents), "
        f"substitutions {st.substitutions}, GMRES iterations {st.krylov_iterations}"
    )
    print(f"  total {total:.1f} s, peak RSS {peak_gb:.2f} GB; {run.message}")
    print(
        f"  final P = {tuple(round(p, 2) for p in last.pressures_kpa)} kPa: theta {last.theta_deg:.2f} deg, "
        f"phi {last.phi_deg:.2f} deg (eq. 6: {last.phi_cc_deg:.2f}), "
        f"tip {tuple(round(v, 2) for v in last.tip_mm)} mm, "
        f"arc RMS {last.arc_rms_mm:.3f} mm, d_eff {last.d_eff_mm:.2f} mm, splay {last.splay_mm:.3f} mm"
    )


if __name__ == "__main__":
    main()
