"""The constrained optimiser's evaluation on the fake simulator: each constraint switches exactly
where the fake response crosses its bound (values worked out in the comments)."""

from __future__ import annotations

import pytest

from softcrawl.studies.epsa import optimiser as OA
from softcrawl.studies.epsa.constrained_objective import evaluate_constrained

SETTINGS = {"simulate": "tests.studies.fakes:fake_simulate", "quick": True}


def constraints(r, n, simulate="tests.studies.fakes:fake_simulate"):
    result = evaluate_constrained(
        {"chamber_radius": r, "fiber_turns": n}, {}, SETTINGS | {"simulate": simulate}
    )
    assert result.ok
    return result.attrs["constraints"], result.values[0]


def test_extension_and_radius_constraints_switch_where_the_response_crosses_them():
    """Fake at r = 3, 100 kPa: extension 20 (1 + 0.5 N/(N + 10)), N = 50 -> 28.33 mm; |dR| =
    2/(1 + N/5) mm. N = 12 is 10.2 % short (infeasible), N = 13 9.5 % (feasible); |dR|/9 mm is
    6.2 % at N = 13 (above the 5 % bound), 4.8 % at N = 18 (below)."""
    (c0, c1, c2), thread = constraints(3, 12)
    assert c0 == 0.0 and c2 == pytest.approx(25.4545 / 28.3333 * -1 + 1 - 0.10, abs=1e-4)
    assert c2 > 0
    (_, c1, c2), _ = constraints(3, 13)
    assert c2 < 0 and c1 == pytest.approx((2 / 3.6) / 9 - OA.MAX_RADIUS_CHANGE_REL, rel=1e-9) and c1 > 0
    (_, c1, c2), thread18 = constraints(3, 18)
    assert c1 < 0 and c2 < 0 and thread18 > thread


def test_a_design_that_bursts_is_infeasible_not_failed():
    (c0, c1, c2), _ = constraints(5, 20, "tests.studies.fakes:limited_simulate")
    assert c0 > 0 and (c1, c2) == (1.0, 1.0)


def test_mark_optimum_takes_the_least_thread_among_feasible_trials():
    rows = [
        {
            "trial_status": "completed",
            "constraints": "[0, -0.1, -0.01]",
            "thread_length_mm": 900.0,
            "radial_expansion_mm": -0.1,
            "chamber_radius": 3,
            "fiber_turns": 20,
        },
        {
            "trial_status": "completed",
            "constraints": "[0, 0.02, -0.01]",
            "thread_length_mm": 500.0,
            "radial_expansion_mm": 0.6,
            "chamber_radius": 3,
            "fiber_turns": 10,
        },
        {
            "trial_status": "failed",
            "constraints": "",
            "thread_length_mm": "",
            "radial_expansion_mm": "",
            "chamber_radius": 2,
            "fiber_turns": 1,
        },
    ]
    marked = OA.mark_optimum(rows)
    assert [r["feasible"] for r in marked] == [True, False, False]
    assert [r["pareto"] for r in marked] == [True, False, False]
    assert "the paper's Table 1 design" in OA.optimum_record([marked[0]], "m")["verdict"]
