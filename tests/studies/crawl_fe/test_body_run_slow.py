"""The FE-body crawl end to end (`studies.crawl_fe.files.run_and_write`): under its weight, the
body gains less per cycle heading up than heading down.

The small body of test_holding.py (30 mm actuators, no rings, coarse skirts; 74,400 DOFs) in a
77 mm pipe, friction 0.3, one cycle of two chambers at 20 kPa and back (a gait that bends it),
once in the vertical-up pipe (gravity -z, against the heading) and once in the vertical-down one.
Everything else equal, the weight (0.6 N here) helps the downward crawl and hinders the upward
one, so the upward stride must be the shorter. Both runs write their files; the holds carry
nothing of the weight (below 1e-3 N against wall forces of ~8 N per foot); the two chambers at
20 kPa bend the body (the third at zero) and its chamber volumes grow with the pressure.
"""

import json

import numpy as np
import pytest

from softcrawl.geometry.design import EPSADesign, RobotDesign
from softcrawl.studies.crawl.model import CrawlSetup
from softcrawl.studies.crawl.schedule import Schedule
from softcrawl.studies.crawl_fe.files import run_and_write
from softcrawl.studies.sweeps.tables import read_csv

from .test_holding import SMALL


@pytest.mark.slow
@pytest.mark.timeout(3600)
def test_the_upward_stride_is_shorter_than_the_downward_one(tmp_path):
    setup = CrawlSetup(pipe_diameter=77.0, insert_steps=1, steps=1, cycles=1, mu_smooth=0.3, mu_grooved=0.3)
    gait = Schedule(
        "bend", np.array([0.0, 1.0, 2.0]), np.array([[0.0] * 3, [20.0, 20.0, 0.0], [0.0] * 3]), "test"
    )
    design = RobotDesign(n_rings=0, epsa=EPSADesign(length=30.0))
    strides = {}
    for pipe in ("vertical-up", "vertical-down"):
        out = tmp_path / pipe
        ok, summary = run_and_write(
            setup, gait, out, pipe=pipe, mesh=SMALL, design=design, progress=lambda _: None
        )
        assert ok, summary["message"]
        assert {p.name for p in out.iterdir()} >= {
            "states.csv",
            "cycles.csv",
            "summary.json",
            "crawl.png",
            "vtu",
        }
        assert json.loads((out / "summary.json").read_text())["strides_mm"] == summary["strides_mm"]
        rows = read_csv(out / "states.csv")
        assert max(float(r["holds_max_n"]) for r in rows) < 1e-3
        inflated = [r for r in rows if r["phase"] == "cycle" and float(r["P1_kpa"]) == 20.0][0]
        assert float(inflated["bend_deg"]) > 0.1
        assert float(inflated["V1_mm3"]) > float(inflated["V3_mm3"])
        strides[pipe] = summary["strides_mm"][0]
    assert strides["vertical-up"] < strides["vertical-down"]


@pytest.mark.slow
@pytest.mark.timeout(1200)
def test_a_run_past_its_time_limit_stops_and_writes_what_it_has(tmp_path):
    """A budget shorter than the insertion (~50 s here): the run stops at it, exit code 1's
    `converged` false, the message naming the budget, and every file written."""
    setup = CrawlSetup(pipe_diameter=77.0, insert_steps=1, steps=1, cycles=1, mu_smooth=0.3, mu_grooved=0.3)
    gait = Schedule("test", np.array([0.0, 1.0]), np.array([[0.0] * 3, [20.0] * 3]), "test")
    design = RobotDesign(n_rings=0, epsa=EPSADesign(length=30.0))
    ok, summary = run_and_write(
        setup, gait, tmp_path, mesh=SMALL, design=design, progress=lambda _: None, max_wall_s=5.0
    )
    assert (
        not ok and summary["message"].startswith("time limit of 5 s reached") and summary["strides_mm"] == []
    )
    assert {"states.csv", "cycles.csv", "summary.json", "vtu"} <= {p.name for p in tmp_path.iterdir()}
