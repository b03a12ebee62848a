"""The conventions every command shares (studies/cli.py): --version, -q/-v, one spelling per
option with the old ones deprecated, --json [FILE], range errors that name the range."""

import argparse
import json
import shutil
from pathlib import Path

import pytest

from softcrawl import __version__, console
from softcrawl.studies.cli import build_parser, main

RESULTS = Path(__file__).resolve().parents[3] / "results"


@pytest.fixture(autouse=True)
def _normal_level():
    yield
    console.set_level(0)


def _leaves(parser, path=()):
    subs = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    if not subs:
        yield path, parser
        return
    for name, child in subs[0].choices.items():
        yield from _leaves(child, (*path, name))


def test_version(capsys):
    assert main(["--version"]) == 0
    assert capsys.readouterr().out.strip() == f"softcrawl {__version__}"


def test_every_command_takes_quiet_and_verbose():
    leaves = list(_leaves(build_parser()))
    assert len(leaves) >= 20
    for path, parser in leaves:
        flags = {s for a in parser._actions for s in a.option_strings}
        assert {"-q", "--quiet", "-v", "--verbose"} <= flags, path
    args = build_parser().parse_args(["-q", "verify", "--case", "patch"])
    assert args.quiet == 1
    args = build_parser().parse_args(["verify", "-vv"])
    assert args.verbose == 2


def test_quiet_prints_no_progress_lines(tmp_path, capsys):
    copy = tmp_path / "results" / "fiber-turns" / "ecoflex-00-50@mu=0.0638"
    shutil.copytree(RESULTS / "fiber-turns" / "ecoflex-00-50@mu=0.0638", copy)
    assert main(["replot", str(tmp_path / "results")]) == 0
    assert "fiber-turns.png" in capsys.readouterr().out  # a progress line per figure
    assert main(["replot", "-q", str(tmp_path / "results")]) == 0
    out = capsys.readouterr().out
    assert out.strip().startswith("redrew") and "fiber-turns.png" not in out


def test_verbose_verify_prints_the_details(capsys):
    assert main(["verify", "--case", "patch"]) == 0
    assert "stress_error" not in capsys.readouterr().out
    assert main(["-v", "verify", "--case", "patch"]) == 0
    assert "stress_error" in capsys.readouterr().out


@pytest.mark.parametrize(
    "argv, old, dest, value",
    [
        (["mesh", "epsa", "--out", "o", "--outer_radius", "9.5"], "--outer_radius", "p:outer_radius", 9.5),
        (["mesh", "epsa", "--out", "o", "--edge-length", "4"], "--edge-length", "edge_length", 4.0),
        (["crawl", "--out", "o", "--edge-length", "3"], "--edge-length", "edge_length", 3.0),
        (["model", "speed", "--cycle", "3"], "--cycle", "cycle", 3.0),
    ],
)
def test_old_spellings_work_with_one_deprecation_line(argv, old, dest, value, capsys):
    args = build_parser().parse_args(argv)
    assert getattr(args, dest) == value
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and old in err and "deprecated" in err


def test_the_dashed_spelling_is_the_one_shown(capsys):
    assert main(["mesh", "epsa", "--help"]) == 0
    out = capsys.readouterr().out
    assert "--outer-radius" in out and "--outer_radius" not in out
    assert "--mesh-size" in out and "--edge-length" not in out


def test_json_on_stdout_or_into_a_file(tmp_path, capsys):
    assert main(["verify", "--case", "patch", "--json"]) == 0
    captured = capsys.readouterr()
    assert json.loads(captured.out)["all_passed"] is True
    assert "patch" in captured.err  # the table, out of the JSON's way
    target = tmp_path / "sub" / "v.json"
    assert main(["verify", "--case", "patch", "--json", str(target)]) == 0
    assert json.loads(target.read_text())["cases"][0]["case"] == "patch"
    assert main(["material", "list", "--json", str(tmp_path / "m.json")]) == 0
    assert any(m["name"] == "ecoflex-00-50" for m in json.loads((tmp_path / "m.json").read_text()))
    capsys.readouterr()
    assert main(["model", "fk", "--lengths", "110", "125", "140", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["lengths_mm"] == [110.0, 125.0, 140.0]


@pytest.mark.parametrize(
    "argv, expected",
    [
        (["epsa", "--pressures", "0:1200:100"], "1000 kPa limit"),
        (["epsa", "--pressures", "100,1200"], "1000 kPa limit"),
        (["robot", "--pressures", "1200,40,60"], "[0, 1000] kPa"),
    ],
)
def test_a_pressure_above_the_limit_names_the_limit(argv, expected, tmp_path, capsys):
    assert main([*argv, "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert expected in err and "START:STOP:STEP" not in err and err.count("\n") == 1
