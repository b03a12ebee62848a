"""One crawl cycle of the robot's two grooved feet in the 70 mm pipe, on the quick feet mesh.

Shows the crawl simulation of the public API: `sc.simulate_crawl` inserts both feet into a rigid
pipe, switches friction on and follows the "inflate" gait (all three ePSAs 0 -> 100 kPa -> 0 in a
2 s cycle); the ePSAs act through the paper's identified axial law. Prints every converged state
as it comes, then the stride and speed of each cycle beside the paper's Table 2 (18.3 mm/s forward
at 70 mm). The friction is the committed identification's (mu = 0.3 on both faces: the sourced
range's lower end, since no mu in 0.3-0.9 gives the measured resistance; docs/decisions/070-identify-feet.md).
The first cycle (from rest) strides 15.98 mm, as the quick crawl study's point at 70 mm, mu = 0.3
(results/crawl/rubber-70a-quick); record 070 says why the FE crawl falls short of the paper. The quick
crawl takes 2-4 minutes (about 140 s of CPU).

    python examples/crawl.py [CYCLES]        (CYCLES defaults to 1)
"""

import sys

import softcrawl as sc

PAPER_SPEED_MM_S = 18.3  # Table 2, 70 mm pipe, forward, 2 s cycles


def main(cycles: int) -> None:
    result = sc.simulate_crawl(70.0, gait="inflate", cycles=cycles, quick=True, progress=print)
    print(f"{result.message}; {result.n_dofs} DOFs, {result.increments} states, {result.wall_s:.0f} s")
    for c in result.cycles:
        print(
            f"cycle {c['cycle']}: stride {c['stride_mm']:.3f} mm, speed {c['speed_mm_s']:.2f} mm/s "
            f"(paper: {PAPER_SPEED_MM_S} mm/s)"
        )
    raise SystemExit(0 if result.converged else 1)


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 1)
