"""The `softcrawl` command line: one subcommand per job.

Error policy: no traceback reaches a user, whatever the input.

- Bad input (an unknown option, an impossible design, an unphysical material, a number out of its
  range, an output folder that cannot be written) ends with one line on stderr that names the
  parameter, and exit code 2. Library code signals such input with a `softcrawl.errors.InputError`
  (or any `ValueError` that carries a `parameter` attribute); argparse errors are one line too.
- A signal ends with one line, "interrupted", and exit code 128 + the signal: 130 for Ctrl-C
  (SIGINT), 143 for SIGTERM (a job scheduler's stop), in every command; `softcrawl study` hands
  its running points back first, `softcrawl crawl` and `softcrawl robot` keep their last
  checkpoint (``--resume`` continues).
- A file-system error while working (a full disk, a folder removed meanwhile) is one line with the
  file and the reason, exit code 1.
- Anything else is a bug: one line saying so, naming the exception, and how to see the traceback
  (``SOFTCRAWL_DEBUG=1``), exit code 70 (EX_SOFTWARE of sysexits.h). Out of memory is reported
  the same way, with a hint to reduce the problem size.

Pressures are entered in kPa here and converted to MPa once, in the command modules.

Conventions of every command: ``softcrawl --version``; ``-q`` (no progress lines) and ``-v``
(more detail) before or after the command's name (`softcrawl.console`); one spelling per option,
dashed (``--outer-radius``, ``--mesh-size``, ``--cycle-time``), the old spellings accepted with a
one-line deprecation warning (`options.add_alias`); ``--json [FILE]``: JSON on stdout, or into
FILE (`options.add_json`).
"""

from __future__ import annotations

import argparse
import importlib
import os
import re
import signal
import sys
import threading

from softcrawl.provenance import git_commit
from softcrawl.studies.commands import COMMAND_MODULES

#: Exit codes (see the module docstring).
EXIT_INPUT, EXIT_FAILED, EXIT_INTERNAL = 2, 1, 70
#: 128 + the signal, the shell's convention: Ctrl-C (SIGINT) and SIGTERM.
EXIT_INTERRUPTED, EXIT_TERMINATED = 128 + signal.SIGINT, 128 + signal.SIGTERM
#: Set to 1 to get the full traceback of an unexpected error instead of the one-line report.
DEBUG_VARIABLE = "SOFTCRAWL_DEBUG"


class Terminated(BaseException):
    """SIGTERM, raised in the main thread like KeyboardInterrupt for SIGINT (a BaseException, so
    that no ``except Exception`` swallows it)."""


def _raise_terminated(signum: int, frame: object) -> None:
    raise Terminated()


class _terminate_as_exception:
    """SIGTERM raises `Terminated` while a command runs (main thread only; restored after)."""

    def __enter__(self) -> None:
        self._previous = None
        if threading.current_thread() is threading.main_thread():
            self._previous = signal.signal(signal.SIGTERM, _raise_terminated)

    def __exit__(self, *exc: object) -> None:
        if self._previous is not None:
            signal.signal(signal.SIGTERM, self._previous)


class _Parser(argparse.ArgumentParser):
    """argparse, but usage errors are a single line (no usage dump) with exit code 2."""

    def error(self, message: str) -> None:
        self.exit(EXIT_INPUT, f"{self.prog}: error: {' '.join(message.split())}\n")


def _add_verbosity(parser: argparse.ArgumentParser) -> None:
    """-q/--quiet and -v/--verbose on `parser` and on every subcommand below it (so that they may
    stand before or after the command's name); counted, so -vv is more than -v."""
    for flags, dest, text in (
        (("-q", "--quiet"), "quiet", "no progress lines: only results and errors"),
        (("-v", "--verbose"), "verbose", "more detail where a command has any (repeatable)"),
    ):
        parser.add_argument(*flags, action="count", dest=dest, default=argparse.SUPPRESS, help=text)
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for child in dict.fromkeys(action.choices.values()):
                _add_verbosity(child)


def verbosity(args: argparse.Namespace) -> int:
    """-1 with -q, 0 by default, the count of -v otherwise (`softcrawl.console.LEVEL`)."""
    return getattr(args, "verbose", 0) - getattr(args, "quiet", 0)


def build_parser() -> argparse.ArgumentParser:
    from softcrawl import __version__

    parser = _Parser(prog="softcrawl", description=__doc__.splitlines()[0])
    parser.add_argument("--version", action="version", version=f"softcrawl {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    for name in COMMAND_MODULES:
        try:
            module = importlib.import_module(f"softcrawl.studies.commands.{name}")
        except ModuleNotFoundError as exc:
            if exc.name == f"softcrawl.studies.commands.{name}":
                continue
            raise
        module.register(sub)
    _add_verbosity(parser)
    return parser


def _one_line(text: str, width: int = 300) -> str:
    text = " ".join(str(text).split())
    return text if len(text) <= width else text[: width - 3] + "..."


#: argparse's own test for a negative number (a value it takes as an option's argument).
_NEGATIVE_NUMBER = re.compile(r"^-\d+$|^-\d*\.\d+$")


def attach_negative_values(argv: list[str]) -> list[str]:
    """``--pressures -10,20,30`` -> ``--pressures=-10,20,30``. argparse takes a word that starts
    with '-' for an option unless it is a plain negative number, so a list or range that starts
    with a negative number got "expected one argument"; attached, the value reaches the option's
    own check, which rejects it by its range and names the option."""
    out: list[str] = []
    for word in argv:
        previous = out[-1] if out else ""
        if (
            re.match(r"^-[\d.]", word)
            and not _NEGATIVE_NUMBER.match(word)
            and previous.startswith("--")
            and "=" not in previous
            and previous != "--"
        ):
            out[-1] = f"{previous}={word}"
        else:
            out.append(word)
    return out


def _parse(argv: list[str] | None) -> argparse.Namespace | int:
    """The parsed options, or the exit code of argparse (2 for a usage error, 0 after --help and
    --version); sets the verbosity (`softcrawl.console`)."""
    from softcrawl import console

    argv = attach_negative_values(sys.argv[1:] if argv is None else list(argv))
    try:
        args = build_parser().parse_args(argv)
    except SystemExit as exc:
        return exc.code if isinstance(exc.code, int) else EXIT_INPUT
    console.set_level(verbosity(args))
    return args


def main(argv: list[str] | None = None) -> int:
    """Run one command line and return its exit code (see the module docstring); usage errors
    and --help return too, so that tests can run any command line in-process."""
    prog = "softcrawl"
    if os.environ.get(DEBUG_VARIABLE, "") not in ("", "0"):
        args = _parse(argv)
        return args if isinstance(args, int) else int(args.func(args) or 0)
    try:
        with _terminate_as_exception():
            args = _parse(argv)
            if isinstance(args, int):
                return args
            prog = f"softcrawl {args.command}"
            git_commit()  # the checkout's commit as the command starts, for every summary it writes
            return int(args.func(args) or 0)
    except KeyboardInterrupt:
        print(f"{prog}: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    except Terminated:
        print(f"{prog}: interrupted (SIGTERM)", file=sys.stderr)
        return EXIT_TERMINATED
    except ValueError as exc:
        parameter = getattr(exc, "parameter", None)
        if parameter is None:
            return _internal(prog, exc)
        print(_one_line(f"{prog}: error: {exc}"), file=sys.stderr)
        return EXIT_INPUT
    except MemoryError:
        print(
            f"{prog}: internal error: out of memory; reduce the problem size (mesh, pressures, "
            f"samples), or set {DEBUG_VARIABLE}=1 for the traceback",
            file=sys.stderr,
        )
        return EXIT_INTERNAL
    except BrokenPipeError:  # e.g. `softcrawl material list | head -1`
        _silence_stdout()
        return 0
    except OSError as exc:
        where = f" {exc.filename}" if exc.filename else ""
        print(_one_line(f"{prog}: error:{where}: {exc.strerror or exc}"), file=sys.stderr)
        return EXIT_FAILED
    except Exception as exc:  # noqa: BLE001 - the documented last resort: one line, not a traceback
        return _internal(prog, exc)


def _internal(prog: str, exc: BaseException) -> int:
    print(
        _one_line(
            f"{prog}: internal error ({type(exc).__name__}: {exc}); please report it; "
            f"{DEBUG_VARIABLE}=1 shows the traceback"
        ),
        file=sys.stderr,
    )
    return EXIT_INTERNAL


def _silence_stdout() -> None:
    """After a broken pipe, point stdout at /dev/null so that the interpreter's final flush does
    not raise again (Python's documented idiom)."""
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, sys.stdout.fileno())


if __name__ == "__main__":
    raise SystemExit(main())
