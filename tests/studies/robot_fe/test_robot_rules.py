"""The ring-count and foot-radius rules on constructed study summaries: each reason can fail."""

import math

from softcrawl.studies.robot_fe.rules import (
    ENDOSCOPE_DIAMETER_MM,
    channel_admits_camera,
    foot_radius_rule,
    ring_rule,
)


def _ring(n, theta, ext, splay, arc):
    return {"n_rings": n, "theta_asym_deg": theta, "extension_equal_mm": ext, "splay_max_mm": splay,
            "arc_rms_max_mm": arc}  # fmt: skip


def test_too_few_rings_do_not_combine_and_too_many_cost_bending():
    rows = [
        _ring(1, 80.0, 50.0, 3.0, 0.5),  # splay 3 mm > 1.4 mm: not one body
        _ring(2, 78.0, 50.0, 1.0, 2.0),  # arc RMS 2 mm > 1 mm: not one arc
        _ring(3, 76.0, 49.5, 0.5, 0.3),
        _ring(4, 76.5, 49.0, 0.3, 0.2),
        _ring(5, 70.0, 45.0, 0.2, 0.1),  # 8.5 % less bending: coupling loss
    ]
    d = ring_rule(rows)
    assert d.value == 3
    ev = {e["n_rings"]: e for e in d.evidence}
    assert not ev[1]["combined"] and not ev[2]["combined"] and ev[5]["combined"]
    assert ev[5]["bending_loss"] > 0.02


def test_the_ring_rule_picks_the_best_bending_when_every_count_loses():
    rows = [_ring(1, 80.0, 50.0, 0.5, 0.2), _ring(2, 70.0, 40.0, 0.5, 0.2)]
    assert ring_rule(rows).value == 1


def test_no_computed_ring_count_gives_no_decision():
    d = ring_rule([_ring(3, math.nan, math.nan, math.nan, math.nan)])
    assert d.value is None and "no ring count" in d.reason


def test_foot_radius_is_the_best_bending_that_leaves_room_for_the_camera():
    rows = [{"d": d, "theta_asym_deg": 200.0 - 10 * d} for d in (11.0, 12.0, 13.0, 14.0, 15.0, 16.0)]
    decision = foot_radius_rule(rows, R0=9.0)
    first = min(r["d"] for r in rows if channel_admits_camera(r["d"], 9.0))
    assert decision.value == first
    assert 2 * (first - 9.0) >= ENDOSCOPE_DIAMETER_MM
    assert not channel_admits_camera(first - 1.0, 9.0)
    # a larger d that bends more wins
    rows.append({"d": 15.5, "theta_asym_deg": 500.0})
    assert foot_radius_rule(rows, R0=9.0).value == 15.5
