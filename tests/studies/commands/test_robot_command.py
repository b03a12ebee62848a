"""`softcrawl robot` input errors and `softcrawl study rings|foot-radius` with a fake runner (no FE):
the sweep, the tables, the rule's decision and the figure."""

from __future__ import annotations

import csv
import json

import pytest

pytest.importorskip("optuna")
from softcrawl.studies.cli import main

FAKE = "tests.studies.fakes:fake_robot_cases"


BAD = [
    (["--pressures", "10,20"], "pressures"),
    (["--pressures", "10,20,30", "--first", "a,b,c"], "first"),
    (["--pressures", "10,20,30", "--steps", "0"], "steps"),
]


@pytest.mark.parametrize("argv, parameter", BAD)
def test_robot_input_errors_are_one_line(argv, parameter, capsys):
    assert main(["robot", *argv]) == 2
    assert parameter in capsys.readouterr().err


def test_ring_study_decides_the_row_from_its_rule(tmp_path, capsys):
    argv = ["study", "rings", "--quick", "--simulator", FAKE, "--out", str(tmp_path), "--no-progress"]
    assert main(argv) == 0
    folder = next((tmp_path / "robot-rings").iterdir())
    summary = list(csv.DictReader(open(folder / "summary.csv")))
    assert [int(r["n_rings"]) for r in summary] == [1, 2, 3, 4, 5]
    decision = json.loads((folder / "decision.json").read_text())
    # splay 3/n mm against 1.4 mm: n >= 3 combine; n = 3 bends most of them (each ring costs 2 deg)
    assert decision["value"] == 3
    assert (folder / "rings.png").stat().st_size > 0
    assert "connecting rings = 3" in capsys.readouterr().out


def test_foot_radius_study_respects_the_camera(tmp_path):
    argv = ["study", "foot-radius", "--quick", "--simulator", FAKE, "--out", str(tmp_path), "--no-progress"]
    assert main(argv) == 0
    folder = next((tmp_path / "robot-foot-radius").iterdir())
    assert json.loads((folder / "decision.json").read_text())["value"] == 14.0
