"""The cost of a strain-stiffening law: Neo-Hookean against Yeoh (and Gent) in the same kernel.

    python bench/law_bench.py [--repeat 5]           # assembly on the ~19k-DOF tube
    python bench/law_bench.py --epsa                 # + Table 1 ePSA ramps 0-100 kPa

Assembly: best-of --repeat of `Solid.stress` and `Solid.element_tangent` at the same state (the
bench tube of bench/solver_bench.py at 4 kPa) with each law (same initial shear modulus). --epsa:
wall time of the default-mesh ramp 0:100:20 of the Table 1 ePSA with ecoflex-00-50 (Neo-Hookean)
and ecoflex-00-50-yeoh, alternating, twice each (the acceptance is Yeoh <= 1.5x Neo-Hookean).
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parent))


def best_of(fn, repeat):
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return min(times)


def assembly(repeat: int) -> None:
    from assembly_bench import build_model

    from softcrawl.fem.laws import Gent, Yeoh
    from softcrawl.fem.path import load_path
    from softcrawl.fem.solid import Solid

    model = build_model()
    x = load_path(model, [(0.004, 0.0)]).steps[-1].x
    mu, bulk = float(model.mu.max()), float(model.bulk.max())
    laws = {
        "neo-hookean": model.solid,
        "yeoh": Solid(model.space, Yeoh(c10=mu / 2, c20=mu / 20, c30=mu / 200, bulk=bulk)),
        "gent": Solid(model.space, Gent(mu=mu, jm=20.0, bulk=bulk)),
    }
    print(f"cpus={os.cpu_count()} load={os.getloadavg()[0]:.2f} dofs={model.n_dofs}")
    for name, solid in laws.items():
        stress = solid.stress(x)
        values = model.pattern.new_values()
        blocks = model.pattern.views(values)
        t_s = best_of(lambda s=solid: s.stress(x), repeat)
        t_k = best_of(lambda s=solid, st=stress, b=blocks: s.element_tangent(st, b), repeat)
        print(f"{name:<12} stress {1e3 * t_s:6.1f} ms   element_tangent {1e3 * t_k:6.1f} ms")


def epsa_ramps() -> None:
    from softcrawl.geometry.design import EPSADesign
    from softcrawl.studies.epsa.response import simulate_epsa

    for material in ("ecoflex-00-50", "ecoflex-00-50-yeoh") * 2:
        load = os.getloadavg()[0]
        t = time.perf_counter()
        curve = simulate_epsa(EPSADesign(), material=material, pressures_kpa=(20, 40, 60, 80, 100))
        print(
            f"{material:<20} {time.perf_counter() - t:7.1f} s  load {load:.1f}  "
            f"length at 100 kPa {curve.rows[-1].length_mm:.2f} mm  ({curve.material_law})"
        )


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--epsa", action="store_true")
    args = ap.parse_args(argv)
    assembly(args.repeat)
    if args.epsa:
        epsa_ramps()


if __name__ == "__main__":
    main()
