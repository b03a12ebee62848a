"""`softcrawl report --out DIR`: one self-contained HTML design review from results/.

Reads the committed results (study tables and figures, Table 1, calibration, renders,
verification, convergence) and writes DIR/index.html with every image embedded, so the page opens
anywhere without a network. Computes no finite-element solution: about 8 s of CPU (15-20 s wall
on a loaded 2-core machine; docs/decisions/064-review-and-cli.md), and it prints its build time.
A section whose results are missing names the command that makes them.
"""

from __future__ import annotations

import time
from pathlib import Path

# Project modules are imported inside the functions that use them: softcrawl --help stays fast.
from softcrawl.console import progress


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "report", help="self-contained HTML design review from results/", description=__doc__.splitlines()[0]
    )
    p.add_argument("--results", default="results", help="results folder to read (default: results)")
    p.add_argument("--out", required=True, help="output folder (index.html)")
    p.set_defaults(func=run)


def run(args) -> int:
    from softcrawl.errors import InputError
    from softcrawl.studies.commands.options import output_folder
    from softcrawl.studies.review.report import build_report

    results = Path(args.results)
    if not results.is_dir():
        raise InputError("results", f"{results} is not a folder (run from the checkout, or give --results)")
    output_folder(args.out)  # before the report is built
    t0, cpu0 = time.perf_counter(), time.process_time()
    progress(f"design review from {results}:")
    path = build_report(results, Path(args.out), progress=progress)
    size = path.stat().st_size / 1e6
    wall, cpu = time.perf_counter() - t0, time.process_time() - cpu0
    print(f"wrote {path} ({size:.1f} MB) in {wall:.1f} s ({cpu:.1f} s CPU)")
    return 0
