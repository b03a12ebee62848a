r"""Where the ePSA's volumetric constraint holds: |J - 1 - p/K| under mesh refinement.

The mixed P2-P1 body enforces J - 1 = p/K only weakly (orthogonal to the P1 pressures), so the
pointwise error e = |J - 1 - p/K| at the quadrature points measures how far a point's volume change
(and with it the hydrostatic stress, K e) is from what the pressure field says. For each element
size h this records, at each pressure: max e, the volume average, the volume fraction with
e > `TRUST_LEVEL`, and where the worst elements sit (reference radius and height of the element
centroid, its distance from the chamber's re-entrant end corners, where the sharp 90-degree corner
of the cavity makes the strain singular) and the error away from those corners.

    python -m softcrawl.studies.epsa.volumetric --sizes 10,5,3.33 --out results/epsa-volumetric
"""

from __future__ import annotations

import argparse
import csv
from pathlib import Path

import numpy as np

from softcrawl.fem.path import load_path
from softcrawl.geometry.design import EPSADesign
from softcrawl.studies.epsa.model import MeshSettings, build_model
from softcrawl.units import kpa_to_mpa, mpa_to_kpa

#: A point whose |J - 1 - p/K| exceeds this has its deviatoric Cauchy stress off by more than
#: about 1 % (`fem.post.volumetric_error`): its stress is not trusted.
TRUST_LEVEL = 0.01


def volumetric_rows(design, material, sizes, pressures_kpa, fibers="sheet") -> list[dict]:
    rows = []
    for h in sizes:
        model, _, _ = build_model(design, material, MeshSettings.from_size(h, design), False, fibers=fibers)
        res = load_path(model, [(kpa_to_mpa(p), 0.0) for p in pressures_kpa])
        for step in res.steps:
            if step.past_limit:
                continue
            rows.append({"h_mm": h, "n_dofs": model.n_dofs} | _measures(model, step.x, design, step.pressure))
    return rows


def _measures(model, x, design, pressure) -> dict:
    """Over the silicone (subdomain "epsa"; the ABS seal heads are compressible and excluded)."""
    state = model.solid.stress(x)
    silicone = np.asarray(model.mesh.subdomains["epsa"])
    err = np.abs(state.J - 1.0 - state.p / model.bulk)[silicone]  # (E, Q)
    dx = model.dx[silicone]
    elem = (err * dx).sum(axis=1) / dx.sum(axis=1)
    centroid = model.mesh.p[:, model.mesh.t[:4, silicone]].mean(axis=1)  # reference centroids
    radius, z = np.hypot(centroid[0], centroid[1]), centroid[2]
    ends = model.nodes[2, model.boundary_nodes("chamber_ends")]
    corner_z = np.array([ends.min(), ends.max()])  # the chamber's two end planes
    corner = np.hypot(radius - design.chamber_radius, np.abs(z[:, None] - corner_z).min(axis=1))
    worst = np.argsort(elem)[-max(1, elem.size // 100) :]  # the worst 1 % of the elements
    bad = err > TRUST_LEVEL
    near = np.broadcast_to((corner <= CORNER_ZONE_MM)[:, None], err.shape)
    return {
        "pressure_kpa": round(mpa_to_kpa(pressure), 4),
        "max": float(err.max()),
        "volume_average": float((err * dx).sum() / dx.sum()),
        "untrusted_volume_fraction": float(dx[bad].sum() / dx.sum()),
        "untrusted_share_near_corners": float(dx[bad & near].sum() / max(dx[bad].sum(), 1e-300)),
        "max_away_from_corners": float(err[~near].max()),
        "average_away_from_corners": float((err * dx)[~near].sum() / dx[~near].sum()),
        "worst1pct_median_corner_distance_mm": float(np.median(corner[worst])),
    }


#: The zone around the chamber's re-entrant end corners (r = r0 at the chamber's end planes),
#: where the strain is singular and the error concentrates.
CORNER_ZONE_MM = 2.0


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", default="10,5,3.33")
    ap.add_argument("--pressures", default="20,40,60,80,100")
    ap.add_argument("--material", default="ecoflex-00-50@mu=0.0638")
    ap.add_argument("--out", required=True)
    args = ap.parse_args(argv)
    sizes = [float(v) for v in args.sizes.split(",")]
    pressures = [float(v) for v in args.pressures.split(",")]
    rows = volumetric_rows(EPSADesign(), args.material, sizes, pressures)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    path = out / f"volumetric-{args.material}.csv"
    with open(path, "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    print(f"-> {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
