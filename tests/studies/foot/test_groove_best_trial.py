"""optuna's best_trial of the groove study is the groove rule's height, including its "at every
mu" clause (decision 063): a height that passes at one friction coefficient and fails at another is
infeasible at both. A fake groove run (no FE) sets the strains; the real sweep, rule and tables."""

from __future__ import annotations

import csv
import math

import numpy as np
import pytest

from softcrawl.studies.foot import contact_studies, groove_rule
from softcrawl.studies.foot.groove_model import GrooveResult
from softcrawl.studies.foot.runs import contact_spec, run_contact_study

optuna = pytest.importorskip("optuna")

#: p99 strain per (h, mu): h = 2 passes at mu 0.3 and fails at 0.5; h = 1.5 passes at both.
STRAINS = {
    (0.5, 0.3): 0.02, (0.5, 0.5): 0.03,
    (1.0, 0.3): 0.04, (1.0, 0.5): 0.05,
    (1.5, 0.3): 0.06, (1.5, 0.5): 0.09,
    (2.0, 0.3): 0.08, (2.0, 0.5): 0.12,
}  # fmt: skip
CALLS: list[tuple[float, float]] = []


def _fake_run(h, mu, settings, on_state=None):
    CALLS.append((h, mu))
    drag = np.linspace(0.0, 5.0, 6)
    normal = np.full(6, 10.0)
    metrics = {
        "max_principal_strain_p99": STRAINS[(h, mu)],
        "von_mises_mpa_p99": 0.1 * h,
        "von_mises_mpa_max": 0.2 * h,
        "max_principal_strain_max": 2 * STRAINS[(h, mu)],
        "deformation_max_mm": 0.2 * h,
    }
    return GrooveResult(
        h, mu, 0.1, True, "", drag, mu * normal, normal, np.full(6, 0.8), np.full(6, 1.0),
        10.0, 0.0, mu * 10.0, 1.0, metrics, (2, 2), 100, 0.01,
    )  # fmt: skip


def test_best_trial_is_the_rule_s_height_at_every_mu(tmp_path, monkeypatch):
    monkeypatch.setattr(contact_studies, "_groove_run", _fake_run)
    monkeypatch.setattr(contact_studies, "_STRAINS", {})
    CALLS.clear()
    run_contact_study("groove", tmp_path, material="rubber-70a", progress=False)
    (folder,) = {p.parent for p in tmp_path.rglob("summary.csv")}
    with open(folder / "summary.csv", newline="") as f:
        decided = groove_rule.decide(list(csv.DictReader(f))).value
    assert decided == 1.5
    spec = contact_spec("groove", folder, "rubber-70a", False)
    study = optuna.load_study(study_name=spec.name, storage=f"sqlite:///{folder / 'study.db'}")
    assert study.best_trial.params["groove_height"] == decided
    deep = [t for t in study.trials if t.params["groove_height"] == 2.0]
    # h = 2 fails at mu = 0.5 only, and is infeasible at both mus
    assert len(deep) == 2 and all(t.constraints["strain_p99"] > 0 for t in deep)
    assert math.isclose(deep[0].user_attrs["rule_strain_p99_by_mu"]["0.5"], 0.12)
    # each (h, mu) is solved at most twice in one process: once as its own point, once at most
    # as another point's "every mu" check (cached afterwards)
    assert max(CALLS.count(k) for k in STRAINS) <= 2 and len(CALLS) < 2 * len(STRAINS)
