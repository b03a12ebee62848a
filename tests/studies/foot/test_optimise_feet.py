"""`softcrawl study optimise-feet` with the fake foot (`tests/studies/fakes.py:fake_foot`, no FE):
the paper's foot first, the categorical hardness, the two objectives, FAIL trials with their
reason, resume, replot, the identification it needs, and the search engine's categorical space."""

from __future__ import annotations

import csv
import json
import shutil
from pathlib import Path

import pytest

from softcrawl.studies.cli import main
from softcrawl.studies.foot.optimise import HARDNESS, folder_of, replot_folder
from softcrawl.studies.foot.optimise_evaluator import evaluate_feet_design
from softcrawl.studies.sweeps.spec import SearchSpec, StudyError

FAKE = "tests.studies.fakes:fake_foot"
COMMITTED = Path(__file__).resolve().parents[3] / "results" / "identify" / "feet" / "feet.json"


def _out(tmp_path) -> Path:
    """An output folder holding the committed identification (mu 0.3 on both faces, flagged)."""
    target = tmp_path / "identify" / "feet" / "feet.json"
    target.parent.mkdir(parents=True)
    shutil.copy(COMMITTED, target)
    return tmp_path


def _run(out, trials=8, *extra):
    argv = ["study", "optimise-feet", "--quick", "--trials", str(trials), "--simulator", FAKE]
    return main([*argv, *extra, "--out", str(out), "--no-progress"])


def _rows(out):
    return list(csv.DictReader(open(folder_of(out, True) / "trials.csv")))


def test_the_study_runs_resumes_and_marks_the_paper_foot(tmp_path, capsys):
    out = _out(tmp_path)
    assert _run(out) == 0
    rows = _rows(out)
    assert len(rows) == 8
    paper = [r for r in rows if r["initial"] == "True"]
    assert len(paper) == 1 and float(paper[0]["angle"]) == 120.0 and paper[0]["hardness"] == "rubber-70a"
    assert float(paper[0]["skirt_thickness"]) == 3.0
    assert {r["hardness"] for r in rows} <= set(HARDNESS)
    assert all(30.0 <= float(r["angle"]) <= 120.0 and 1.5 <= float(r["skirt_thickness"]) <= 3.5 for r in rows)
    done = [r for r in rows if r["trial_status"] == "completed"]
    assert done and all(r["margin"] != "" and float(r["mass_g"]) > 0 for r in done)
    assert any(r["front"] == "True" for r in done)
    # the fake paper foot by hand: mu 0.3 (the identified value), 70A: E = 3 mu, t = 3 mm
    p = paper[0]
    assert float(p["mu_smooth"]) == 0.3 and float(p["f_fwd_n_D55"]) == pytest.approx(57.156, abs=1e-3)
    assert (p["deciding_inequality"], float(p["deciding_pipe_mm"])) == ("slide", 55.0)
    assert float(p["margin"]) == pytest.approx((15.1948 - 57.1563) / 15.1948, abs=1e-3)
    folder = folder_of(out, True)
    summary = (folder / "summary.md").read_text()
    assert "outside the sourced range" in summary and "The paper's foot: margin" in summary
    png = (folder / "pareto.png").read_bytes()
    assert len(png) > 10_000
    # resume: the budget is spent, nothing new; replot redraws the same figure from the table
    assert _run(out) == 0
    assert len(_rows(out)) == 8
    # without --trials (as `--confirm N` is run) the stored budget of 8 stands, not the default 12
    argv = ["study", "optimise-feet", "--quick", "--simulator", FAKE, "--out", str(out), "--no-progress"]
    assert main(argv) == 0
    assert len(_rows(out)) == 8
    assert replot_folder(folder) == [folder / "pareto.png"]
    assert (folder / "pareto.png").read_bytes() == png
    assert "the paper's foot" in capsys.readouterr().out.lower()


def test_failed_solves_are_fail_trials_with_their_reason(tmp_path, monkeypatch, capfd):
    monkeypatch.setenv("SOFTCRAWL_FAKE_FOOT_FAIL", "200")  # every design fails at 55 mm
    out = _out(tmp_path)
    assert _run(out, 4) == 0
    rows = _rows(out)
    assert len(rows) == 4 and all(r["trial_status"] == "failed" for r in rows)
    assert all(r["reason"].startswith("D = 55 mm: stage insert") for r in rows)
    assert "failed" in (folder_of(out, True) / "summary.md").read_text()
    assert "Traceback" not in "".join(capfd.readouterr())


def test_a_limit_point_counts_as_a_flagged_lower_bound(tmp_path):
    settings = {"pipes": [55.0, 75.0], "quick": True, "mu_smooth": 0.3, "mu_grooved": 0.3, "simulator": FAKE}
    params = {"angle": 120.0, "skirt_thickness": 3.5, "hardness": "rubber-60a"}
    result = evaluate_feet_design(params, {}, settings)
    assert result.ok and result.attrs["lower_bounds"] == "f_bwd D75"


def test_the_identification_is_needed_before_any_work(tmp_path, capfd):
    assert _run(tmp_path / "out") == 2
    err = capfd.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "identification" in err[0] and "identify-feet" in err[0]
    assert not (tmp_path / "out" / "optimise-feet").exists()


def test_material_is_refused_because_the_hardness_is_a_design_variable(tmp_path, capfd):
    """--material was silently ignored (every design still took its own hardness): exit 2, one line
    naming it, before any work, with the identification present."""
    out = _out(tmp_path)
    assert _run(out, 2, "--material", "rubber-50a") == 2
    err = capfd.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--material does not apply to study optimise-feet" in err[0], err
    assert not (out / "optimise-feet").exists()


@pytest.mark.parametrize(
    "dimension",
    [("categorical", ()), ("categorical", ("a", "a")), ("categorical", (True, False)), ("categorical", "ab"),
     ("int", 3, 1), ("float", 0.0)],
)  # fmt: skip
def test_a_bad_search_dimension_names_itself(dimension, tmp_path):
    with pytest.raises(StudyError) as exc:
        SearchSpec("s", {"x": dimension}, str(tmp_path), 2, ("minimize",), "optimise-feet")
    assert exc.value.parameter == "space.x"


def test_the_review_shows_the_run(tmp_path):
    from softcrawl.studies.foot.optimise import report_block

    out = _out(tmp_path)
    assert _run(out, 3) == 0
    html = report_block(folder_of(out, True))
    assert "softcrawl study optimise-feet --quick --workers 2" in html and "<img" in html
    assert "The paper's foot: margin" in html


def test_confirm_crawls_the_best_designs_once(tmp_path, monkeypatch):
    """The confirm stage with a fake crawl: the front's best margins first, one crawl per design,
    the crawl given the design's foot and material, a crawl's failure a row, a rerun reads back."""
    import types

    import softcrawl.studies.crawl.confirm_feet as confirm_feet
    from softcrawl.studies.crawl.confirm_feet import best_designs, confirm_best

    monkeypatch.setattr(confirm_feet, "CrawlSetup", lambda **kw: types.SimpleNamespace(**kw))
    rows = [
        {"trial": 0, "angle": "120", "skirt_thickness": "3", "hardness": "rubber-70a", "margin": "-0.5",
         "mass_g": "18", "front": "False", "trial_status": "completed"},
        {"trial": 1, "angle": "60", "skirt_thickness": "2", "hardness": "rubber-50a", "margin": "-0.2",
         "mass_g": "20", "front": "True", "trial_status": "completed"},
        {"trial": 2, "angle": "90", "skirt_thickness": "1.5", "hardness": "rubber-60a", "margin": "-0.9",
         "mass_g": "10", "front": "True", "trial_status": "completed"},
        {"trial": 3, "angle": "30", "skirt_thickness": "2", "hardness": "rubber-60a", "margin": "",
         "mass_g": "", "front": "False", "trial_status": "failed"},
    ]  # fmt: skip
    assert [r["trial"] for r in best_designs(rows, 3)] == [1, 2, 0]
    calls = []

    def crawl(setup, folder):
        calls.append(setup)
        if setup.material == "rubber-60a":
            raise RuntimeError("diverged in cycle 1")
        return {"converged": True, "message": "", "strides_mm": "5.0;2.0", "speed_mm_s": 1.0,
                "steady_stride_mm": float("nan")}  # fmt: skip

    settings = {"mu_smooth": 0.3, "mu_grooved": 0.3, "mu_smooth_flag": "outside the sourced range"}
    out = confirm_best(tmp_path, rows, settings, 2, crawl=crawl)
    assert [(c.foot.angle, c.foot.skirt_thickness, c.material) for c in calls] == [
        (60.0, 2.0, "rubber-50a"),
        (90.0, 1.5, "rubber-60a"),
    ]
    assert calls[0].pipe_diameter == 70.0 and calls[0].cycles == 2 and calls[0].sectors >= 24
    assert out[0]["speed_mm_s"] == 1.0 and out[1]["converged"] is False and "diverged" in out[1]["message"]
    text = (tmp_path / "confirm.md").read_text()
    assert "diverged in cycle 1" in text and "outside the sourced range" in text
    for done in tmp_path.glob("confirm/*/confirm.json"):  # strict JSON: a NaN is null
        json.loads(done.read_text(), parse_constant=lambda c: pytest.fail(f"bare {c} in a confirm.json"))
    confirm_best(tmp_path, rows, settings, 2, crawl=crawl)
    assert len(calls) == 2  # read back, not crawled again


def test_the_confirm_setup_is_the_crawls():
    """The confirm stage builds the crawl's own `CrawlSetup` with the design's foot and rubber."""
    from softcrawl.studies.crawl.confirm_feet import crawl_setup
    from softcrawl.studies.crawl.model import CrawlSetup

    row = {"angle": "60", "skirt_thickness": "2.25", "hardness": "rubber-50a"}
    setup = crawl_setup(row, {"mu_smooth": 0.3, "mu_grooved": 0.3})
    assert isinstance(setup, CrawlSetup) and setup.material == "rubber-50a"
    assert (setup.foot.angle, setup.foot.skirt_thickness, setup.sectors) == (60.0, 2.25, 42)
    assert (setup.pipe_diameter, setup.cycles, setup.insert_steps) == (70.0, 2, 4)


def test_a_wedge_search_has_its_folder_and_passes_the_wedge_on(tmp_path):
    """--wedge 4: OUT/optimise-feet/rubber-quick-wedge4, `copies` in the spec's settings (the
    evaluator hands it to the foot simulator), the confirm crawl on a multiple of 4 sectors."""
    from softcrawl.studies.crawl.confirm_feet import crawl_setup

    out = _out(tmp_path)
    assert _run(out, 2, "--wedge", "4") == 0
    folder = folder_of(out, True, 4)
    assert folder.name == "rubber-quick-wedge4" and (folder / "trials.csv").exists()
    settings = json.loads((folder / "spec.json").read_text())["settings"]
    assert settings["copies"] == 4
    row = {"angle": "60", "skirt_thickness": "2.25", "hardness": "rubber-50a"}
    setup = crawl_setup(row, settings)
    assert (setup.sectors, setup.copies) == (44, 4)
