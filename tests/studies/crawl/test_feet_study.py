"""`softcrawl study feet` with a fake crawl (tests/studies/fakes.py), and Fig. 21's statements at the
points where each verdict flips (no FE here)."""

import shutil
from pathlib import Path

import pytest

from softcrawl.paper import FIG21_MIN_SPEED_MM_S
from softcrawl.studies.crawl import feet_statements as fs
from softcrawl.studies.crawl import feet_study
from softcrawl.studies.foot.identify import IdentificationMissing

FAKE = "tests.studies.fakes:fake_feet_crawl"
IDENTIFIED = Path(__file__).parents[3] / "results" / "identify" / "feet" / "feet.json"


def _out(tmp_path):
    out = tmp_path / "results"
    (out / "identify" / "feet").mkdir(parents=True)
    shutil.copy(IDENTIFIED, out / "identify" / "feet" / "feet.json")
    return out


def _calls(out, quick=False):
    return (feet_study.study_folder(out, quick) / "points" / "calls.log").read_text().splitlines()


def test_the_study_runs_every_point_records_a_failure_and_resumes(tmp_path):
    out = _out(tmp_path)
    outcome = feet_study.run_feet_study(out, simulate=FAKE, progress=False)
    folder = feet_study.study_folder(out, False)
    assert folder.name == "D70" and len(_calls(out)) == 12
    assert _calls(out)[0] == "70,120"  # 70A and the paper's angle first
    rows = feet_study.point_rows(feet_study.sweep_spec_from_file(folder), folder)
    failed = [r for r in rows if r["status"] != "completed"]
    assert [(r["shore_a"], r["angle_deg"], r["status"]) for r in failed] == [(50.0, 30.0, "failed")]
    assert "Newton diverged" in failed[0]["message"] and not outcome.ok
    ok = next(r for r in rows if (r["shore_a"], r["angle_deg"]) == (70.0, 120.0))
    assert ok["first_stride_mm"] == pytest.approx(37.0) and ok["steady_stride_mm"] == pytest.approx(36.0)
    assert ok["speed_mm_s"] == pytest.approx(18.0) and ok["material"] == "rubber-70a"
    assert ok["mu_smooth"] == 0.3 and ok["hub_thickness_mm"] == pytest.approx(4.0)
    text = (folder / "summary.md").read_text()
    assert "mu_smooth = 0.3 (outside the sourced range" in text and "mu_grooved = 0.3" in text
    assert '"> 10 mm/s over 50A-70A and 30-120 deg": undecided (11 of 12 points above' in text
    assert '"rises with angle at 70A": holds' in text
    assert {p.name for p in folder.iterdir()} >= {"feet.csv", "summary.md", "feet.png", "spec.json"}
    # resumed: the completed points are not run again, a failed one only with --retry-failed
    feet_study.run_feet_study(out, simulate=FAKE, progress=False)
    assert len(_calls(out)) == 12
    feet_study.run_feet_study(out, simulate=FAKE, progress=False, retry=True)
    assert _calls(out)[12:] == ["50,30"]


def test_quick_is_a_smaller_grid_of_one_cycle_and_replots_byte_for_byte(tmp_path):
    out = _out(tmp_path)
    feet_study.run_feet_study(out, quick=True, simulate=FAKE, progress=False)
    folder = feet_study.study_folder(out, True)
    assert sorted(_calls(out, True)) == ["50,120", "50,60", "70,120", "70,60"]
    assert "1 cycle(s)" in (folder / "summary.md").read_text()
    png = (folder / "feet.png").read_bytes()
    assert feet_study.replot_folder(folder) == [folder / "feet.png"]
    assert (folder / "feet.png").read_bytes() == png
    html = feet_study.report_block(folder)  # the design review's block
    assert "softcrawl study feet --quick" in html and "rises with angle at 70A" in html and "<img" in html


def test_a_point_that_raises_is_a_failure_with_its_reason(tmp_path):
    out = _out(tmp_path)
    outcome = feet_study.run_feet_study(
        out, quick=True, simulate="tests.studies.fakes:raising_feet_crawl", progress=False
    )
    folder = feet_study.study_folder(out, True)
    rows = {
        (r["shore_a"], r["angle_deg"]): r
        for r in feet_study.point_rows(feet_study.sweep_spec_from_file(folder), folder)
    }
    assert rows[(50.0, 60.0)]["status"] == "failed"
    assert "cannot be built" in rows[(50.0, 60.0)]["message"]
    assert "- 50A, 60 deg: failed: RuntimeError: made-up" in (folder / "summary.md").read_text()
    assert any("50A, 60 deg: failed" in p for p in outcome.problems)


def test_the_friction_is_the_identifications_or_an_error(tmp_path):
    assert feet_study.friction(_out(tmp_path))["mu_grooved_flag"].startswith("outside the sourced range")
    with pytest.raises(IdentificationMissing) as err:  # the reader's error (studies.foot.identify)
        feet_study.friction(tmp_path / "empty")
    assert err.value.parameter == "out"


def _rows(speeds: dict) -> list[dict]:
    return [
        {"shore_a": s, "angle_deg": a, "status": "completed" if v is not None else "failed", "speed_mm_s": v}
        for (s, a), v in speeds.items()
    ]


GRID = [(s, a) for s in (70.0, 60.0, 50.0) for a in (120.0, 90.0, 60.0, 30.0)]


def test_above_10_flips_at_one_point_of_the_range():
    fast = dict.fromkeys(GRID, 12.0)
    assert fs.above_speed(_rows(fast)).verdict == "holds"
    at = fast | {(60.0, 90.0): FIG21_MIN_SPEED_MM_S}  # "greater than": 10 mm/s is not
    verdict = fs.above_speed(_rows(at))
    assert verdict.verdict == "fails" and verdict.detail.startswith("11 of 12 points")
    assert fs.above_speed(_rows(fast | {(60.0, 90.0): 10.001})).verdict == "holds"
    # a slow point outside 50A-70A does not decide it; a missing one in range leaves it open
    assert fs.above_speed(_rows(fast | {(80.0, 90.0): 1.0})).verdict == "holds"
    assert fs.above_speed(_rows(fast | {(50.0, 30.0): None})).verdict == "undecided"
    # ... unless a computed point already fails it
    assert fs.above_speed(_rows(at | {(50.0, 30.0): None})).verdict == "fails"


def test_rising_with_angle_flips_at_one_step_of_70a_only():
    rising = {(70.0, a): a / 10.0 for a in (120.0, 90.0, 60.0, 30.0)}
    others = {(50.0, a): 20.0 - a / 10.0 for a in (120.0, 90.0, 60.0, 30.0)}  # falls: not 70A
    assert fs.rises_with_angle(_rows(rising | others)).verdict == "holds"
    # 60 -> 90 deg rises by exactly the resolution (0.0 -> 0.01 mm/s): not "increases"
    flat = rising | {(70.0, 30.0): -1.0, (70.0, 60.0): 0.0, (70.0, 90.0): fs.SPEED_RESOLUTION_MM_S}
    assert fs.rises_with_angle(_rows(flat)).verdict == "fails"
    just = flat | {(70.0, 90.0): 2 * fs.SPEED_RESOLUTION_MM_S}
    assert fs.rises_with_angle(_rows(just)).verdict == "holds"
    assert fs.rises_with_angle(_rows(rising | {(70.0, 60.0): None})).verdict == "undecided"
    assert fs.rises_with_angle(_rows(rising | {(70.0, 120.0): 0.0})).verdict == "fails"


def test_a_wedge_run_has_its_folder_and_multiples_of_its_sectors(tmp_path):
    """--wedge 4: OUT/feet/D70-quick-wedge4, each point's feet a quarter wedge on quick_sectors
    rounded up to a multiple of 4 (24 / 44 at 120 / 60 deg), the command in the review block."""
    out = _out(tmp_path)
    feet_study.run_feet_study(out, quick=True, wedge=4, simulate=FAKE, progress=False)
    folder = feet_study.study_folder(out, True, 4)
    assert folder.name == "D70-quick-wedge4" and (folder / "summary.md").exists()
    spec = feet_study.sweep_spec_from_file(folder)
    setups = {p["angle_deg"]: feet_study.point_setup(p, spec.settings) for p in spec.points()}
    assert {a: (s.sectors, s.copies) for a, s in setups.items()} == {120.0: (24, 4), 60.0: (44, 4)}
    whole = feet_study.point_setup(
        {"shore_a": 70.0, "angle_deg": 60.0}, {"mu_smooth": 0.3, "mu_grooved": 0.3}
    )
    assert (whole.sectors, whole.copies) == (42, 1)  # the whole feet keep quick_sectors
    assert "softcrawl study feet --quick --wedge 4" in feet_study.report_block(folder)
