"""Solver benchmark on the Table 1 ePSA: the pressure ramp of `softcrawl epsa`, step by step.

The problem is `softcrawl epsa --pressures 0:100:20 --no-vtu` (Table 1 design, Ecoflex 00-50 at
mu = 0.03 MPa, smeared winding, free top): the mesh and the model as `studies.epsa.model`
builds them and the ramp 20, 40, ..., 100 kPa through `fem.path.load_path`. Each configuration
runs in its own child process, so that its peak resident memory is its own. Printed per run:
DOFs, set-up time (mesh + model), Newton iterations (every linear system of the Newton
iterations, failed sub-steps included), factorisations, substitutions and GMRES iterations, time
per Newton iteration, the linear-solve and assembly shares of the path, the path and total wall
times, the peak RSS, and the length at 100 kPa (the result every configuration must agree on to
the solver tolerance).

    python bench/epsa_bench.py                   # default mesh (22k DOFs)
    python bench/epsa_bench.py --mesh-size 2.5   # refined: ~170k DOFs
    python bench/epsa_bench.py --compare         # + the solver settings before issue 18

Configurations: "default" (`NewtonOptions()`: tangent predictor, adaptive steps, the last
factorisation reused where that is cheaper), "no reuse" (a factorisation per Newton iteration),
"mkl spin" (the default with MKL's OpenMP threads spinning 200 ms after each parallel region,
Intel's default, against the 0 ms that `fem.linsolve` sets), and with --compare "before"
(secant predictor, no reuse: the path of issue 18's profile, with the set-up and symmetry fixes
of issue 18 in). At h = 2.5 mm run `--only default` (a "no reuse" ramp takes ~twice as long).
"""

from __future__ import annotations

import argparse
import os
import resource
import sys
import time
from pathlib import Path

from child import in_child

from softcrawl.units import kpa_to_mpa

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

PRESSURES_KPA = (20, 40, 60, 80, 100)
CONFIGS = {
    "default": {},
    "no reuse": {"reuse_factor": False},
    # MKL's own OpenMP spin time (fem.linsolve.KMP_BLOCKTIME_MS sets 0 unless the user sets it)
    "mkl spin": {"env": {"KMP_BLOCKTIME": "200"}},
    "before": {"predictor": "secant", "reuse_factor": False},
}
DEFAULT_RUN = ("default", "no reuse", "mkl spin")


def run_ramp(mesh_size, options, queue):
    options = dict(options)
    os.environ.update(options.pop("env", {}))  # before MKL is loaded
    from softcrawl.fem.path import NewtonOptions, load_path
    from softcrawl.fem.post import actuator_length
    from softcrawl.geometry.design import EPSADesign
    from softcrawl.studies.epsa.model import MeshSettings, build_model

    t0 = time.perf_counter()
    design = EPSADesign()
    mesh = "default" if mesh_size is None else MeshSettings.from_size(mesh_size, design)
    model, _, _ = build_model(design, "ecoflex-00-50", mesh, False)
    setup = time.perf_counter() - t0
    res = load_path(model, [(kpa_to_mpa(p), 0.0) for p in PRESSURES_KPA], options=NewtonOptions(**options))
    s = res.stats
    queue.put(
        {
            "dofs": model.n_dofs,
            "setup_s": setup,
            "stats": s,
            "total_s": time.perf_counter() - t0,
            "converged": res.converged,
            "message": res.message,
            "length_mm": actuator_length(model, res.steps[-1].x) if res.steps else float("nan"),
            "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
        }
    )


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mesh-size", type=float, default=None, help="element size (mm); default mesh if unset")
    ap.add_argument("--compare", action="store_true", help="also the settings before issue 18")
    ap.add_argument("--only", choices=sorted(CONFIGS), action="append", help="run only these")
    args = ap.parse_args(argv)
    names = args.only or [n for n in CONFIGS if n in DEFAULT_RUN or args.compare]
    print(
        f"Table 1 ePSA, 0-100 kPa in 20 kPa targets, mu = 0.03 MPa, mesh "
        f"{'default' if args.mesh_size is None else f'h = {args.mesh_size} mm'}; "
        f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores"
    )
    print(
        f"{'config':<10}{'DOFs':>8}{'setup':>7}{'iters':>6}{'fact':>5}{'subst':>6}{'gmres':>6}"
        f"{'s/iter':>7}{'lin %':>6}{'asm %':>6}{'path s':>7}{'total s':>8}{'RSS MB':>7}{'L100 mm':>10}"
    )
    for name in names:
        r = in_child(run_ramp, args.mesh_size, CONFIGS[name])
        if "error" in r:
            print(f"{name:<10} failed: {r['error']}")
            continue
        s = r["stats"]
        print(
            f"{name:<10}{r['dofs']:>8}{r['setup_s']:>7.1f}{s.iterations:>6}{s.factorizations:>5}"
            f"{s.substitutions:>6}{s.krylov_iterations:>6}{s.wall_s / max(s.iterations, 1):>7.2f}"
            f"{100 * s.solve_s / s.wall_s:>6.0f}{100 * s.assembly_s / s.wall_s:>6.0f}{s.wall_s:>7.1f}"
            f"{r['total_s']:>8.1f}{r['peak_rss_mb']:>7.0f}{r['length_mm']:>10.4f}"
        )
        if not r["converged"]:
            print(f"  NOT CONVERGED: {r['message']}")


if __name__ == "__main__":
    main()
