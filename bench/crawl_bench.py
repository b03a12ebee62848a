"""Crawl benchmark (issues 17, 31): insertion plus two full cycles, quick feet, one pipe.

    python bench/crawl_bench.py [--pipe 70] [--cycles 2] [--runs cold,warm] [--default-mesh]
                                [--linear split|lu] [--wedge 1,4] [--cache DIR]

The run is `softcrawl crawl --quick --cycles 2` (24-sector revolved feet, 81,984 DOFs, 4
insertion steps, 4 sub-steps per schedule segment, the "inflate" gait at 100 kPa in 2 s, mu 0.5 on
both faces): the frictionless insertion, friction on, then the cycles. Two runs, each in its own
child process (its peak resident memory is its own), in this order:

  cold  a new design: the insertion is computed (and written to a fresh insertion cache);
  warm  the same design again: the insertion comes from that cache (`studies.crawl.insertion`).

Printed per run: DOFs; wall time of mesh + model, of the insertion (or the cache read), of the
friction step and of each cycle, and in total; the stride of each cycle (the first, from rest, and
the second, the steady one); Newton iterations of the whole run, per phase and per sub-step of the
cycles (the load reversals show there); PARDISO's symbolic analyses, numeric factorisations and
substitutions (counted at PARDISO's phase calls); the linear solves' and assembly's seconds; the
peak RSS. The two runs' strides must agree bit for bit (the cached state is the computed one).
`--linear lu` factorises every non-symmetric tangent by LU, the path before
docs/decisions/080-symmetric-part.md (the default, "split", factorises its symmetric part and
runs GMRES); the counts of those factorisations and of the fallbacks to LU are printed.
`--wedge 1,4` (the default) runs cold and warm on the whole feet (`softcrawl crawl --quick`), then
on a quarter wedge of them (`--wedge 4`, cyclic symmetry, tied exactly: records 082, 083); each
has its own insertion cache.

Targets (issue 31, on an idle 2-core machine): cold at most 60 s, warm at most 30 s. The figures
printed under load are not those: the lead reruns this on an idle machine.
"""

from __future__ import annotations

import argparse
import os
import resource
import sys
import tempfile
import time
from pathlib import Path

from child import in_child

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))


def _count_pardiso_phases() -> dict:
    """Count PARDISO's phase calls: 11 symbolic analysis, 22 numeric factorisation, 33 solve."""
    import pypardiso

    counts = {11: 0, 22: 0, 33: 0}
    original = pypardiso.PyPardisoSolver.set_phase

    def set_phase(self, phase):
        counts[phase] = counts.get(phase, 0) + 1
        return original(self, phase)

    pypardiso.PyPardisoSolver.set_phase = set_phase
    return counts


def _record_solves() -> list:
    """The Newton iterations of every converged sub-step: the first solve's, then those of each
    augmented-Lagrangian re-solve (`fem.contact_stages._solve_augmented`)."""
    from softcrawl.fem import contact_stages

    solves = []
    original = contact_stages._solve_augmented

    def recorded(*args, **kwargs):
        out = original(*args, **kwargs)
        solves.append(tuple(int(i) for i in out[1]))
        return out

    contact_stages._solve_augmented = recorded
    return solves


def _count_symmetric_parts() -> dict:
    """Count the factorisations of a tangent's symmetric part and the fallbacks to its LU."""
    from softcrawl.fem import linsolve

    counts = {"parts": 0, "fallbacks": 0}
    original = linsolve.LinearSolver.factor

    def factor(self, A, symmetric=None, part=False):
        counts["parts"] += bool(part)
        return original(self, A, symmetric, part)

    linsolve.LinearSolver.factor = factor
    fallback = linsolve.StepSolver._factored_solve

    def factored_solve(self, *args):
        before = self.split_fallbacks
        out = fallback(self, *args)
        counts["fallbacks"] += self.split_fallbacks - before
        return out

    linsolve.StepSolver._factored_solve = factored_solve
    return counts


def run_case(pipe: float, cycles: int, quick: bool, cache: str, linear: str, copies: int, queue) -> None:
    import dataclasses

    from softcrawl.fem.linsolve import _prepare_mkl
    from softcrawl.materials import get_material
    from softcrawl.materials.fem_law import solid_law
    from softcrawl.studies.crawl import model as crawl_model
    from softcrawl.studies.crawl.insertion import InsertionCache
    from softcrawl.studies.crawl.mesh import QUICK_SECTORS, crawl_mesh
    from softcrawl.studies.crawl.model import CrawlSetup, build, run_crawl
    from softcrawl.studies.crawl.schedule import preset

    # "lu": every factorisation of the non-symmetric tangent by LU, as before record 080
    crawl_model.CRAWL_NEWTON = dataclasses.replace(crawl_model.CRAWL_NEWTON, symmetric_part=linear == "split")
    _prepare_mkl()
    counts = _count_pardiso_phases()
    parts = _count_symmetric_parts()
    solves = _record_solves()
    setup = CrawlSetup(
        pipe_diameter=pipe,
        insert_steps=4 if quick else 8,
        steps=4,
        cycles=cycles,
        sectors=QUICK_SECTORS if quick else None,
        copies=copies,
    )
    t_start = time.perf_counter()
    design, mesh = crawl_mesh(setup.mirrored, foot=setup.foot, **setup.mesh_options())
    law = solid_law(get_material(setup.material), hyperelastic_only=True)
    cm = build(mesh, law, design, setup)
    insertion = InsertionCache(cm, mesh, design, law, cache)
    t_build = time.perf_counter() - t_start
    marks = []  # (time, row) per converged state

    def on_state(row, model, x):
        marks.append((time.perf_counter(), row))

    t0 = time.perf_counter()
    res = run_crawl(cm, preset("inflate", 100.0, 2.0), on_state=on_state, insertion=insertion)
    t_end = time.perf_counter()
    # phase boundaries from the converged states: the end of the insertion, of friction on, of each cycle
    ends = {}
    for t, row in marks:
        key = row["stage"] if row["cycle"] == 0 else f"cycle {row['cycle']}"
        ends[key] = t
    bounds, last = {}, t0
    for key in ("insert", "friction", *(f"cycle {k + 1}" for k in range(cycles))):
        if key in ends:
            bounds[key] = ends[key] - last
            last = ends[key]
    newton = {}
    for row in res.states:
        key = row["stage"] if row["cycle"] == 0 else f"cycle {row['cycle']}"
        newton.setdefault(key, []).append(int(row["newton"]))
    queue.put(
        {
            "dofs": res.n_dofs,
            "message": res.message,
            "hit": bool(insertion.hit),
            "build_s": t_build,
            "run_s": t_end - t0,
            "total_s": time.perf_counter() - t_start,
            "phases_s": bounds,
            "strides": res.strides,
            "newton_total": res.newton_iterations,
            "newton": newton,
            "solves": solves,
            "analyses": counts[11],
            "factorizations": counts[22],
            "linear": linear,
            "copies": copies,
            "parts": parts["parts"],
            "fallbacks": parts["fallbacks"],
            "substitutions": counts[33],
            "solve_s": res.solve_s,
            "assembly_s": res.assembly_s,
            "peak_gb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024**2,
        }
    )


def report(name: str, r: dict) -> None:
    ph = r["phases_s"]
    insertion = "cached, read" if r["hit"] else "computed"
    feet = "whole feet" if r["copies"] == 1 else f"a 1/{r['copies']} wedge of the feet"
    print(f"{name} ({r['linear']}, {feet}): {r['dofs']} DOFs; {r['message']}; insertion {insertion}")
    print(
        f"  wall {r['total_s']:.1f} s = mesh + model {r['build_s']:.1f} s + run {r['run_s']:.1f} s: "
        + ", ".join(f"{k} {v:.1f} s" for k, v in ph.items())
    )
    strides = r["strides"]
    first = f"{strides[0]:.15g}" if strides else "-"
    steady = f"{strides[1]:.15g}" if len(strides) > 1 else "-"
    print(f"  strides: first {first} mm, steady (cycle 2) {steady} mm")
    per = "; ".join(f"{k} {sum(v)} ({' '.join(map(str, v))})" for k, v in r["newton"].items())
    print(f"  Newton iterations {r['newton_total']} (insertion's counted from the cache when read): {per}")
    solves = r.get("solves", [])
    augment = sum(sum(s[1:]) for s in solves)
    print(
        f"  of this run's {sum(sum(s) for s in solves)}, {augment} in augmented-Lagrangian re-solves; "
        "per sub-step (first+re-solves): " + " ".join("+".join(map(str, s)) for s in solves)
    )
    print(
        f"  PARDISO: {r['analyses']} symbolic analyses, {r['factorizations']} factorisations, "
        f"{r['substitutions']} substitutions ({r['parts']} factorisations of the symmetric part, "
        f"{r['fallbacks']} fallbacks to LU); linear solves {r['solve_s']:.1f} s, "
        f"assembly {r['assembly_s']:.1f} s"
    )
    print(f"  peak RSS {r['peak_gb']:.2f} GB")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--pipe", type=float, default=70.0, help="pipe diameter (mm)")
    ap.add_argument("--cycles", type=int, default=2)
    ap.add_argument("--runs", default="cold,warm", help="comma-separated: cold, warm")
    ap.add_argument("--default-mesh", action="store_true", help="48 sectors and 8 insertion steps")
    ap.add_argument("--cache", help="insertion cache folder (default: a new temporary one)")
    ap.add_argument(
        "--linear",
        default="split",
        choices=("split", "lu"),
        help="non-symmetric tangents: the symmetric part's LDL^T with GMRES (the default), or LU",
    )
    ap.add_argument("--wedge", default="1,4", help="comma-separated wedge counts (1: the whole feet)")
    args = ap.parse_args()
    runs = args.runs.split(",")
    try:
        wedges = [int(w) for w in args.wedge.split(",")]
    except ValueError:
        ap.error(f"--wedge: comma-separated integers, not {args.wedge}")
    if any(w < 1 or 24 % w or 24 // w < 2 for w in wedges):
        ap.error(f"--wedge: each must divide the quick feet's 24 sectors and leave 2, not {args.wedge}")
    if not set(runs) <= {"cold", "warm"}:
        ap.error(f"--runs: cold and/or warm, not {args.runs}")
    load = os.getloadavg()[0]
    print(f"$ python {' '.join(sys.argv)}")
    print(f"load average {load:.1f} on {os.cpu_count()} cores at the start; threads: "
          f"SOFTCRAWL_THREADS={os.environ.get('SOFTCRAWL_THREADS', '-')}, "
          f"MKL_NUM_THREADS={os.environ.get('MKL_NUM_THREADS', '-')}")  # fmt: skip
    with tempfile.TemporaryDirectory(prefix="crawl-bench-") as tmp:
        cache = args.cache or tmp
        for copies in wedges:
            for name in runs:
                result = in_child(
                    run_case, args.pipe, args.cycles, not args.default_mesh, cache, args.linear, copies
                )
                if "error" in result:
                    print(f"{name}: {result['error']}")
                    continue
                report(name, result)


if __name__ == "__main__":
    main()
