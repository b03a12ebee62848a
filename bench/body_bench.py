"""The one FE body (issue 34, step 1): its size, one tangent, one Newton step, and the insertion.

    python bench/body_bench.py [--mesh quick|default] [--insert] [--pipe 70] [--insert-steps 8]
                               [--cycles N] [--pressure 100] [--steps 4] [--mu 0.5] [--wedge 1|3]

Printed: the mesh (vertices, tets, skirt sectors), the DOFs, the three-fold asymmetry of the P2
nodes, the mass per part against the prototype's 70.2 g; the wall time of building the model; one
residual-and-tangent assembly (s, nonzeros); one Newton load step at 10 kPa in every chamber with
the wall clear of the skirts (iterations, factorisations, assembly and linear seconds); with
`--insert`, the body put into the straight pipe (`studies.crawl_fe.pipe.into_pipe`: frictionless
insertion, holds stiff; friction on, holds softened) with each foot's wall force and the holds'
forces after each phase; with `--cycles N` (implies `--insert`), N cycles of the "inflate" gait
(all three chambers 0 -> PRESSURE -> 0 kPa in 2 s, `studies.crawl_fe.cycle`) with each segment's
foot positions, lateral drift, wall forces, holds and Newton iterations, the stride of each cycle
and its wall time; the peak RSS at the end. `--wedge 3`: one wedge of 120 deg of the body, tied by
its three-fold symmetry (`studies.crawl_fe.wedge`; the mesh, DOFs and nonzeros printed are the
wedge's, the masses, forces and positions the whole body's).
Nothing is asserted (bench/, CONTRIBUTING.md).
Run it on an idle machine with SOFTCRAWL_THREADS=1 for the record's figures
(docs/decisions/076-one-body.md).
"""

from __future__ import annotations

import argparse
import resource
import sys
import time

import numpy as np

from softcrawl.fem.newton import NewtonSolver
from softcrawl.geometry.body_mesh import rotation_defect
from softcrawl.studies.crawl.model import CrawlSetup
from softcrawl.studies.crawl.schedule import preset
from softcrawl.studies.crawl_fe.cycle import crawl_cycles
from softcrawl.studies.crawl_fe.mass import mass_summary
from softcrawl.studies.crawl_fe.model import BODY_NEWTON, build_body
from softcrawl.studies.crawl_fe.pipe import into_pipe
from softcrawl.units import kpa_to_mpa


def _peak_gb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024**2


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mesh", default="quick", choices=("quick", "default"))
    ap.add_argument("--insert", action="store_true")
    ap.add_argument("--pipe", type=float, default=70.0)
    ap.add_argument("--insert-steps", type=int, default=8)
    ap.add_argument("--cycles", type=int, default=0, help="gait cycles after the insertion")
    ap.add_argument("--pressure", type=float, default=100.0, help="the gait's pressure (kPa)")
    ap.add_argument("--steps", type=int, default=4, help="sub-steps per schedule segment")
    ap.add_argument("--mu", type=float, default=0.5, help="friction of both faces (CrawlSetup's 0.5)")
    ap.add_argument("--wedge", type=int, default=1, choices=(1, 3), help="3: one wedge of 120 deg")
    args = ap.parse_args(argv)
    t0 = time.perf_counter()
    if args.cycles < 0:
        ap.error(f"--cycles: a number of cycles >= 0, not {args.cycles}")
    if not 0.0 <= args.mu <= 5.0:
        ap.error(f"--mu: a friction coefficient in [0, 5], not {args.mu}")
    setup = CrawlSetup(pipe_diameter=args.pipe, mu_smooth=args.mu, mu_grooved=args.mu, copies=args.wedge)
    bm = build_body(setup, args.mesh)
    m, tm = bm.model, bm.mesh
    print(f"mesh {args.mesh}: {tm.n_nodes} vertices, {tm.n_tets} tets, {bm.settings.sectors} skirt sectors")
    print(f"DOFs {m.n_dofs} (u {m.n_u}, p {m.n_p}); built in {time.perf_counter() - t0:.1f} s")
    if bm.copies == 1:  # a wedge's cuts are tied node for node (`studies.crawl_fe.wedge`)
        print(f"asymmetry (P2 nodes, 120 deg): {rotation_defect(np.asarray(m.nodes).T, 120.0):.2e} mm")
    s = mass_summary(bm.design, m.mesh, bm.materials, bm.copies)
    for part, p in s["parts"].items():
        print(f"  {part:10s} {p['material']:26s} {p['volume_mm3']:10.1f} mm^3 {p['mass_g']:8.2f} g")
    print(f"mass {s['total_g']:.2f} g (+ winding {s['winding_g']:.2f} g) against {s['prototype_g']} g")
    x = m.initial_state()
    P = np.asarray(bm.pressures([kpa_to_mpa(10.0)] * 3))
    t = time.perf_counter()
    _, K = m.residual_and_tangent(x, P, 0.0)
    print(f"one tangent: {time.perf_counter() - t:.2f} s, {K.nnz} nonzeros", flush=True)
    solver = NewtonSolver(m, BODY_NEWTON)
    t = time.perf_counter()
    _, rec = solver.load_step(x, P, 0.0)
    st = solver.stats(t)
    print(
        f"one load step (10 kPa, wall clear): {rec.iterations} iterations, "
        f"{st.factorizations} factorisations, assembly {st.assembly_s:.1f} s, linear {st.solve_s:.1f} s, "
        f"wall {st.wall_s:.1f} s; peak {_peak_gb():.2f} GB",
        flush=True,
    )
    if args.insert or args.cycles:
        run = into_pipe(bm, insert_steps=args.insert_steps)
        print(
            f"into the {args.pipe:g} mm pipe: {run.message}; {run.newton_iterations} Newton iterations, "
            f"assembly {run.assembly_s:.0f} s, linear {run.solve_s:.0f} s, wall {run.wall_s:.0f} s"
        )
        for state in run.states:
            holds = max(abs(v) for v in state.holds.values())
            normal = ", ".join(f"{k} {v:.2f} N" for k, v in state.normal.items())
            print(f"  after {state.phase}: wall normal force {normal}; largest hold force {holds:.3g} N")
        if args.cycles and run.converged:
            gait = preset("inflate", args.pressure, 2.0)
            crawl = crawl_cycles(bm, run.states[-1].x, gait, cycles=args.cycles, steps=args.steps)
            print(
                f"{args.cycles} cycle(s) of {gait.name} at {args.pressure:g} kPa: {crawl.message}; "
                f"{crawl.newton_iterations} Newton iterations, assembly {crawl.assembly_s:.0f} s, "
                f"linear {crawl.solve_s:.0f} s, wall {crawl.wall_s:.0f} s",
                flush=True,
            )
            for st in crawl.states:
                print(
                    f"  cycle {st.cycle} t {st.t:.2f} s P {st.pressures_kpa[0]:g} kPa: "
                    f"rear z {st.z['rear']:+.3f}, "
                    f"front z {st.z['front']:+.3f} mm, drift ({st.drift[0]:+.2e}, {st.drift[1]:+.2e}) mm; "
                    f"normal {st.normal['rear']:.2f} / {st.normal['front']:.2f} N, axial friction "
                    f"{st.friction_z['rear']:+.2f} / {st.friction_z['front']:+.2f} N; "
                    f"holds {st.holds_max:.2g} N; "
                    f"{st.newton} Newton"
                )
            print("  strides: " + ", ".join(f"{v:.4f} mm" for v in crawl.strides))
    print(f"peak RSS {_peak_gb():.2f} GB")
    return 0


if __name__ == "__main__":
    sys.exit(main())
