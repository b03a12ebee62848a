"""Time pytetwild meshing of the Table 1 ePSA at the default density (no cache).

    python bench/mesh_bench.py [--repeat 2] [--edge-length L]

Prints, per run, the wall time of the whole mesh_epsa call (surface, pytetwild, tagging, snapping),
the tet count (it varies between identical pytetwild calls) and the acceptance figures.
"""

from __future__ import annotations

import argparse
import math
import os
import time


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=1)
    parser.add_argument("--edge-length", type=float, default=None)
    args = parser.parse_args()

    from softcrawl.geometry.design import EPSADesign
    from softcrawl.geometry.tagging import distance_to_surface
    from softcrawl.geometry.tetwild import mesh_epsa

    design = EPSADesign()
    print(f"cpus={os.cpu_count()} load={os.getloadavg()[0]:.2f} design={design.short_hash()}")
    for run in range(args.repeat):
        t0 = time.perf_counter()
        mesh = mesh_epsa(design, edge_length=args.edge_length, cache_dir=False)
        seconds = time.perf_counter() - t0
        lc = design.chamber_length
        vol_err = mesh.volume() / design.body_volume - 1
        wall_err = mesh.area("chamber_wall") / (2 * math.pi * design.chamber_radius * lc) - 1
        fib_err = max((x / design.helix_length - 1 for x in mesh.fiber_lengths()), key=abs)
        fib_dist = max(distance_to_surface(f, mesh.points, mesh.facets["outer"]).max() for f in mesh.fibers)
        q = mesh.quality()
        print(
            f"run {run + 1}: {seconds:.1f} s (pytetwild {mesh.meta['mesh_seconds']:.1f} s), "
            f"edge {mesh.edge_length:.3f} mm, {mesh.n_nodes} nodes, {mesh.n_tets} tets, "
            f"volume err {100 * vol_err:+.3f} %, chamber-wall area err {100 * wall_err:+.3f} %, "
            f"fiber length err {100 * fib_err:+.3f} %, fiber-surface dist {fib_dist:.4f} mm, "
            f"min quality {q['min_quality']:.3f}, min dihedral {q['min_dihedral_deg']:.1f} deg, "
            f"tags {sorted((t, len(f)) for t, f in mesh.facets.items())}, "
            f"load {os.getloadavg()[0]:.2f}"
        )


if __name__ == "__main__":
    main()
