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


def test_the_table_takes_settings_reference_and_scalar_columns_from_their_sources():
    """Each column family from its own source: settings (blank when the spec has none), the
    reference dict (never over a grid or fixed value; blank for a missing key), the evaluator's
    scalars (only those stored, in its order, None blank); a completed trial's stale failure
    attribute is no reason."""
    layout = TableLayout(
        settings_columns=("mesh", "absent"),
        reference="reference",
        reference_columns=("volume", "r", "L", "gone"),
        scalar_columns=("z", "a", "none"),
    )
    s = SweepSpec(
        name="s",
        grid={"r": (1.0, 2.0)},
        out_dir="unused",
        evaluator="x",
        fixed={"L": 100},
        settings={"mesh": "quick"},
    )
    attrs = {
        "reference": {"volume": 7.0, "r": 99.0, "L": 99.0},
        "a": 1.0,
        "z": 2.0,
        "none": None,
        "failure": "old",
    }
    done = Trial(0, TrialState.COMPLETE, {"r": 1.0}, attrs)
    failed = Trial(1, TrialState.FAIL, {"r": 2.0}, {"failure": "limit point", "reference": "not a dict"})
    study = SimpleNamespace(get_trials=lambda deepcopy=False: [done, failed], user_attrs={})
    ok, bad = collect(study, s, layout)
    assert (ok["mesh"], ok["absent"]) == ("quick", "")
    assert (ok["volume"], ok["r"], ok["L"], ok["gone"]) == (7.0, 1.0, 100, "")
    assert ok["reason"] == "" and ok["trial_status"] == "completed"
    assert [k for k in ok if k in layout.scalar_columns] == ["a", "z", "none"]  # the evaluator's order
    assert (ok["z"], ok["a"], ok["none"]) == (2.0, 1.0, "")
    assert bad["reason"] == "limit point" and "volume" not in bad and "z" not in bad
    # without a reference or rows attribute name nothing is looked up (not even an attribute "")
    odd = Trial(0, TrialState.COMPLETE, {"r": 1.0}, {"": {"volume": 5.0}})
    odd_study = SimpleNamespace(get_trials=lambda deepcopy=False: [odd], user_attrs={})
    (plain, _) = collect(odd_study, s, TableLayout(reference_columns=("volume",)))
    assert "volume" not in plain
    odd.user_attrs[""] = [{"p": 1}, {"p": 2}]
    assert len(collect(odd_study, s, TableLayout(row_columns=("p",)))) == 2  # one row per point
    # a row without one of the row columns: blank there
    odd.user_attrs["rows"] = [{"p": 1}, {"q": 2}]
    first, second, _ = collect(odd_study, s, TableLayout(rows="rows", row_columns=("p",)))
    assert (first["p"], second["p"]) == (1, "")


def test_the_study_fails_on_input_only_when_every_point_failed_on_input():
    from softcrawl.studies.sweeps.spec import StudyError
    from softcrawl.studies.sweeps.tables import input_failure

    s = SweepSpec(name="s", grid={"r": (1.0, 2.0)}, out_dir="unused", evaluator="x")
    bad = {"input_error": {"parameter": "wall", "detail": "must be positive"}, "failure": "bad input"}
    both = [Trial(0, TrialState.FAIL, {"r": 1.0}, bad), Trial(1, TrialState.FAIL, {"r": 2.0}, bad)]

    def study(trials):
        return SimpleNamespace(get_trials=lambda deepcopy=False: trials, user_attrs={})

    other_input = {"input_error": {"parameter": "length", "detail": "too long"}, "failure": "bad input"}
    both[1] = Trial(1, TrialState.FAIL, {"r": 2.0}, other_input)
    err = input_failure(study(both), s)
    assert isinstance(err, StudyError) and err.parameter == "wall"  # the first point's error
    assert str(err).count("must be positive (no point of the study could be evaluated)") == 1
    one_ok = [both[0], Trial(1, TrialState.COMPLETE, {"r": 2.0}, {})]
    assert input_failure(study(one_ok), s) is None
    other = [both[0], Trial(1, TrialState.FAIL, {"r": 2.0}, {"failure": "diverged"})]
    assert input_failure(study(other), s) is None
    assert input_failure(study([both[0]]), s) is None  # a missing point is no failure


def test_csv_keeps_line_breaks_inside_a_value(tmp_path):
    """CSV files are opened with newline="" (the csv module's rule): a value holding a CRLF
    reads back as written."""
    path = write_csv([{"message": "limit point\r\nat 80 kPa", "n": 1}], tmp_path / "t.csv")
    assert read_csv(path) == [{"message": "limit point\r\nat 80 kPa", "n": "1"}]
