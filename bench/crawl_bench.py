"""Crawl benchmark (issue 17): the two-feet crawl in a 70 mm pipe, the extension half-cycle.

    python bench/crawl_bench.py [--quick-only] [--pipe 70] [--cycle]

By default the run is the extension (0 -> 100 kPa, 2 segments' worth of sub-steps), because the
retraction of the paper's feet at mu = 0.5 stalls in cut-backs near -6 N
(docs/decisions/054-crawl-tetwild.md); --cycle runs the whole inflate cycle (and reports where it stops).

Targets (issue 17): one gait cycle on the default settings at most 15 minutes, --quick at most 3
minutes, on an idle 2-core machine. Prints per run: DOFs, states (increments), Newton iterations,
wall time of the setup (insertion, friction on) and per cycle, the linear solves' and assembly's
seconds, and the contact terms' share of one assembly (`ContactTerm.arrays`, residual and tangent).
The feet are the revolved mesh: 48 sectors by default, 24 in --quick, which also takes 4
insertion steps instead of 8; both 4 sub-steps per schedule segment.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from bench.contact_bench import contact_share  # run with (CONTRIBUTING)


def run_case(pipe: float, whole_cycle: bool, quick: bool) -> None:
    from softcrawl.materials import get_material
    from softcrawl.materials.fem_law import solid_law
    from softcrawl.studies.crawl.mesh import QUICK_SECTORS, crawl_mesh
    from softcrawl.studies.crawl.model import CrawlSetup, build, run_crawl
    from softcrawl.studies.crawl.schedule import Schedule, preset

    setup = CrawlSetup(
        pipe_diameter=pipe,
        insert_steps=4 if quick else 8,
        steps=4,
        cycles=1,
        sectors=QUICK_SECTORS if quick else None,
    )
    extend = Schedule("extend", np.array([0.0, 1.0]), np.array([[0.0] * 3, [100.0] * 3]), "0 -> 100 kPa")
    schedule = preset("inflate") if whole_cycle else extend
    t0 = time.perf_counter()
    design, mesh = crawl_mesh(setup.mirrored, **setup.mesh_options())
    cm = build(mesh, solid_law(get_material("rubber-70a"), hyperelastic_only=True), design, setup)
    t_build = time.perf_counter() - t0
    stamps = {}

    def on_state(row, model, x):
        stamps[row["index"]] = time.perf_counter()
        stamps["x"] = x

    t0 = time.perf_counter()
    res = run_crawl(cm, schedule, on_state=on_state)
    setup_states = [s for s in res.states if s["cycle"] == 0]
    t_setup = (stamps[setup_states[-1]["index"]] - t0) if setup_states else float("nan")
    t_run = res.wall_s - t_setup
    full, contact = contact_share(cm.model, stamps["x"])
    label = "quick" if quick else "default"
    print(f"{label}: {pipe:g} mm pipe, {res.n_dofs} DOFs, mesh + model {t_build:.1f} s; {res.message}")
    print(
        f"  {res.increments} states ({len(setup_states)} setup), {res.newton_iterations} Newton iterations; "
        f"setup {t_setup:.0f} s, {schedule.name} {t_run:.0f} s (cycle target {'180' if quick else '900'} s)"
    )
    print(f"  linear solves {res.solve_s:.0f} s, assembly {res.assembly_s:.0f} s of {res.wall_s:.0f} s")
    print(f"  assembly {full:.2f} s per iteration, contact terms {contact:.2f} s ({contact / full:.1%})")
    end = res.states[-1]
    print(
        f"  last state t = {end['time_s']:.3f} s: rear {end['rear_u_mm']:+.3f} mm, "
        f"front {end['front_u_mm']:+.3f} mm"
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick-only", action="store_true")
    ap.add_argument("--pipe", type=float, default=70.0, help="pipe diameter (mm)")
    ap.add_argument("--cycle", action="store_true", help="the whole inflate cycle, not the extension")
    args = ap.parse_args()
    run_case(args.pipe, args.cycle, True)
    if not args.quick_only:
        run_case(args.pipe, args.cycle, False)


if __name__ == "__main__":
    main()
