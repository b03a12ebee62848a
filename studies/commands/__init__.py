"""One module per `softcrawl` subcommand.

Each module defines `register(subparsers)`, which adds its parser and sets `func` to a callable
`func(args) -> int`. Modules import their heavy dependencies (pyvista, the solver) inside `func`, so
that `softcrawl --help` stays fast.
"""

#: Subcommand modules, in the order `softcrawl --help` lists them. A module that is missing
#: (work in progress on a branch) is skipped.
COMMAND_MODULES = (
    "mesh",
    "epsa",
    "verify",
    "material",
    "model",
    "robot",
    "crawl",
    "study",
    "table1",
    "calibrate",
    "replot",
    "report",
)
