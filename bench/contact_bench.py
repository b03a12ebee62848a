"""Contact benchmarks (issue 16): a groove-segment case, a whole-foot insertion plus a 10 mm drag,
Newton iterations per increment and the share of the contact terms in an iteration.

    python bench/contact_bench.py [--skip-foot] [--pipe 65] [--mesher revolved|tetwild] [--mesh-cache DIR]

Targets: the groove case (h = 1 mm, mu = 0.3, 100 kPa, 5 mm drag) at most 60 s, the foot
(insertion into a 65 mm pipe, 10 mm forward drag) at most 3 minutes on an idle 2-core machine.
Prints wall times, Newton iterations per increment, and per Newton iteration: the full assembly,
the contact terms' share of it (`ContactTerm.arrays`, residual and tangent), and the linear solve.
The foot is meshed as in `softcrawl study foot` (the revolved mesh, `geometry.foot_revolved`);
`--mesher tetwild` runs the pytetwild mesh of the earlier results.
"""

from __future__ import annotations

import argparse
import time

import numpy as np


def contact_share(model, x, repeat: int = 3) -> tuple[float, float]:
    """(seconds per full residual-and-tangent assembly, seconds of it in the contact terms)."""
    t0 = time.perf_counter()
    for _ in range(repeat):
        model.residual_and_tangent(x)
    full = (time.perf_counter() - t0) / repeat
    t0 = time.perf_counter()
    for _ in range(repeat):
        for term in model.contacts:
            term.arrays(x, None, True)
    return full, (time.perf_counter() - t0) / repeat


def groove_case() -> None:
    from softcrawl.materials import get_material
    from softcrawl.materials.fem_law import solid_law
    from softcrawl.studies.foot import groove_model as gm

    mat = solid_law(get_material("rubber-70a"))
    seg = gm.GrooveSegment(groove_height=1.0)
    keep = {}
    t0 = time.perf_counter()
    r = gm.run_groove(seg, mat, 0.3, on_state=lambda label, model, x, *t: keep.update(model=model, x=x))
    wall = time.perf_counter() - t0
    full, contact = contact_share(keep["model"], keep["x"])
    print(f"groove h = 1 mm, mu = 0.3: {wall:.1f} s (target 60 s), {r.n_dofs} dofs, converged {r.converged}")
    print(
        f"  Newton iterations per drag increment (first solve): mean {np.mean(r.iterations):.2f}, "
        f"max {max(r.iterations)}"
    )
    print(
        f"  assembly {full * 1e3:.1f} ms per iteration, contact terms {contact * 1e3:.1f} ms "
        f"({contact / full:.1%})"
    )
    print(f"  plateau / mu N = {r.plateau_over_mu_n:.5f}, N error vs p A = {r.normal_error:.1e}")


def foot_case(pipe: float, mesher: str, mesh_cache) -> None:
    from softcrawl.materials import get_material
    from softcrawl.materials.fem_law import solid_law
    from softcrawl.studies.foot import model as fm
    from softcrawl.studies.foot.contact_studies import _foot_mesh

    t0 = time.perf_counter()
    design, mesh = _foot_mesh({"mesher": mesher, "mesh_cache": mesh_cache})
    t_mesh = time.perf_counter() - t0
    mat = solid_law(get_material("rubber-70a"))
    model = fm.foot_model(mesh, mat, design, pipe / 2, 10.0)
    stages = fm._insert_stages(model, design, pipe / 2, 0.5, 0.5, 8)
    t0 = time.perf_counter()
    res = fm.run_stages(model, stages, options=fm.FOOT_NEWTON, max_cutbacks=fm.MAX_CUTBACKS, **fm.AUGMENT)
    snap = [(c.multiplier.copy(), c.stick.copy(), c.surface) for c in model.contacts]
    ends = (model.boundary_nodes("rim"), model.boundary_nodes("hub_top"))
    curve, drag = fm._drag(model, res.x, snap, "forward", 10.0, 10, ends)
    wall = time.perf_counter() - t0
    full, contact = contact_share(model, drag.x if drag.steps else res.x, repeat=2)
    its = [s.iterations[0] for s in res.steps + drag.steps]
    solves = res.newton_iterations + drag.newton_iterations
    print(f"foot in a {pipe:g} mm pipe, {mesher} mesh: {t_mesh:.1f} s to mesh, {model.n_dofs} dofs")
    print(
        f"  insertion + 10 mm forward drag: {wall:.1f} s (target 180 s), "
        f"converged {res.converged and drag.converged}"
    )
    print(
        f"  Newton iterations per increment (first solve): mean {np.mean(its):.2f}, max {max(its)}; "
        f"{solves} in all"
    )
    print(
        f"  linear solves {res.solve_s + drag.solve_s:.1f} s, "
        f"assembly {res.assembly_s + drag.assembly_s:.1f} s"
    )
    print(
        f"  assembly {full * 1e3:.0f} ms per iteration, contact terms {contact * 1e3:.0f} ms "
        f"({contact / full:.1%})"
    )
    print(f"  forward resistance at 10 mm: {curve.resistance[-1]:.3g} N")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--skip-foot", action="store_true")
    ap.add_argument("--pipe", type=float, default=65.0, help="pipe diameter (mm)")
    from softcrawl.geometry.foot_meshers import FOOT_MESHERS
    from softcrawl.studies.foot.contact_studies import FOOT_MESHER

    ap.add_argument("--mesher", default=FOOT_MESHER, choices=FOOT_MESHERS, help="the foot's mesh")
    ap.add_argument("--mesh-cache", default=None, help="pytetwild mesh cache folder (--mesher tetwild)")
    args = ap.parse_args()
    groove_case()
    if not args.skip_foot:
        foot_case(args.pipe, args.mesher, args.mesh_cache)


if __name__ == "__main__":
    main()
