"""The top-level error policy of `studies.cli` (no traceback reaches a user) and the help texts."""

from __future__ import annotations

import argparse
import subprocess
import sys

import pytest

import softcrawl.studies.commands.table1 as table1_command
from softcrawl.studies import cli


def _raising(exc: BaseException):
    def run(args):
        raise exc

    return run


@pytest.mark.parametrize(
    "exc, code, words",
    [
        (KeyboardInterrupt(), 130, ["interrupted"]),
        (MemoryError(), 70, ["internal error", "out of memory", "SOFTCRAWL_DEBUG=1"]),
        (RuntimeError("a bug\nover two lines"), 70, ["internal error", "RuntimeError", "SOFTCRAWL_DEBUG=1"]),
        (ValueError("no parameter named"), 70, ["internal error", "ValueError"]),
        (OSError(28, "No space left on device", "out/table1.md"), 1, ["No space left", "out/table1.md"]),
    ],
)
def test_unexpected_errors_are_one_line(monkeypatch, capfd, tmp_path, exc, code, words):
    monkeypatch.delenv("SOFTCRAWL_DEBUG", raising=False)
    monkeypatch.setattr(table1_command, "run", _raising(exc))
    assert cli.main(["table1", "--out", str(tmp_path)]) == code
    out, err = capfd.readouterr()
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert err.startswith("softcrawl table1: ")
    for word in words:
        assert word in err


def test_debug_variable_shows_the_traceback(monkeypatch, tmp_path):
    monkeypatch.setenv("SOFTCRAWL_DEBUG", "1")
    monkeypatch.setattr(table1_command, "run", _raising(RuntimeError("a bug")))
    with pytest.raises(RuntimeError, match="a bug"):
        cli.main(["table1", "--out", str(tmp_path)])


def test_help_returns_0(capsys):
    assert cli.main(["model", "plan", "--help"]) == 0
    assert "--step" in capsys.readouterr().out


def test_console_command_bad_input_is_one_line(tmp_path):
    """The installed entry point: exit code 2 and one line, in a fresh interpreter."""
    result = subprocess.run(
        [
            sys.executable,
            "-m",
            "softcrawl",
            "model",
            "plan",
            "--pipe",
            "straight",
            "--step",
            "0",
            "--out",
            str(tmp_path),
        ],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert result.returncode == 2 and result.stdout == ""
    assert len(result.stderr.strip().splitlines()) == 1 and "--step" in result.stderr


def _parsers(parser: argparse.ArgumentParser, prefix: str = "softcrawl"):
    yield prefix, parser
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                yield from _parsers(sub, f"{prefix} {name}")


def test_every_option_has_a_complete_help_text():
    """Every option says what it is; no help names an internal module constant; numbers give a
    unit or a default; the descriptions end with a full stop or a closing bracket, not mid-sentence."""
    problems = []
    for name, parser in _parsers(cli.build_parser()):
        if parser.description and not parser.description.rstrip().endswith((".", ")", "`")):
            problems.append(f"{name}: description ends mid-sentence: {parser.description[-40:]!r}")
        for action in parser._actions:
            if (
                isinstance(action, (argparse._HelpAction, argparse._SubParsersAction))
                or not action.option_strings
                or action.help == argparse.SUPPRESS  # a deprecated spelling (options.add_alias)
            ):
                continue
            text = action.help or ""
            flag = action.option_strings[-1]
            if not text.strip():
                problems.append(f"{name} {flag}: no help")
            if "studies." in text and "simulate_epsa" not in text:
                problems.append(f"{name} {flag}: help names a module: {text}")
            if action.type in (int, float) or getattr(action.type, "__name__", "") in ("number", "integer"):
                if "default" not in text and "Table 1" not in text and not action.required:
                    problems.append(f"{name} {flag}: number without a default in its help: {text}")
    assert not problems, "\n".join(problems)


def test_calibrate_and_mesh_help_is_complete(capsys):
    assert cli.main(["calibrate", "--help"]) == 0
    text = " ".join(capsys.readouterr().out.split())
    assert "calibration.json and DIR/calibration.png." in text
    assert cli.main(["mesh", "foot", "--help"]) == 0
    text = " ".join(capsys.readouterr().out.split())
    assert "included angle of the conical skirt, 180 = flat disk (deg; default 120)" in text
    assert cli.main(["epsa", "--help"]) == 0
    assert "DEFAULT_FIBERS" not in capsys.readouterr().out
