"""The robot studies say so when optuna's best_trial is not the rule's pick (decision 063): the
foot-radius rule's 1 % tie-break goes to the smaller d, which optuna, judging one design at a time,
cannot see. Synthetic summary rows, the real rule."""

from __future__ import annotations

import math

from softcrawl.studies.robot_fe.robot_studies import best_trial_note, design_tests
from softcrawl.studies.robot_fe.rules import foot_radius_rule


def _row(d, theta):
    return {"d": d, "theta_asym_deg": theta, "converged": True, "splay_max_mm": 0.2, "arc_rms_max_mm": 0.1}


def test_a_tie_break_pick_is_named_beside_optunas_best():
    rows = [_row(12.0, 80.0), _row(14.0, 74.5), _row(15.0, 75.0)]  # d = 12: the camera does not fit
    assert design_tests("foot-radius", rows[0])[1] == [1.0]
    decision = foot_radius_rule(rows)
    assert decision.value == 14.0  # 74.5 is within 1 % of 75.0: the smaller d
    note = best_trial_note("foot-radius", rows, decision.value)
    assert note is not None and "d = 15" in note and "d = 14" in note


def test_no_note_when_best_trial_is_the_pick():
    rows = [_row(12.0, 80.0), _row(14.0, 74.0), _row(15.0, 75.0)]  # 74 < 0.99 * 75: no tie
    decision = foot_radius_rule(rows)
    assert decision.value == 15.0
    assert best_trial_note("foot-radius", rows, decision.value) is None
    assert best_trial_note("foot-radius", [_row(14.0, math.nan)], None) is None
