"""`softcrawl replot DIR`: redraw the committed study figures from their tables, computing nothing.

For every study of the registry (`studies.registry`) that draws a figure, and every run folder of
it under DIR (DIR/FOLDER/MATERIAL/, the output of `softcrawl study`), the study's own `replot`
redraws the figure from the files as they are: its tables, spec.json and stored point results. So
a change of a figure's style reaches results/ without re-running the sweeps.

DIR may also be a folder inside a results folder (results/feet, results/crawl/rubber-70a-quick):
the runs under it are redrawn, found from the nearest folder above it, at most `MAX_DEPTH` levels
up, that holds study results there (a run folder is at most DIR/FOLDER/VARIANT/MATERIAL deep).
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


#: How far above DIR its results folder may be: a run folder is at most DIR/FOLDER/VARIANT/MATERIAL.
MAX_DEPTH = 3


def runs_under(path: Path) -> list[tuple]:
    """(study, run folder) of every run at or under `path` that a study redraws, found from `path`
    or the nearest of its first `MAX_DEPTH` parents that holds such runs under `path`."""
    for root in (path, *path.parents)[: MAX_DEPTH + 1]:
        found = [
            (study, folder)
            for study in registry.studies()
            if study.replot is not None
            for folder in study.results_folders(root, nested=True)
            if folder == path or path in folder.parents
        ]
        if found:
            return found
    return []


def redraw(runs: list[tuple]) -> list[Path]:
    """Redraw the figures of `runs` (`runs_under`); returns what it wrote, printing each path."""
    written = []
    for study, folder in runs:
        for figure in resolve(study.replot)(folder):
            progress(f"  {figure}")
            written.append(figure)
    return written


def run(args) -> int:
    root = Path(args.results)
    if not root.is_dir():
        raise InputError("results", f"{root} is not a folder")
    runs = runs_under(root)
    if not runs:
        raise InputError(
            "results", f"{root} holds no study results to redraw (softcrawl study ... --out {root})"
        )
    written = redraw(runs)
    print(f"redrew {len(written)} figures under {root}")
    return 0
