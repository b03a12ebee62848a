"""`softcrawl study` with a fake simulator (no FE): outputs, optimiser, input errors."""

from __future__ import annotations

import csv
import json

import pytest

pytest.importorskip("optuna")
from softcrawl.studies.cli import main

FAKE = "tests.studies.fakes:fake_simulate"


def test_sweep_outputs_every_grid_point_with_status(tmp_path, monkeypatch, capsys):
    monkeypatch.setenv("SOFTCRAWL_FAKE_DIVERGE", "1")
    assert (
        main(
            [
                "study",
                "chamber-radius",
                "--quick",
                "--simulator",
                FAKE,
                "--out",
                str(tmp_path),
                "--no-progress",
            ]
        )
        == 0
    )
    folder = tmp_path / "chamber-radius" / "ecoflex-00-50-quick"
    rows = list(csv.DictReader(open(folder / "curves.csv")))
    assert {float(r["chamber_radius"]) for r in rows} == {2.0, 3.0, 4.0, 5.0, 6.0}
    assert all(r["trial_status"] in ("completed", "failed") for r in rows)
    assert all(r["row_status"] for r in rows)
    failed = [r for r in rows if r["trial_status"] == "failed"]
    assert failed and all("diverged" in r["reason"] for r in failed)
    summary = list(csv.DictReader(open(folder / "summary.csv")))
    assert [s["withstands_100kpa"] for s in summary] == ["True", "True", "True", "False", "False"]
    assert (folder / "chamber-radius.png").stat().st_size > 10_000
    assert (folder / "study.db").exists()
    assert "1 failed" in capsys.readouterr().out


def test_optimise_actuator_marks_table1(tmp_path, capsys):
    assert (
        main(
            [
                "study",
                "optimise-actuator",
                "--quick",
                "--trials",
                "8",
                "--simulator",
                FAKE,
                "--out",
                str(tmp_path),
                "--no-progress",
            ]
        )
        == 0
    )
    folder = tmp_path / "optimise-actuator" / "ecoflex-00-50-quick"
    rows = list(csv.DictReader(open(folder / "trials.csv")))
    assert len(rows) == 8
    first = [r for r in rows if r["initial"] == "True"]
    assert len(first) == 1 and float(first[0]["chamber_radius"]) == 3.0
    assert int(first[0]["fiber_turns"]) == 20
    assert all(2.0 <= float(r["chamber_radius"]) <= 6.0 for r in rows)
    assert any(r["pareto"] == "True" for r in rows)
    assert (folder / "pareto.png").stat().st_size > 10_000
    # resume: the budget is already spent, nothing new
    assert (
        main(
            [
                "study",
                "optimise-actuator",
                "--quick",
                "--trials",
                "8",
                "--simulator",
                FAKE,
                "--out",
                str(tmp_path),
                "--no-progress",
            ]
        )
        == 0
    )
    assert len(list(csv.DictReader(open(folder / "trials.csv")))) == 8
    assert "Table 1 design" in capsys.readouterr().out


@pytest.mark.parametrize(
    "argv, parameter",
    [
        (["--material", "nope"], "material"),
        (["--workers", "0"], "workers"),
        (["--simulator", "nocolon"], "simulator"),
        (["--storage", "study.db"], "storage"),
    ],
)
def test_input_errors_exit_2(tmp_path, capsys, argv, parameter):
    assert main(["study", "fiber-turns", "--out", str(tmp_path), *argv]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and parameter in err


def test_optimiser_failed_trials_are_results_not_tracebacks(tmp_path, capfd):
    assert (
        main(
            [
                "study",
                "optimise-actuator",
                "--quick",
                "--trials",
                "10",
                "--simulator",
                "tests.studies.fakes:limited_simulate",
                "--out",
                str(tmp_path),
                "--no-progress",
            ]
        )
        == 0
    )
    rows = list(csv.DictReader(open(tmp_path / "optimise-actuator" / "ecoflex-00-50-quick" / "trials.csv")))
    # a design that does not reach 100 kPa is a result: a completed, infeasible trial whose
    # first constraint (withstand the target) is positive
    short = [r for r in rows if r["trial_status"] == "completed" and json.loads(r["constraints"])[0] > 0]
    assert short and all(r["feasible"] == "False" for r in short)
    out, err = capfd.readouterr()
    assert "Traceback" not in out + err and "failed" in out
