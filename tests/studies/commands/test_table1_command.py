"""`softcrawl table1` from study outputs made with a fake simulator (no FE)."""

from __future__ import annotations

import csv
import json

import pytest

pytest.importorskip("optuna")
from softcrawl.studies.cli import main

PAPER_LIKE = "tests.studies.fakes:paper_like_simulate"
FAKE = "tests.studies.fakes:fake_simulate"


def _study(tmp_path, name, material, simulator):
    assert (
        main(
            [
                "study",
                name,
                "--quick",
                "--material",
                material,
                "--simulator",
                simulator,
                "--out",
                str(tmp_path),
                "--no-progress",
            ]
        )
        == 0
    )


def _row(md: str, label: str) -> list[str]:
    line = next(line for line in md.splitlines() if line.startswith(f"| {label} |"))
    return [c.strip() for c in line.strip("|").split("|")]


def _sections(md: str) -> dict[str, str]:
    out = {}
    for part in md.split("\n## ")[1:]:
        head = part.splitlines()[0]
        if head.startswith("Material "):
            out[head.split()[1]] = part
    return out


def test_table1_follows_the_study_data(tmp_path, capsys):
    _study(tmp_path, "chamber-radius", "ecoflex-00-50-fit", PAPER_LIKE)
    _study(tmp_path, "fiber-turns", "ecoflex-00-50-fit", PAPER_LIKE)
    _study(tmp_path, "chamber-radius", "ecoflex-00-50", FAKE)  # another "material": no limits
    assert main(["table1", "--out", str(tmp_path)]) == 0
    md = (tmp_path / "table1.md").read_text()
    sections = _sections(md)
    fit, other = sections["ecoflex-00-50-fit"], sections["ecoflex-00-50"]
    chamber = _row(fit, "air chamber radius r0")
    assert chamber[1:3] == ["3 mm", "3 mm"] and chamber[5] == "agree"
    assert "ecoflex-00-50-fit" in chamber[4] and "quick mesh" in chamber[4]
    turns = _row(fit, "fiber winding turns N")
    assert turns[2] == "20" and turns[5] == "agree"
    assert _row(fit, "ePSA length l0")[5] == "agree (input)"
    for label in ("foot groove height h", "foot radius d", "connecting rings"):
        assert _row(fit, label)[5] == "pending"
    chamber_other = _row(other, "air chamber radius r0")
    assert chamber_other[2] == "2 mm" and chamber_other[5] == "disagree"
    assert _row(other, "fiber winding turns N")[5] == "undetermined"
    assert "**depends on the material**" in md
    # the summary names each assumption and its law; the closing section follows the data
    summary = _row(md, "tensile Neo-Hookean fit (strain 0-100 %)")
    assert "Neo-Hookean mu = 0.02242 MPa" in summary[1] and summary[2] == "3 (agree)"
    assert _row(md, "literature Neo-Hookean")[2] == "2 (disagree)"
    closing = md.split("## Which conclusions of the paper survive")[1]
    assert "r0 = 3 mm is selected by the paper's own reasons with: `ecoflex-00-50-fit`" in closing

    # edit the study data: r = 2 no longer fluctuates -> the rule now selects 2 mm
    path = tmp_path / "chamber-radius" / "ecoflex-00-50-fit-quick" / "curves.csv"
    rows = list(csv.DictReader(open(path)))
    for r in rows:
        if float(r["chamber_radius"]) == 2.0:
            r["length_mm"] = str(100 + 0.05 * float(r["pressure_kpa"]))
    with open(path, "w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    assert main(["table1", "--out", str(tmp_path), "--material", "ecoflex-00-50-fit"]) == 0
    md = (tmp_path / "table1.md").read_text()
    chamber = _row(md, "air chamber radius r0")
    assert chamber[2] == "2 mm" and chamber[5] == "disagree"


def test_table1_without_results(tmp_path, capsys):
    """A folder with no study results is bad input (issue 30): one line naming it, no table1.md."""
    assert main(["table1", "--out", str(tmp_path)]) == 2
    assert "results" in capsys.readouterr().err and not (tmp_path / "table1.md").exists()
    assert main(["table1", "--out", str(tmp_path / "x"), "--results", str(tmp_path / "nope")]) == 2
    assert "results" in capsys.readouterr().err


def test_robot_level_rows_follow_their_studies(tmp_path):
    """The groove, foot-radius and ring rows are read from their studies' outputs: a fake ring
    study decides the ring row, and raising the strain of the h = 2 mm groove lowers h."""
    _study(tmp_path, "chamber-radius", "ecoflex-00-50-fit", PAPER_LIKE)
    fake_robot = "tests.studies.fakes:fake_robot_cases"
    argv = ["study", "rings", "--quick", "--simulator", fake_robot, "--out", str(tmp_path), "--no-progress"]
    assert main(argv) == 0
    (decision,) = (tmp_path / "robot-rings").glob("*/decision.json")
    rings = json.loads(decision.read_text())["value"]
    groove = tmp_path / "groove" / "rubber-70a" / "summary.csv"
    groove.parent.mkdir(parents=True)
    rows = [
        {
            "groove_height": h,
            "mu": mu,
            "trial_status": "completed",
            "converged": "True",
            "plateau_over_mu_n": 1.0,
            "von_mises_mpa_p99": 0.2 * h,
            "max_principal_strain_p99": strain,
            "deformation_max_mm": 0.1 * h,
        }  # fmt: skip
        for mu in (0.3, 0.5)
        for h, strain in ((0.5, 0.03), (1.0, 0.04), (1.5, 0.05), (2.0, 0.2))
    ]
    with open(groove, "w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    assert main(["table1", "--out", str(tmp_path)]) == 0
    md = (tmp_path / "table1.md").read_text()
    ring_row = _row(md, "connecting rings")
    assert ring_row[2] == f"{rings:g}" and "quick mesh" in ring_row[4]
    assert ring_row[5] == ("agree" if rings == 3 else "disagree")
    groove_row = _row(md, "foot groove height h")
    assert groove_row[2] == "1.5 mm" and groove_row[4] == "rubber-70a" and groove_row[5] == "disagree"
    assert _row(md, "foot radius d")[5] == "pending"  # no foot-radius study in this folder
    assert "## Rows decided by the foot and robot-level studies" in md
