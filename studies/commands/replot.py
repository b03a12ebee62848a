"""`softcrawl replot DIR`: redraw the committed study figures from their tables, computing nothing.

For every study of the registry (`studies.registry`) that draws a figure, and every run folder of
it under DIR (DIR/FOLDER/MATERIAL/, the output of `softcrawl study`), the study's own `replot`
redraws the figure from the files as they are: its tables, spec.json and stored point results. So
a change of a figure's style reaches results/ without re-running the sweeps.
"""

from __future__ import annotations

from pathlib import Path

from softcrawl.console import progress
from softcrawl.errors import InputError
from softcrawl.studies import registry
from softcrawl.studies.declaration import resolve


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "replot", help="redraw study figures from their committed tables", description=__doc__.splitlines()[0]
    )
    p.add_argument("results", nargs="?", default="results", help="results folder (default: results)")
    p.set_defaults(func=run)


def redraw(root: Path) -> list[Path]:
    """Redraw every study figure under `root`; returns what it wrote, printing each path."""
    written = []
    for study in registry.studies():
        if study.replot is None:
            continue
        for folder in study.results_folders(root, nested=True):
            for path in resolve(study.replot)(folder):
                progress(f"  {path}")
                written.append(path)
    return written


def run(args) -> int:
    root = Path(args.results)
    if not root.is_dir():
        raise InputError("results", f"{root} is not a folder")
    if not any(s.replot and s.results_folders(root, nested=True) for s in registry.studies()):
        raise InputError(
            "results", f"{root} holds no study results to redraw (softcrawl study ... --out {root})"
        )
    written = redraw(root)
    print(f"redrew {len(written)} figures under {root}")
    return 0
