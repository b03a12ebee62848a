"""Table 1 robot rules at the flip (issue 32): inputs built so that each clause alone decides the
outcome, so that flipping any comparison or boolean in `studies.robot_fe.rules` changes the
decision. Thresholds: splay <= 0.1 d0 = 1.4 mm, arc RMS <= 0.01 L = 1 mm, 2 % coupling loss, a
channel of radius d - R0 >= 4.5 mm, bending ties within 1 %."""

import math

import pytest

from softcrawl.studies.robot_fe import rules as R

EPS = 1e-6


def ring(n, theta=30.0, ext=10.0, splay=0.5, arc=0.5):
    return {
        "n_rings": n,
        "theta_asym_deg": theta,
        "extension_equal_mm": ext,
        "splay_max_mm": splay,
        "arc_rms_max_mm": arc,
    }


@pytest.mark.parametrize(
    "field, at, over",
    [("splay", 1.4, 1.4 + EPS), ("arc", 1.0, 1.0 + EPS)],
)
def test_each_combination_clause_alone_rejects_a_count(field, at, over):
    """Count 2 is better in everything; it is rejected by one clause just over its limit, and
    kept exactly at the limit (<=, not <)."""
    base = [ring(3, theta=30.0)]
    kept = R.ring_rule(base + [ring(2, theta=30.0, **{field: at})])
    assert kept.value == 2
    rejected = R.ring_rule(base + [ring(2, theta=30.0, **{field: over})])
    assert rejected.value == 3
    e = {x["n_rings"]: x for x in rejected.evidence}
    assert e[2]["computed"] is True and e[2]["combined"] is False and e[3]["combined"] is True
    assert "not combined: [2]" in rejected.reason


@pytest.mark.parametrize("field", ["theta", "ext", "splay", "arc"])
def test_a_missing_quantity_alone_makes_a_count_uncomputed(field):
    decision = R.ring_rule([ring(2, **{field: float("nan")}), ring(3)])
    e = {x["n_rings"]: x for x in decision.evidence}
    assert e[2]["computed"] is False and e[2]["combined"] is False and decision.value == 3
    assert math.isnan(e[2]["bending_loss"]) and math.isnan(e[2]["extension_loss"])
    assert "not combined: none" in decision.reason  # an uncomputed count is not "too few"


def test_no_combined_count_is_undetermined_with_both_limits_named():
    d = R.ring_rule([ring(2, splay=2.0), ring(3, arc=2.0)])
    assert d.value is None and "1.40 mm" in d.reason and "1.00 mm" in d.reason
    assert R.ring_rule([]).value is None


@pytest.mark.parametrize("field, best", [("theta", 30.0), ("ext", 10.0)])
def test_each_loss_clause_alone_decides(field, best):
    """Two rings lose 2 % (kept, fewest wins) or just over 2 % (lost: three rings, the better)
    of one quantity only."""
    at = best * (1 - R.COUPLING_LOSS_TOLERANCE) * (1 + 1e-9)
    over = best * (1 - R.COUPLING_LOSS_TOLERANCE) * (1 - 1e-6)
    assert R.ring_rule([ring(3, **{field: best}), ring(2, **{field: at})]).value == 2
    lossy = R.ring_rule([ring(3, **{field: best}), ring(2, **{field: over})])
    assert lossy.value == 3 and "coupling losses: [2]" in lossy.reason


def test_ties_go_to_the_fewest_rings_and_without_a_lossless_count_to_the_best_bending():
    assert R.ring_rule([ring(4), ring(3), ring(5)]).value == 3
    # every count loses against the best of another quantity: no lossless count, best theta wins
    d = R.ring_rule([ring(2, theta=30.0, ext=5.0), ring(3, theta=20.0, ext=10.0)])
    assert d.value == 2
    d = R.ring_rule([ring(2, theta=20.0, ext=10.0), ring(3, theta=30.0, ext=5.0)])
    assert d.value == 3


def test_ring_losses_are_relative_to_the_best_combined_count():
    d = R.ring_rule([ring(3, theta=30.0, ext=10.0), ring(2, theta=60.0, ext=20.0, splay=5.0)])
    e = {x["n_rings"]: x for x in d.evidence}
    assert d.value == 3 and e[3]["bending_loss"] == 0.0 and e[2]["bending_loss"] == pytest.approx(-1.0)
    assert e[2]["extension_loss"] == pytest.approx(-1.0)
    assert [x["n_rings"] for x in d.evidence] == [2, 3]  # sorted by count


def test_ring_thresholds_scale_with_d0_and_length():
    rows = [ring(2, splay=2.0, arc=1.5), ring(3, splay=0.1, arc=0.1, theta=10.0)]
    assert R.ring_rule(rows).value == 3
    assert R.ring_rule(rows, d0=20.0, length=150.0).value == 2


def test_camera_channel_at_the_flip():
    need = R.ENDOSCOPE_DIAMETER_MM / 2 + R.CHANNEL_CLEARANCE_MM  # 4.5 mm
    assert R.channel_admits_camera(9.0 + need, 9.0)
    assert not R.channel_admits_camera(9.0 + need - 1e-6, 9.0)
    assert R.channel_admits_camera(5.0 + need, 5.0) and not R.channel_admits_camera(9.0 + need, 9.5)


def foot(d, theta):
    return {"d": d, "theta_asym_deg": theta}


def test_foot_radius_camera_clause_alone_decides():
    """d = 13 bends best but its channel (2 * 4 mm) is too small: 13.5 is picked."""
    d = R.foot_radius_rule([foot(13.0, 50.0), foot(13.5, 40.0), foot(14.0, 30.0)])
    assert d.value == 13.5
    e = {x["d"]: x for x in d.evidence}
    assert e[13.0]["camera_fits"] is False and e[13.5]["camera_fits"] is True
    assert e[13.0]["channel_diameter_mm"] == 8.0
    assert "best bending overall is d = 13 mm" in d.reason


def test_foot_radius_computed_clause_alone_decides():
    d = R.foot_radius_rule([foot(14.0, float("nan")), foot(15.0, 20.0)])
    assert d.value == 15.0 and {x["d"]: x["computed"] for x in d.evidence} == {14.0: False, 15.0: True}


def test_foot_radius_tie_at_the_flip_goes_to_the_smaller_d():
    best = 40.0
    at = (1 - R.BENDING_TIE_TOLERANCE) * best
    assert R.foot_radius_rule([foot(14.0, at), foot(16.0, best)]).value == 14.0
    assert R.foot_radius_rule([foot(14.0, at - 1e-6), foot(16.0, best)]).value == 16.0
    assert R.foot_radius_rule([foot(16.0, best), foot(14.0, best)]).value == 14.0


def test_foot_radius_without_a_candidate_is_undetermined():
    d = R.foot_radius_rule([foot(12.0, 50.0), foot(14.0, float("nan"))])
    assert d.value is None and "8 mm camera" in d.reason
    assert R.foot_radius_rule([foot(14.0, 30.0)], R0=10.0).value is None


def test_number_reads_bad_values_as_nan():
    assert R._number({"a": "2.5"}, "a") == 2.5
    assert all(math.isnan(R._number(r, "a")) for r in ({}, {"a": None}, {"a": "x"}))


def test_decision_round_trips_through_json(tmp_path):
    d = R.ring_rule([ring(3), ring(2)])
    path = tmp_path / "decision.json"
    path.write_text(d.to_json())
    back = R.decision_from_json(path)
    assert (back.parameter, back.value, back.reason) == (d.parameter, d.value, d.reason)
    assert back.evidence == d.evidence


def test_table1_row_prefers_the_full_run_and_reads_the_material(tmp_path):
    from softcrawl.studies.table1_row import QUICK_SUFFIX, fmt_value, material_of, pick_run

    for run in ("b-mat" + QUICK_SUFFIX, "a-mat" + QUICK_SUFFIX, "c-mat", "d-mat"):
        (tmp_path / "robot-rings" / run).mkdir(parents=True)
        (tmp_path / "robot-rings" / run / "decision.json").write_text("{}")
    full = pick_run(tmp_path, "robot-rings/*/decision.json")
    assert full.parent.name == "c-mat" and material_of(full) == ("c-mat", False)
    for run in ("c-mat", "d-mat"):
        (tmp_path / "robot-rings" / run / "decision.json").unlink()
    quick = pick_run(tmp_path, "robot-rings/*/decision.json")
    assert quick.parent.name == "a-mat-quick" and material_of(quick) == ("a-mat", True)
    assert pick_run(tmp_path, "nothing/*/decision.json") is None and material_of(None) == ("-", False)
    assert fmt_value(1.23456) == "1.235" and fmt_value(float("nan")) == "n/a" and fmt_value(None) == "n/a"
    assert fmt_value(float("inf")) == "n/a" and fmt_value(3) == "3" and fmt_value("x") == "x"


def test_camera_channel_exactly_at_its_bound_admits():
    bound = R.ENDOSCOPE_DIAMETER_MM / 2 + R.CHANNEL_CLEARANCE_MM - 1e-9
    assert (9.0 + bound) - 9.0 == bound  # the comparison meets equality here
    assert R.channel_admits_camera(9.0 + bound, 9.0)


def test_decisions_name_their_parameter_and_keep_their_evidence():
    none = R.ring_rule([ring(2, splay=5.0)])
    assert (none.parameter, none.value) == ("connecting rings", None)
    assert none.evidence == (
        dict(
            n_rings=2,
            theta_asym_deg=30.0,
            extension_equal_mm=10.0,
            splay_max_mm=5.0,
            arc_rms_max_mm=0.5,
            computed=True,
            combined=False,
        ),
    )
    assert R.ring_rule([ring(3)]).parameter == "connecting rings"
    d = R.foot_radius_rule([foot(16.0, 30.0), foot(12.0, 50.0), foot(14.0, 30.0)])
    assert (d.parameter, d.value) == ("foot radius d", 14.0)
    assert [e["d"] for e in d.evidence] == [12.0, 14.0, 16.0]  # sorted by d, whatever the row order
    no = R.foot_radius_rule([foot(13.0, 50.0)])
    assert (no.parameter, no.value, len(no.evidence)) == ("foot radius d", None, 1)
    assert no.reason == "no computed d leaves a channel for a 8 mm camera"


def test_the_decision_file_is_indented_json():
    text = R.ring_rule([ring(3)]).to_json()
    assert text.startswith('{\n  "parameter": "connecting rings",\n  "value": 3,')


def test_the_ring_decision_says_its_limits_and_losses():
    d = R.ring_rule([ring(3), ring(2)])
    assert d.reason == (
        "2 rings: the fewest that combine the actuators into one arc (splay 0.50 <= 1.40 mm, arc RMS "
        "0.50 <= 1.00 mm) with no more than 2 % loss of bending and extension against the best "
        "combined count; not combined: none; coupling losses: none"
    )
