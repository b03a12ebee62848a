"""Sweep records (issue 32): a failed evaluation is a FAIL trial with its reason, whatever values
it carries (`studies.sweeps.worker.store`), and the table shows it failed, with that reason and
the point's own columns (`studies.sweeps.tables.collect`). Fake trials, no optuna storage."""

import math
from types import SimpleNamespace

import pytest
from optuna.trial import TrialState

from softcrawl.studies.sweeps.spec import Evaluation, SweepSpec, TableLayout
from softcrawl.studies.sweeps.tables import blank, collect, flat_attrs, read_csv, write_csv
from softcrawl.studies.sweeps.worker import EvaluationFailed, store


class Trial:
    def __init__(self, number=0, state=TrialState.RUNNING, params=None, user_attrs=None):
        self.number, self.state, self.params = number, state, params or {}
        self.user_attrs = dict(user_attrs or {})
        self.constraints = {}

    def set_user_attr(self, key, value):
        self.user_attrs[key] = value

    def set_constraint(self, key, value):
        self.constraints[key] = value


@pytest.mark.parametrize(
    "result, reason",
    [
        (Evaluation(ok=False, values=(1.0,), message="limit point at 80 kPa"), "limit point at 80 kPa"),
        (Evaluation(ok=False, values=(1.0,)), "failed"),
        (Evaluation(ok=True, values=(math.nan,)), "evaluator returned no finite values"),
        (Evaluation(ok=True, values=(math.inf,), message="diverged"), "diverged"),
        (Evaluation(ok=True, values=()), "evaluator returned no finite values"),
        (Evaluation(ok=True, values=(1.0, 2.0)), "evaluator returned no finite values"),
    ],
    ids=["failed-with-values", "failed-no-message", "nan", "inf", "no-values", "too-many"],
)
def test_a_failed_evaluation_is_a_fail_with_its_reason_whatever_its_values(result, reason):
    trial = Trial()
    with pytest.raises(EvaluationFailed, match=reason):
        store(trial, result, 1)
    assert trial.user_attrs["failure"] == reason


def test_a_good_evaluation_stores_its_values_attributes_and_constraints():
    trial = Trial()
    result = Evaluation(ok=True, values=(2, 3.5), attrs={"metrics": {"a": 1.0}, "constraints": [0.5, -1]})
    assert store(trial, result, 2) == [2.0, 3.5]
    # metrics are stored flat, one user attribute each (decision 063), so optuna's tools sort them
    assert "failure" not in trial.user_attrs and trial.user_attrs["a"] == 1.0
    assert "metrics" not in trial.user_attrs
    assert trial.constraints == {"c0": 0.5, "c1": -1.0}


def spec():
    return SweepSpec(name="s", grid={"r": (1.0, 2.0, 3.0)}, out_dir="unused", evaluator="x", fixed={"L": 100})


def test_the_table_shows_a_failed_point_failed_with_its_reason_and_keeps_every_point():
    layout = TableLayout(
        point_columns=("score",), rows="rows", row_columns=("p", "v"), renamed={"v": "value"}
    )
    done = Trial(
        0, TrialState.COMPLETE, {"r": 1.0}, {"score": 5.0, "rows": [{"p": 1, "v": 2}, {"p": 2, "v": None}]}
    )
    failed = Trial(
        1, TrialState.FAIL, {"r": 2.0}, {"failure": "limit point", "score": 9.0, "peak_rss_gb": 0.5}
    )
    study = SimpleNamespace(get_trials=lambda deepcopy=False: [done, failed], user_attrs={})
    rows = collect(study, spec(), layout)
    by_r = {}
    for r in rows:
        by_r.setdefault(r["r"], []).append(r)
    assert [r["value"] for r in by_r[1.0]] == [2, ""] and [r["p"] for r in by_r[1.0]] == [1, 2]
    assert all(r["trial_status"] == "completed" and r["reason"] == "" for r in by_r[1.0])
    (f,) = by_r[2.0]
    assert (f["trial_status"], f["reason"], f["trial"], f["score"]) == ("failed", "limit point", 1, 9.0)
    assert f["p"] == "" and f["peak_rss_gb"] == 0.5 and f["L"] == 100 and f["study"] == "s"
    (m,) = by_r[3.0]
    assert m["trial_status"] == "missing" and m["trial"] == "" and m["reason"] == ""


def test_flat_attrs_and_blank_and_the_csv_round_trip(tmp_path):
    t = Trial(user_attrs={"metrics": {"a": 1, "b": 2}, "b": 3})
    assert flat_attrs(t) == {"a": 1, "b": 3, "metrics": {"a": 1, "b": 2}}
    assert flat_attrs(None) == {} and flat_attrs(Trial(user_attrs={"metrics": 4})) == {"metrics": 4}
    assert blank(None) == "" and blank(0) == 0
    path = write_csv([{"a": 1}, {"b": 2, "a": 3}], tmp_path / "t.csv")
    assert read_csv(path) == [{"a": "1", "b": ""}, {"a": "3", "b": "2"}]
