"""Fig. 3's two readings at 70 mm: the conical foot (one section revolved about the robot axis) and
the lobed one (the same section revolved about each sub circle, `geometry.foot_lobed`).

    python bench/foot_readings.py                                 # the geometry of both (seconds)
    python bench/foot_readings.py --fe conical|lobed|both [--edge 4.0] [--diameter 70] [--mu 0.5]

Both feet are meshed by pytetwild at the same edge length (so the mesher is not the difference),
with straight-sided P2 elements (see `run`), and
run through the foot study's model (`studies.foot.model.run_foot`) with the quick settings of
`studies.foot.simulate` (4 insertion steps, 2 mm of drag in 2 steps each way), Shore 70A, mu on both
faces. Prints the undeformed geometry of each reading (tip outline, share of the pipe's circumference
reached, where the skirt crosses the axis) and, per foot, the normal force after insertion, F_fwd,
F_bwd, the unknowns and the wall time. The lobed FE run is long: its pytetwild mesh at 4 mm has
48,856 tets (~216k unknowns), and it did not finish on the shared machine. Record 066
(docs/decisions/066-body-geometry.md) has the figures; no input is fitted.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from softcrawl.analytic.pipe import Pipe
from softcrawl.geometry import foot_lobed as fl
from softcrawl.geometry.design import FootDesign
from softcrawl.geometry.tetwild import mesh_foot
from softcrawl.materials import get_material
from softcrawl.materials.fem_law import solid_law
from softcrawl.paper import PIPE_DIAMETERS_MM
from softcrawl.studies.foot.model import run_foot
from softcrawl.studies.foot.simulate import QUICK


def geometry_lines(foot: FootDesign) -> list[str]:
    between = float(fl.outline_radius(foot, math.pi / 3))
    shares = ", ".join(f"{D:g} mm {100 * fl.contact_share(foot, D):.1f} %" for D in PIPE_DIAMETERS_MM)
    return [
        f"conical: tip outline {2 * foot.tip_radius:g} mm all round; touches 100 % of every pipe 55-75 mm",
        f"lobed: tip outline {2 * foot.tip_radius:g} mm at the lobes, {2 * between:.2f} mm between them; "
        f"share of the circumference reached: {shares}",
        f"lobed: the skirts cross the robot axis at z = {fl.axis_crossing(foot):.2f} mm (front face)",
    ]


def run(name, mesh, foot, diameter, mu):
    law = solid_law(get_material("rubber-70a"), hyperelastic_only=True)
    t = time.perf_counter()
    # straight-sided P2 for both readings: on the lobed mesh, midside nodes moved onto the lobes'
    # cones near the ridges where two lobes meet leave facet quadrature points outside their
    # elements (the contact term cannot be built), so neither reading gets the curved faces
    m = dataclasses.replace(mesh, meta={**mesh.meta, "curved_surfaces": {}}).to_skfem(2)
    steps = {"drag": QUICK["drag"], "drag_steps": QUICK["drag_steps"], "insert_steps": QUICK["insert_steps"]}
    r = run_foot(m, law, foot, Pipe(diameter=diameter), mu_smooth=mu, mu_grooved=mu, max_wall_s=None, **steps)
    f_fwd = r.forward.peak if r.forward else float("nan")
    f_bwd = r.backward.peak if r.backward else float("nan")
    print(f"{name}: {len(mesh.tets)} tets, {r.n_dofs} unknowns, converged {r.converged} ({r.message}); "
          f"N = {r.normal_force:.2f} N, F_fwd = {f_fwd:.3f} N, F_bwd = {f_bwd:.3f} N, "
          f"ratio {r.ratio:.3f}, {time.perf_counter() - t:.0f} s", flush=True)  # fmt: skip


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--edge", type=float, default=4.0, help="pytetwild edge length, mm")
    ap.add_argument("--diameter", type=float, default=70.0, help="pipe diameter, mm")
    ap.add_argument("--mu", type=float, default=0.5, help="friction coefficient of both faces")
    ap.add_argument("--fe", choices=("conical", "lobed", "both"), help="also run the FE of a reading")
    a = ap.parse_args()
    foot = FootDesign()
    fe = f" --fe {a.fe} --edge {a.edge:g} --diameter {a.diameter:g} --mu {a.mu:g}" if a.fe else ""
    print(f"python bench/foot_readings.py{fe}")
    for line in geometry_lines(foot):
        print(line)
    if a.fe in ("conical", "both"):
        run("conical", mesh_foot(foot, edge_length=a.edge), foot, a.diameter, a.mu)
    if a.fe in ("lobed", "both"):
        run("lobed", fl.mesh_foot_lobed(foot, edge_length=a.edge), foot, a.diameter, a.mu)


if __name__ == "__main__":
    main()
