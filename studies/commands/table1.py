"""`softcrawl table1`: select the Table 1 parameters from the study outputs and compare with the paper.

    softcrawl table1 --out DIR [--results DIR] [--material M ...]

Reads DIR/chamber-radius/<material>/curves.csv and DIR/fiber-turns/<material>/curves.csv (written by
`softcrawl study`), applies the rules of studies/epsa/rules.py and writes DIR/table1.md: one section per
material (every material found, or those given with --material), one row per Table 1 parameter
(paper value, our value, rule, material, agreement and why). The foot and ring rows are pending.
"""

from __future__ import annotations

import argparse

# Project modules are imported inside the functions that use them: softcrawl --help stays fast.


def register(subparsers) -> None:
    parser = subparsers.add_parser(
        "table1", help="reproduce Table 1 from the study outputs", description=__doc__.splitlines()[0]
    )
    parser.add_argument(
        "--out",
        required=True,
        help="folder for table1.md (created if needed; by default also the study results to read)",
    )
    parser.add_argument(
        "--results", default=None, help="results folder with the study outputs (default: --out)"
    )
    parser.add_argument(
        "--material",
        action="append",
        default=None,
        help="material to report, a preset or NAME@mu=VALUE (repeatable; default: every material found)",
    )
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from pathlib import Path

    from softcrawl.materials import get_material
    from softcrawl.studies.commands.options import CommandLineError, output_folder
    from softcrawl.studies.review.table1 import find_materials, write_table1

    results = Path(args.results if args.results is not None else args.out)
    for name in args.material or ():
        get_material(name)  # an unknown material is an error naming --material
    if args.results is not None and not results.is_dir():
        raise CommandLineError("results", f"no such folder: {results}")
    output_folder(args.out)
    if not results.is_dir():
        raise CommandLineError("results", f"no such folder: {results}")
    materials = args.material or find_materials(results)
    if not materials:
        raise CommandLineError(
            "results",
            f"{results} holds no ePSA study results (softcrawl study chamber-radius ... --out {results})",
        )
    path = write_table1(results, args.out, materials)
    print(f"wrote {path} ({len(materials)} material(s): {', '.join(materials) or 'none'})")
    return 0
