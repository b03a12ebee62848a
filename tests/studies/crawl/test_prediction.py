"""`softcrawl study predict-crawl` (studies/crawl/prediction.py): the speed in the direction of
travel and its error against Table 2 from a crawl's summary, the goal's clauses each deciding
alone, and the runs found where they are (the crawl study's points) or computed where they are
not, with the identification's mu; no FE here (the crawls are stubbed)."""

from __future__ import annotations

import json
import math
import shutil
from dataclasses import asdict, replace

import pytest

from softcrawl.studies.crawl import prediction
from softcrawl.studies.foot import identify


def _summary(d, direction, strides, mu=(0.3, 0.3), cycle_s=2.0, converged=True):
    setup = prediction.setup_for(d, direction, *mu)
    return {"setup": asdict(setup), "strides_mm": list(strides), "schedule": {"cycle_s": cycle_s},
            "converged": converged}  # fmt: skip


def test_speed_is_the_steady_stride_over_the_cycle_in_the_direction_of_travel():
    fwd = prediction.prediction_row(_summary(60.0, "forward", [30.0, 36.0]), "forward", "x")
    assert fwd.speed_mm_s == 18.0 and fwd.first_stride_mm == 30.0  # the second cycle, not the first
    assert fwd.error == pytest.approx((18.0 - 20.1) / 20.1) and fwd.held_out
    back = prediction.prediction_row(_summary(70.0, "backward", [-9.0, -33.4]), "backward", "x")
    assert back.speed_mm_s == pytest.approx(16.7) and back.error == pytest.approx(0.0, abs=1e-12)
    assert not back.held_out  # 70 mm: the identification's diameter
    wrong_way = prediction.prediction_row(_summary(55.0, "backward", [1.0, 2.0]), "backward", "x")
    assert wrong_way.speed_mm_s == -1.0  # moved forward in a backward crawl: a negative speed
    one = prediction.prediction_row(_summary(55.0, "forward", [3.0]), "forward", "x")
    assert math.isnan(one.speed_mm_s) and not one.converged  # one cycle: no steady stride


def _rows(speeds, direction="forward"):
    return [
        prediction.prediction_row(_summary(d, direction, [0.0, 2.0 * v]), direction, "x")
        for d, v in zip((55.0, 60.0, 65.0, 70.0, 75.0), speeds, strict=True)
    ]


def test_the_goal_needs_every_pipe_moving_and_every_held_out_pipe_within_30_percent():
    table2 = (17.4, 20.1, 19.5, 18.3, 17.6)
    assert prediction.goal(_rows(table2))["forward"]["met"]
    # 70 mm is not held out: far off there, the goal still holds while it moves
    assert prediction.goal(_rows((17.4, 20.1, 19.5, 1.0, 17.6)))["forward"]["met"]
    # one held-out pipe at 31 % off: not met, although every speed is positive
    off = prediction.goal(_rows((17.4 * 1.31, 20.1, 19.5, 18.3, 17.6)))["forward"]
    assert not off["met"] and off["positive_everywhere"] and off["within_tolerance"] == [60.0, 65.0, 75.0]
    # 29 % off: within
    assert prediction.goal(_rows((17.4 * 1.29, 20.1, 19.5, 18.3, 17.6)))["forward"]["met"]
    # the fit pipe standing still: not met, although every held-out pipe is within
    still = prediction.goal(_rows((17.4, 20.1, 19.5, 0.0, 17.6)))["forward"]
    assert not still["met"] and not still["positive_everywhere"] and len(still["within_tolerance"]) == 4
    # a stalled crawl's 1e-3 mm stride is not a speed above 0
    assert not prediction.goal(_rows((17.4, 20.1, 19.5, 0.0005, 17.6)))["forward"]["positive_everywhere"]
    assert prediction.goal(_rows((17.4, 20.1, 19.5, 0.006, 17.6)))["forward"]["met"]
    trend = prediction.goal(_rows((0.0, 0.0, 0.0, 3.9, 17.7)))["forward"]["trend_60_75"]
    assert trend["fe_mm_s"] == pytest.approx(17.7) and trend["table2_mm_s"] == pytest.approx(-2.5)


def test_runs_are_found_in_the_crawl_study_or_computed_with_the_identified_mu(tmp_path, monkeypatch):
    results = tmp_path / "results"
    (results / "identify" / "feet").mkdir(parents=True)
    shutil.copy(identify.COMMITTED, results / "identify" / "feet" / "feet.json")  # mu 0.3 / 0.3
    point = results / "crawl" / "rubber-70a" / "points" / "D55-mu0.3"
    point.mkdir(parents=True)
    (point / "summary.json").write_text(json.dumps(_summary(55.0, "forward", [1.0, 4.0])))
    other = results / "crawl" / "rubber-70a" / "points" / "D60-mu0.3"
    other.mkdir(parents=True)  # another setup (one cycle): not this prediction's run
    (other / "summary.json").write_text(json.dumps(_summary(60.0, "forward", [1.0]) | {"setup": {}}))
    committed = results / "crawl" / "backward-70-mu0.3-2cycles"  # a committed softcrawl crawl run
    committed.mkdir(parents=True)
    (committed / "summary.json").write_text(json.dumps(_summary(70.0, "backward", [-9.2, -0.1])))
    ran = []

    def fake_run(setup, folder, progress):
        ran.append((setup.pipe_diameter, setup.feet, setup.mu_smooth, setup.mu_grooved, folder.name))
        sign = -1.0 if setup.feet == "backward" else 1.0
        return _summary(setup.pipe_diameter, "backward" if sign < 0 else "forward", [0.0, sign * 10.0])

    monkeypatch.setattr(prediction, "_run", fake_run)
    rows, inputs = prediction.predict(results)
    assert inputs["mu_smooth"] == 0.3 and "outside" in inputs["mu_smooth_is"]
    assert len(rows) == 10 and len(ran) == 8  # every run but the crawl study's D55 point and backward 70
    assert rows[0].source == "crawl/rubber-70a/points/D55-mu0.3" and rows[0].speed_mm_s == 2.0
    assert {r[1] for r in ran} == {"paper", "backward"} and all(r[2:4] == (0.3, 0.3) for r in ran)
    assert ("forward-D60" in {r[4] for r in ran}) and ("backward-D65" in {r[4] for r in ran})
    assert rows[7].source == "crawl/backward-70-mu0.3-2cycles" and rows[7].speed_mm_s == pytest.approx(0.05)
    folder = tmp_path / "out"
    written = prediction.write_tables(rows, inputs, folder)
    assert [r.speed_mm_s for r in prediction.read_rows(folder)] == [r.speed_mm_s for r in rows]
    text = (folder / "prediction.md").read_text()
    assert "forward: goal not met" in text and "| 55 | forward | 2.000 | 17.4 | -88.5 % |" in text
    png = prediction.plot_prediction(rows, results, folder / "prediction.png")
    assert png.stat().st_size > 10_000 and len(written) == 3


def test_a_stored_run_matches_only_its_own_setup():
    setup = prediction.setup_for(60.0, "backward", 0.3, 0.3)
    stored = _summary(60.0, "backward", [0.0, -1.0])
    assert prediction._same_setup(stored, setup)
    older = json.loads(json.dumps(stored))
    del older["setup"]["thickness_layers"]  # a run stored before the field existed had its default
    assert prediction._same_setup(older, setup)
    assert not prediction._same_setup(older, replace(setup, thickness_layers=4))
    assert not prediction._same_setup(stored, prediction.setup_for(60.0, "forward", 0.3, 0.3))
    assert not prediction._same_setup(stored, prediction.setup_for(60.0, "backward", 0.3, 0.5))
    assert not prediction._same_setup({"setup": {}}, setup)


def test_without_computing_the_missing_runs_are_rows_not_computed(tmp_path):
    results = tmp_path / "results"
    (results / "identify" / "feet").mkdir(parents=True)
    shutil.copy(identify.COMMITTED, results / "identify" / "feet" / "feet.json")
    rows, _ = prediction.predict(results, compute=False)
    assert len(rows) == 10 and all(r.source == "not computed" and not r.converged for r in rows)
    assert math.isnan(rows[0].speed_mm_s) and rows[0].table2_mm_s == 17.4
    assert not prediction.goal(rows)["forward"]["met"]
