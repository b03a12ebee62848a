"""Recompute chosen pipe diameters of a `softcrawl study foot` folder in place, then rebuild its
tables and plot from the stored points (the study's own evaluator and the settings of its
spec.json; the other diameters keep their stored results).

    python bench/foot_rerun.py results/foot/rubber-70a 55 75 [--mesh-cache DIR]

Used for issue 16's convergence fixes (docs/decisions/040-contact-fixes.md), where a full rerun of the
five pipes did not fit the time available; the README of the folder says which points predate
which change. Prints one line per diameter (converged, ratio, wall time).
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("folder", help="the study folder (with spec.json and points/)")
    ap.add_argument("diameters", type=float, nargs="+", help="pipe diameters (mm) to recompute")
    ap.add_argument("--mesh-cache", default=None, help="pytetwild mesh cache (default FOLDER/mesh)")
    ap.add_argument("--no-vtu", action="store_true", help="write no VTU series")
    args = ap.parse_args()
    from softcrawl.studies.foot.contact_studies import evaluate_foot
    from softcrawl.studies.foot.runs import rebuild_outputs

    folder = Path(args.folder)
    settings = json.loads((folder / "spec.json").read_text())["settings"]
    settings |= {"out_dir": str(folder), "vtu_dir": None if args.no_vtu else str(folder / "vtu")}
    settings["mesh_cache"] = args.mesh_cache or str(folder / "mesh")
    for d in args.diameters:
        t0 = time.perf_counter()
        ev = evaluate_foot({"pipe_diameter": d}, {}, settings)
        ratio, wall = ev.attrs.get("ratio_bwd_fwd", float("nan")), time.perf_counter() - t0
        print(f"D = {d:g} mm: converged {ev.ok}, F_bwd / F_fwd = {ratio:.3g}, {wall:.0f} s")
        if not ev.ok:
            print(f"  {ev.message}")
    for line in rebuild_outputs("foot", folder).lines:
        print(line)


if __name__ == "__main__":
    main()
