"""What optuna's own tools read in a study (decision 063): named objectives, the Table 1
rule's design as ``best_trial``, flat metrics, no machine paths, and older databases refused.
Fake simulators (`tests.studies.fakes`), no FE."""

from __future__ import annotations

import dataclasses
import json
import os
import socket
import sqlite3
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

import pytest

optuna = pytest.importorskip("optuna")

from softcrawl.studies.epsa import rules  # noqa: E402
from softcrawl.studies.epsa.evaluator import EPSA_TABLE  # noqa: E402
from softcrawl.studies.epsa.grid_studies import sweep_spec  # noqa: E402
from softcrawl.studies.sweeps.spec import StudyError  # noqa: E402
from softcrawl.studies.sweeps.storage import connect  # noqa: E402
from softcrawl.studies.sweeps.sweep import run_sweep  # noqa: E402

PAPER_LIKE = "tests.studies.fakes:paper_like_simulate"


def _run(tmp_path, name, simulate=PAPER_LIKE, **replace):
    settings = {"material": "fake", "quick": True, "pressures_kpa": [20.0, 40.0, 60.0, 80.0, 100.0]}
    settings |= {"simulate": simulate, "vtu_dir": str(tmp_path / "vtu")}
    spec = sweep_spec(name, tmp_path, settings)
    if replace:
        spec = dataclasses.replace(spec, **replace)
    rows = run_sweep(spec, layout=EPSA_TABLE, progress=False)
    return spec, rows, optuna.load_study(study_name=spec.name, storage=spec.storage_url)


def test_chamber_radius_best_trial_is_the_rule_s_design(tmp_path):
    spec, rows, study = _run(tmp_path, "chamber-radius")
    chosen = rules.select_chamber_radius(rows).value
    assert chosen == 3.0  # r = 5, 6: limit point at 80 kPa; r = 2, 4 fluctuate
    assert study.metric_names == ["radial_expansion_100kpa_mm"]
    best = study.best_trial
    assert best.params["chamber_radius"] == chosen
    # the largest extension (r = 6, limit point at 80 kPa: the old "best") is rejected
    r6 = next(t for t in study.trials if t.params["chamber_radius"] == 6.0)
    assert (
        r6.constraints["withstands_100kpa"] > 0
        and r6.user_attrs["extension_mm"] > best.user_attrs["extension_mm"]
    )
    # metrics are flat, sortable user attributes
    assert "metrics" not in best.user_attrs
    assert isinstance(best.user_attrs["limit_pressure_kpa"], type(None) | float)
    assert best.user_attrs["withstands_100kpa"] is True


def test_fiber_turns_best_trial_is_the_rule_s_design(tmp_path):
    _, rows, study = _run(tmp_path, "fiber-turns")
    chosen = rules.select_fiber_turns(rows).value
    assert chosen == 20
    assert study.metric_names == ["fiber_length_mm"]
    assert study.best_trial.params["fiber_turns"] == chosen
    fewer = [t for t in study.trials if t.params["fiber_turns"] < chosen]
    assert fewer and all(t.constraints["similar_extension"] > 0 for t in fewer)


def test_no_feasible_design_means_no_best_trial(tmp_path):
    """Every radius meets a limit point below 100 kPa: the rule picks none, optuna names none."""
    _, rows, study = _run(
        tmp_path,
        "chamber-radius",
        "tests.studies.fakes:limited_simulate",
        grid={"chamber_radius": (5.0, 6.0)},
    )
    assert rules.select_chamber_radius(rows).value is None
    assert study.best_trials == []
    with pytest.raises(ValueError):
        study.best_trial  # noqa: B018 - optuna's own "no feasible trial"


def test_database_holds_no_absolute_path(tmp_path):
    _run(tmp_path, "chamber-radius")
    with sqlite3.connect(tmp_path / "study.db") as con:
        tables = [t for (t,) in con.execute("SELECT name FROM sqlite_master WHERE type='table'")]
        text = json.dumps([con.execute(f"SELECT * FROM {t}").fetchall() for t in tables], default=str)
    assert str(tmp_path) not in text and "/tmp" not in text


def test_an_older_study_database_is_refused_in_one_line(tmp_path):
    spec = sweep_spec("chamber-radius", tmp_path, {"material": "fake", "simulate": PAPER_LIKE})
    old = optuna.create_study(study_name=spec.name, storage=spec.storage_url, directions=["maximize"])
    old.set_user_attr("spec", spec.to_dict())  # as softcrawl stored it before schema 2
    with pytest.raises(StudyError) as err:
        connect(spec)
    assert err.value.parameter == "storage" and "older softcrawl" in str(err.value)
    assert "\n" not in str(err.value)


def _get(port: int, path: str) -> dict:
    with urllib.request.urlopen(f"http://127.0.0.1:{port}{path}", timeout=10) as r:
        return json.loads(r.read())


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def test_optuna_dashboard_reads_the_metric_names(tmp_path):
    pytest.importorskip("optuna_dashboard", reason="optuna-dashboard absent (pip install -e '.[dashboard]')")
    spec, _, _ = _run(tmp_path, "chamber-radius")
    port = _free_port()
    serve = f"import optuna_dashboard as d; d.run_server({spec.storage_url!r}, host='127.0.0.1', port={port})"
    cmd = [sys.executable, "-c", serve]  # optuna-dashboard's public entry point, as its CLI uses
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=os.environ.copy())
    try:
        listing, deadline = None, time.monotonic() + 30
        while listing is None and time.monotonic() < deadline:
            try:
                listing = _get(port, "/api/studies")
            except OSError:
                assert proc.poll() is None, proc.stderr.read().decode()[-500:]
                time.sleep(0.3)
        assert listing is not None, "optuna-dashboard did not answer in 30 s"
        (summary,) = [s for s in listing["study_summaries"] if s["study_name"] == spec.name]
        data = _get(port, f"/api/studies/{summary['study_id']}")
        assert data["objective_names"] == ["radial_expansion_100kpa_mm"]
        assert "withstands_100kpa" in {a["key"] for a in data.get("union_user_attrs", [])}
    finally:
        proc.terminate()
        proc.wait(timeout=10)


@pytest.mark.parametrize("name", ["rings", "foot-radius"])
def test_robot_best_trial_is_the_rule_s_design(tmp_path, name):
    from softcrawl.studies.robot_fe.robot_studies import run_robot_study, study_spec

    runner = "tests.studies.fakes:fake_robot_cases"
    run_robot_study(name, tmp_path, "fake", True, progress=False, runner=runner)
    spec = study_spec(name, tmp_path, "fake", True, runner)
    decision = json.loads((Path(spec.out_dir) / "decision.json").read_text())
    study = optuna.load_study(study_name=spec.name, storage=spec.storage_url)
    assert study.metric_names == ["theta_asym_deg"]
    key = "n_rings" if name == "rings" else "d"
    assert study.best_trial.params[key] == decision["value"]
