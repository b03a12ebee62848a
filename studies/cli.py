"""The `softcrawl` command line: one subcommand per job.

Error policy. Bad user input (an unknown option, an impossible design, an unphysical material)
ends with one line on stderr that names the parameter, and exit code 2. Library code signals such
input by raising a `ValueError` subclass that carries a `parameter` attribute (for example
`geometry.design.DesignError`); any other exception is a bug and keeps its traceback.
Pressures are entered in kPa here and converted to MPa once, in the command modules.
"""

from __future__ import annotations

import argparse
import importlib
import sys

from studies.commands import COMMAND_MODULES


class _Parser(argparse.ArgumentParser):
    """argparse, but usage errors are a single line (no usage dump) with exit code 2."""

    def error(self, message: str) -> None:
        self.exit(2, f"{self.prog}: error: {message}\n")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="softcrawl", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    for name in COMMAND_MODULES:
        try:
            module = importlib.import_module(f"studies.commands.{name}")
        except ModuleNotFoundError as exc:
            if exc.name == f"studies.commands.{name}":
                continue
            raise
        module.register(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.func(args) or 0)
    except ValueError as exc:
        parameter = getattr(exc, "parameter", None)
        if parameter is None:
            raise
        print(f"softcrawl {args.command}: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    raise SystemExit(main())
