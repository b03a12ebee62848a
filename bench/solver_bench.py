"""Solver benchmark: softcrawl vs FElupe on the same mesh and problem, in one run.

Problem (issue 3): the 1/8 thick tube, inner radius 3 mm, outer 9 mm, half-length 50 mm,
symmetry planes x = 0, y = 0, z = 0 and u_z = 0 at z = 50 (plane strain). Neo-Hookean,
mu = 0.03 MPa, K = 1000 mu. Follower pressure 0 -> 20 kPa in 5 steps. Error: inner radius
against the plane-strain analytic solution (docs/decisions/010-verification.md).

Each solver runs in its own child process (so its peak resident memory is its own) on the same
linear tetrahedral mesh; softcrawl curves the edge midpoints onto the cylinders (`fem.structured`),
FElupe does the same radially on r = A and r = B (see bench/felupe_case.py).

    python bench/solver_bench.py            # ~20k-DOF mesh and a finer one
    python bench/solver_bench.py --quick    # ~20k only
    python bench/solver_bench.py --no-felupe

FElupe is the optional `bench` extra (pip install -e ".[bench]").
"""

from __future__ import annotations

import argparse
import os
import resource
import sys
import time
from pathlib import Path

import numpy as np
from child import in_child

from softcrawl.units import mpa_to_kpa

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

A, B, LENGTH, MU, K_OVER_MU = 3.0, 9.0, 50.0, 0.03, 1000.0
PRESSURES = tuple(np.linspace(0.004, 0.02, 5))  # MPa
MESHES = {"~20k DOF": (5, 8, 16), "finer": (7, 11, 22)}  # radial, around, along cells


def linear_mesh(cells):
    from softcrawl.fem.structured import tube_sector

    m = tube_sector(
        A, B, height=LENGTH, n_radial=cells[0], n_angle=cells[1], n_height=cells[2], quadratic=False
    )
    return m.p.T.copy(), m.t.T.copy()


def analytic_inner_radius():
    from softcrawl.fem.analytic import tube_inner_stretch

    return tube_inner_stretch(MU, PRESSURES[-1], A, B) * A


def tube_model(points, tets):
    """The softcrawl model of the benchmark tube on the given linear mesh (midside nodes curved)."""
    import skfem

    from softcrawl.fem.laws import NeoHookean
    from softcrawl.fem.model import ChamberSpec, Dirichlet, SolidModel
    from softcrawl.fem.structured import curved, tag_boundaries

    mesh = skfem.MeshTet(points.T, tets.T)
    tol = 1e-6
    r = lambda x: np.hypot(x[0], x[1])  # noqa: E731
    mesh = curved(
        tag_boundaries(
            mesh,
            {
                "inner": lambda x: np.abs(r(x) - A) < tol * A,
                "sym_x": lambda x: np.abs(x[0]) < tol,
                "sym_y": lambda x: np.abs(x[1]) < tol,
                "bottom": lambda x: np.abs(x[2]) < tol,
                "top": lambda x: np.abs(x[2] - LENGTH) < tol * LENGTH,
            },
        ),
        "cylinder",
    )
    bcs = [
        Dirichlet.symmetry("sym_x", 0),
        Dirichlet.symmetry("sym_y", 1),
        Dirichlet.symmetry("bottom", 2),
        Dirichlet.symmetry("top", 2),
    ]
    return SolidModel(
        mesh,
        NeoHookean.nearly_incompressible(MU, K_OVER_MU),
        dirichlet=bcs,
        chambers=ChamberSpec(("inner",), (1, 1, 0)),
    )


def run_softcrawl(points, tets, queue):
    from softcrawl.fem.path import load_path
    from softcrawl.fem.reference_models import mean_radius

    t0 = time.perf_counter()
    model = tube_model(points, tets)
    setup = time.perf_counter() - t0
    res = load_path(model, [(p, 0.0) for p in PRESSURES])
    s = res.stats
    queue.put(
        {
            "code": "softcrawl P2-P1",
            "dofs": model.n_dofs,
            "iterations": s.iterations,
            "factorizations": s.factorizations,
            "krylov": s.krylov_iterations,
            "wall_s": s.wall_s,
            "assembly_s": s.assembly_s,
            "solve_s": s.solve_s,
            "setup_s": setup,
            "inner_radius_mm": mean_radius(model, res.steps[-1].x, "inner") if res.steps else np.nan,
            "converged": res.converged,
            "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
        }
    )


def run_felupe(points, tets, queue):
    from felupe_case import solve_tube_felupe

    out = solve_tube_felupe(
        points, tets, inner=A, outer=B, length=LENGTH, mu=MU, k_over_mu=K_OVER_MU, pressures=PRESSURES
    )
    out = {
        "code": "FElupe",
        "dofs": out["dofs"],
        "iterations": out["newton_iterations"],
        "factorizations": out["factorizations"],
        "krylov": 0,
        "wall_s": out["wall_s"],
        "assembly_s": out.get("assembly_s", np.nan),
        "solve_s": out.get("solve_s", np.nan),
        "setup_s": np.nan,
        "inner_radius_mm": out["inner_radius_mm"],
        "converged": out["converged"],
        "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
        "notes": out.get("notes", ""),
    }
    queue.put(out)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="only the ~20k-DOF mesh")
    ap.add_argument("--no-felupe", action="store_true")
    args = ap.parse_args(argv)
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    exact = analytic_inner_radius()
    print(f"analytic inner radius at {mpa_to_kpa(PRESSURES[-1]):.0f} kPa: {exact:.6f} mm")
    header = (
        f"{'mesh':<10}{'code':<17}{'DOFs':>8}{'iters':>6}{'fact':>5}{'gmres':>6}{'s/iter':>8}{'asm %':>7}"
        f"{'solve %':>8}{'wall s':>8}{'RSS MB':>8}{'err a %':>9}"
    )
    rows = []
    for name, cells in MESHES.items():
        if args.quick and name != "~20k DOF":
            continue
        points, tets = linear_mesh(cells)
        codes = [run_softcrawl] + ([] if args.no_felupe else [run_felupe])
        for target in codes:
            r = {"code": target.__name__} | in_child(target, points, tets)
            r["mesh"] = name
            rows.append(r)
    print(header)
    for r in rows:
        if "error" in r:
            print(f"{r['mesh']:<10}{r['code']:<17} failed: {r['error']}")
            continue
        it = max(r["iterations"], 1)
        err = (r["inner_radius_mm"] - exact) / (exact - A) * 100
        print(
            f"{r['mesh']:<10}{r['code']:<17}{r['dofs']:>8}{r['iterations']:>6}{r['factorizations']:>5}"
            f"{r['krylov']:>6}{r['wall_s'] / it:>8.2f}"
            f"{100 * r['assembly_s'] / r['wall_s']:>7.0f}{100 * r['solve_s'] / r['wall_s']:>8.0f}"
            f"{r['wall_s']:>8.1f}{r['peak_rss_mb']:>8.0f}{err:>9.3f}"
        )
    for name in MESHES:
        ours = [r for r in rows if r.get("mesh") == name and r.get("code", "").startswith("softcrawl")]
        peer = [r for r in rows if r.get("mesh") == name and r.get("code") == "FElupe" and "error" not in r]
        if ours and peer and "error" not in ours[0]:
            o, p = ours[0], peer[0]
            ratio = (p["wall_s"] / max(p["iterations"], 1)) / (o["wall_s"] / max(o["iterations"], 1))
            print(
                f"{name}: FElupe / softcrawl time per Newton iteration = {ratio:.2f}x; "
                f"total wall = {p['wall_s'] / o['wall_s']:.2f}x"
            )
    print("err a %: error of the inner-radius displacement a - A against the analytic one")
    print(
        f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores "
        "(the figures are those of an idle machine only when it is about 0)"
    )


if __name__ == "__main__":
    main()
