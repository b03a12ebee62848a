"""`softcrawl replot DIR`: redraw the committed study figures from their tables, computing nothing.

For every study folder under DIR (a folder with spec.json and curves.csv or trials.csv: the
output of `softcrawl study`): NAME.png from curves.csv (chamber-radius, fiber-turns), identify.png
and identification.png from curves.csv, identification.csv and identification.json (identify),
pareto.png from trials.csv (optimise-actuator). The numbers come from the files as they are, so a
change of a figure's style reaches results/ without re-running the sweeps.
"""

from __future__ import annotations

import csv
import json
from pathlib import Path


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "replot", help="redraw study figures from their committed tables", description=__doc__.splitlines()[0]
    )
    p.add_argument("results", nargs="?", default="results", help="results folder (default: results)")
    p.set_defaults(func=run)


def _rows(path: Path) -> list[dict]:
    with open(path, newline="") as handle:
        return list(csv.DictReader(handle))


def redraw_folder(folder: Path) -> list[Path]:
    """Redraw the figures of one study folder; returns what it wrote ([] if not a study folder)."""
    from softcrawl.studies.epsa.grid_studies import GRIDS, draw_study_figure
    from softcrawl.studies.epsa.identification import draw_identification, draw_identify_curves

    spec_path = folder / "spec.json"
    if not spec_path.exists():
        return []
    spec = json.loads(spec_path.read_text())
    name = next((n for n in (*GRIDS, "optimise-actuator") if spec.get("name", "").startswith(n)), None)
    settings = spec.get("settings", {})
    if name == "identify" and (folder / "curves.csv").exists():
        written = [draw_identify_curves(settings, _rows(folder / "curves.csv"), folder)]
        if (folder / "identification.csv").exists() and (folder / "identification.json").exists():
            laws = json.loads((folder / "identification.json").read_text())
            table = _rows(folder / "identification.csv")
            written.append(draw_identification(settings, table, laws, folder))
        return written
    if name in GRIDS and (folder / "curves.csv").exists():
        param = next(iter(spec["grid"]))
        return [
            draw_study_figure(
                name, param, spec.get("fixed", {}), settings, _rows(folder / "curves.csv"), folder
            )
        ]
    if name == "optimise-actuator" and (folder / "trials.csv").exists():
        from softcrawl.studies.epsa.optimiser import draw_pareto

        return [draw_pareto(settings, _rows(folder / "trials.csv"), folder)]
    return []


def run(args) -> int:
    root = Path(args.results)
    if not root.is_dir():
        from softcrawl.errors import InputError

        raise InputError("results", f"{root} is not a folder")
    written = []
    for spec in sorted(root.rglob("spec.json")):
        for path in redraw_folder(spec.parent):
            print(f"  {path}", flush=True)
            written.append(path)
    print(f"redrew {len(written)} figures under {root}")
    return 0
