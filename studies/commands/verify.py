"""`softcrawl verify [--json [FILE]] [--case NAME ...]`: the solver against closed-form solutions.

Runs the verification cases of `fem.verification`, `fem.contact_verification` and
`fem.pipe_verification` on coarse meshes (about a minute and a half in all on two cores), prints
each case's error, tolerance and pass/fail (with -v each case's details), and with --json writes
them as JSON (on stdout, the table then on stderr, or into FILE). Exit code 0 when every case
passes, 1 otherwise.
"""

from __future__ import annotations

import sys
import time

# Project modules are imported inside the functions that use them: softcrawl --help stays fast.


def _cases() -> dict:
    """The solver cases (`fem.verification`) and the contact cases (`fem.contact_verification`, and
    the elbow's in `fem.pipe_verification`)."""
    from softcrawl.fem.contact_verification import CASES as CONTACT
    from softcrawl.fem.pipe_verification import CASES as PIPE
    from softcrawl.fem.verification import CASES

    return {**CASES, **CONTACT, **PIPE}


def register(subparsers) -> None:
    from softcrawl.studies.commands.options import add_json

    p = subparsers.add_parser(
        "verify", help="run the solver verification cases", description=__doc__.splitlines()[0]
    )
    add_json(p, "the results")
    # The case names are checked in run(), not by argparse's choices: listing them here would import
    # the whole solver (2 s) for every `softcrawl --help`.
    p.add_argument(
        "--case", action="append", help="run only this case (repeatable; an unknown name lists the cases)"
    )
    p.set_defaults(func=run)


def _plain(value):
    """JSON-safe copy of numpy scalars and nested containers."""
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if hasattr(value, "item"):
        return value.item()
    return value


def run(args) -> int:
    from softcrawl.console import detail
    from softcrawl.studies.commands.options import STDOUT, CommandLineError, check_json, write_json

    CASES = _cases()
    unknown = [name for name in args.case or () if name not in CASES]
    if unknown:
        raise CommandLineError("case", f"unknown case {unknown[0]!r}; valid: {', '.join(sorted(CASES))}")
    check_json(args)  # before the cases run
    # with JSON on stdout the table goes to stderr, so that stdout is the JSON alone
    table = sys.stderr if args.json == STDOUT else sys.stdout
    names = args.case or list(CASES)
    rows = []
    width = max(len(n) for n in names) + 2
    print(f"{'case':<{width}}{'error':>12}{'tolerance':>12}  result   time", file=table)
    for name in names:
        t0 = time.perf_counter()
        result = CASES[name]()
        dt = time.perf_counter() - t0
        rows.append(
            {
                "case": name,
                "error": float(result.error),
                "tolerance": result.tolerance,
                "passed": result.passed,
                "seconds": round(dt, 2),
                "details": _plain(result.details),
            }
        )
        print(
            f"{name:<{width}}{result.error:>12.3e}{result.tolerance:>12.1e}  "
            f"{'pass' if result.passed else 'FAIL':<6} {dt:6.1f} s",
            flush=True,
            file=table,
        )
        for key, value in rows[-1]["details"].items():
            detail(f"    {key} = {value}")
    if args.json:
        write_json(args.json, {"cases": rows, "all_passed": all(r["passed"] for r in rows)})
    failed = [r["case"] for r in rows if not r["passed"]]
    if failed:
        print(f"failed: {', '.join(failed)}", file=sys.stderr)
        return 1
    return 0
