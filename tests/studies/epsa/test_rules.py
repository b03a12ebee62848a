"""Selection rules of Table 1 on synthetic study tables (no FE)."""

from __future__ import annotations

import pytest

from softcrawl.studies.epsa import linearity, rules


def _rows(
    param,
    value,
    lengths,
    radii,
    *,
    status="completed",
    limit=None,
    reason="",
    pressures=(20, 40, 60, 80, 100),
):
    out = []
    for i, p in enumerate(pressures):
        ok = i < len(lengths)
        out.append(
            {
                param: str(value),
                "length": "100",
                "outer_radius": "9",
                "trial_status": status,
                "reason": reason,
                "limit_pressure_kpa": "" if limit is None else str(limit),
                "pressure_kpa": str(float(p)),
                "length_mm": str(lengths[i]) if ok else "",
                "outer_radius_mm": str(radii[i]) if ok else "",
                "row_status": "converged" if ok else "failed",
            }
        )
    return out


def _linear(slope, start=100.0, n=5):
    return [start + slope * 20 * (i + 1) for i in range(n)]


def paper_like_chamber_rows():
    rows = []
    rows += _rows("chamber_radius", 2, [101, 103.5, 104, 107, 107.5], _linear(0.002, 9))
    rows += _rows("chamber_radius", 3, _linear(0.1), _linear(0.01, 9))
    rows += _rows("chamber_radius", 4, [102, 106, 107, 112, 113], _linear(0.02, 9))
    rows += _rows("chamber_radius", 5, _linear(0.2, n=4), _linear(0.03, 9, 4), limit=80)
    rows += _rows(
        "chamber_radius",
        6,
        _linear(0.3, n=2),
        _linear(0.05, 9, 2),
        status="failed",
        reason="diverged: Newton failed at 60 kPa",
    )
    return rows


def test_chamber_radius_rule_reproduces_the_paper_reasoning():
    sel = rules.select_chamber_radius(paper_like_chamber_rows())
    assert sel.value == 3.0 and sel.status == "selected"
    text = "\n".join(sel.evidence)
    assert "r = 5: does not withstand: limit point at 80 kPa" in text
    sel = rules.select_chamber_radius(paper_like_chamber_rows(), mu=0.03)
    assert "would withstand 100 kPa for mu >= 0.0375 MPa" in "\n".join(sel.evidence)
    assert "r = 6: does not withstand: diverged" in text
    assert "r = 2: withstands; fluctuating" in text and "r = 4: withstands; fluctuating" in text


def test_chamber_radius_follows_the_data():
    rows = [r for r in paper_like_chamber_rows() if r["chamber_radius"] != "2"]
    rows += _rows("chamber_radius", 2, _linear(0.05), _linear(0.001, 9))  # now smooth
    assert rules.select_chamber_radius(rows).value == 2.0
    rows = [r for r in paper_like_chamber_rows() if r["chamber_radius"] != "3"]
    sel = rules.select_chamber_radius(rows)
    assert sel.value is None and sel.status == "undetermined" and "all fluctuate" in sel.reason
    assert rules.select_chamber_radius([]).status == "undetermined"
    rows = _rows("chamber_radius", 2, _linear(0.1, n=2), _linear(0.01, 9, 2), limit=34.1)
    rows += _rows("chamber_radius", 3, _linear(0.1, n=1), _linear(0.01, 9, 1), limit=25.0)
    sel = rules.select_chamber_radius(rows, mu=0.03)
    assert sel.value is None and sel.reason == "no studied radius withstands 100 kPa"
    assert "limit point at 25 kPa (would withstand 100 kPa for mu >= 0.12 MPa)" in sel.evidence[1]


def fiber_rows(ext=None):
    ext = ext or {0: 15.0, 10: 20.0, 20: 24.0, 25: 24.5, 50: 25.0}
    rows = []
    for n, e in ext.items():
        rows += _rows("fiber_turns", n, _linear(e / 100), _linear(0.01 / (1 + n), 9))
    return rows


def test_fiber_turns_rule_and_its_dependence_on_the_data():
    sel = rules.select_fiber_turns(fiber_rows())
    assert sel.value == 20.0
    assert (
        rules.select_fiber_turns(fiber_rows({0: 15.0, 10: 23.0, 20: 24.0, 25: 24.5, 50: 25.0})).value == 10.0
    )
    assert (
        rules.select_fiber_turns(fiber_rows({0: 15.0, 10: 20.0, 20: 21.0, 25: 24.5, 50: 25.0})).value == 25.0
    )
    # a curved response is still admissible: the rule is about extension, not an R^2 threshold
    rows = [r for r in fiber_rows() if r["fiber_turns"] != "20"]
    rows += _rows("fiber_turns", 20, [101, 104, 110, 116, 124], _linear(0.001, 9))
    assert rules.select_fiber_turns(rows).value == 20.0
    # without the most-turned design there is no reference
    rows = [r for r in fiber_rows() if r["fiber_turns"] != "50"]
    rows += _rows("fiber_turns", 50, [], [], status="failed", reason="diverged")
    sel = rules.select_fiber_turns(rows)
    assert sel.value is None and "N = 50" in sel.reason


@pytest.mark.parametrize(
    "lengths, expected",
    [
        ([102, 104, 106, 108, 110], False),  # linear
        ([101, 103, 106, 110, 115], False),  # softening
        ([105, 109, 112, 114, 115], False),  # stiffening
        ([101, 103.5, 104, 107, 107.5], True),  # alternating slope
        ([102, 104, 103, 105, 107], True),  # length drops
    ],
)
def test_fluctuation_definition(lengths, expected):
    assert _fluctuating(lengths) is expected


def _fluctuating(lengths, pressures=None):
    pressures = pressures or tuple(20 * (i + 1) for i in range(len(lengths)))
    rows = _rows("chamber_radius", 3, lengths, [9.0] * len(lengths), pressures=pressures)
    return rules.fluctuation(rules.design_curves(rows, "chamber_radius")[3.0])[0]


# ---- boundary tests: exactly at, just below and just above every named threshold (issue 19) ----


@pytest.mark.parametrize(
    "lengths, changes",
    [
        ([101, 103, 106, 108, 110], 1),  # increments 1, 2, 3, 2, 2: one trend change
        ([101, 103, 104, 107, 110], 2),  # 1, 2, 1, 3, 3: exactly FLUCTUATION_SIGN_CHANGES
        ([101, 103, 104, 107, 108, 111], 3),  # 1, 2, 1, 3, 1, 3: three
    ],
)
def test_trend_changes_boundary(lengths, changes):
    """Fluctuating iff the trend changes at least FLUCTUATION_SIGN_CHANGES (= 2) times; the
    threshold moved by one each way moves the verdict of the curve sitting on it."""
    assert rules.FLUCTUATION_SIGN_CHANGES == 2
    assert _fluctuating(lengths) is (changes >= 2)


def test_trend_changes_threshold_is_inclusive(monkeypatch):
    on_boundary = [101, 103, 104, 107, 110]  # exactly 2 changes
    monkeypatch.setattr(rules, "FLUCTUATION_SIGN_CHANGES", 3)
    assert _fluctuating(on_boundary) is False
    monkeypatch.setattr(rules, "FLUCTUATION_SIGN_CHANGES", 2)
    assert _fluctuating(on_boundary) is True


@pytest.mark.parametrize("step, expected", [(0.2499, False), (0.25, False), (0.2501, True)])
def test_fluctuation_tolerance_boundary(monkeypatch, step, expected):
    """Increments 4, 4 - s, 4, 4 - s, 4 alternate by s; with FLUCTUATION_REL_TOL x 4 = 0.25
    (binary exact) a trend change must exceed the tolerance: at it or below it is noise."""
    monkeypatch.setattr(rules, "FLUCTUATION_REL_TOL", 0.0625)
    increments = [4.0, 4.0 - step, 4.0, 4.0 - step, 4.0]
    lengths, total = [], 100.0
    for d in increments:
        total += d
        lengths.append(total)
    assert _fluctuating(lengths) is expected


def test_decreasing_length_boundary(monkeypatch):
    monkeypatch.setattr(rules, "FLUCTUATION_REL_TOL", 0.0625)  # tol = 0.25 of the largest step 4
    curve = lambda drop: rules.design_curves(  # noqa: E731
        _rows(
            "chamber_radius",
            3,
            [104.0, 108.0, 108.0 - drop, 112.0 - drop],
            [9.0] * 4,
            pressures=(20, 40, 60, 80),
        ),
        "chamber_radius",
    )[3.0]
    assert "decreases" in rules.fluctuation(curve(0.2501))[1]
    assert "decreases" not in rules.fluctuation(curve(0.25))[1]
    assert "decreases" not in rules.fluctuation(curve(0.2499))[1]


@pytest.mark.parametrize("ext20, chosen", [(17.99, 25.0), (18.0, 20.0), (18.01, 20.0)])
def test_similar_extension_boundary(ext20, chosen):
    """N = 50 extends 20 mm: N = 20 differs little at 18 mm (exactly 10 % short) and above, not
    below; N = 25 (19.5 mm) is always within."""
    assert rules.SIMILAR_EXTENSION_REL == 0.10
    rows = fiber_rows({0: 10.0, 10: 15.0, 20: ext20, 25: 19.5, 50: 20.0})
    assert rules.select_fiber_turns(rows).value == chosen


def test_similar_extension_sensitivity_is_reported_not_used():
    rows = fiber_rows({0: 10.0, 10: 16.5, 20: 18.5, 25: 19.5, 50: 20.0})
    assert rules.fiber_turns_sensitivity(rows) == {0.05: 25.0, 0.10: 20.0, 0.20: 10.0}
    assert rules.select_fiber_turns(rows).value == 20.0


@pytest.mark.parametrize("limit, withstands", [(99.9, False), (100.0, True), (100.1, True), (None, True)])
def test_target_pressure_boundary(limit, withstands):
    """A limit point at the target still reaches it (the state at 100 kPa is computed); one
    just below does not."""
    assert rules.TARGET_PRESSURE_KPA == 100.0
    rows = _rows("chamber_radius", 3, _linear(0.1), _linear(0.01, 9), limit=limit)
    assert rules.design_curves(rows, "chamber_radius")[3.0].withstands is withstands


def test_no_state_at_the_target_does_not_withstand():
    rows = _rows("chamber_radius", 3, _linear(0.1, n=4), _linear(0.01, 9, 4))
    assert rules.design_curves(rows, "chamber_radius")[3.0].withstands is False


def test_nonlinearity_measure():
    """0 for a straight line, the exact value for a parabola, None below LINEARITY_MIN_POINTS."""
    straight = rules.design_curves(_rows("fiber_turns", 20, _linear(0.1), [9.0] * 5), "fiber_turns")[20.0]
    assert linearity.nonlinearity(straight) == pytest.approx(0.0, abs=1e-12)
    # L = 100 + p^2/1000 at p = 0, 20, ..., 100: residuals of the LSQ line, RMS / extension 10 mm
    parab = [100 + (20 * (i + 1)) ** 2 / 1000 for i in range(5)]
    curve = rules.design_curves(_rows("fiber_turns", 20, parab, [9.0] * 5), "fiber_turns")[20.0]
    p = [0, 20, 40, 60, 80, 100]
    y = [q * q / 1000 for q in p]
    mp, my = sum(p) / 6, sum(y) / 6
    slope = sum((a - mp) * (b - my) for a, b in zip(p, y)) / sum((a - mp) ** 2 for a in p)
    rms = (sum((b - my - slope * (a - mp)) ** 2 for a, b in zip(p, y)) / 6) ** 0.5
    assert linearity.nonlinearity(curve) == pytest.approx(rms / 10.0, rel=1e-12)
    assert linearity.LINEARITY_MIN_POINTS == 3
    assert linearity.nonlinearity(curve, up_to_kpa=20) is None  # 2 points: (0, L0), (20, L)
    assert linearity.nonlinearity(curve, up_to_kpa=40) is not None  # 3 points


def test_linearity_claim_is_relative_to_the_unreinforced_actuator():
    """The claim holds when every fibered curve is straighter than N = 0's (over the pressures
    both reached), and fails for a fibered curve more curved than N = 0's."""
    bare = _rows("fiber_turns", 0, [101, 103, 108, 116], [9.5] * 4, pressures=(20, 40, 60, 80), limit=90)
    straight = _rows("fiber_turns", 20, _linear(0.2), [9.0] * 5)
    sel = linearity.linearity_claim(bare + straight)
    assert sel.value == 1.0 and "holds" in sel.reason
    assert "up to 80 kPa" in sel.evidence[0]
    curved = _rows("fiber_turns", 25, [100.2, 100.5, 104, 115, 130], [9.0] * 5)
    sel = linearity.linearity_claim(bare + straight + curved)
    assert sel.value == 0.5 and "not closer to linear" in sel.evidence[1]
    assert linearity.linearity_claim(straight).status == "undetermined"


def test_chamber_radius_selection_in_full():
    """Every field of the selection and each evidence line from its own branch (issue 32)."""
    R = rules.CHAMBER_RADIUS_RULE
    assert rules.select_chamber_radius([]) == rules.Selection(
        "chamber_radius", None, R, (), "undetermined", "no chamber-radius study data"
    )
    rows = _rows("chamber_radius", 3, _linear(0.1), _linear(0.01, 9))  # 110 mm and 10 mm at 100 kPa
    sel = rules.select_chamber_radius(rows)
    assert (sel.parameter, sel.value, sel.rule, sel.status) == ("chamber_radius", 3.0, R, "selected")
    assert sel.reason == "r = 3 mm: smallest radial expansion (1 mm) of 1 admissible radii"
    assert sel.evidence[0].startswith("r = 3: withstands; not fluctuating (")
    assert sel.evidence[0].endswith("); extension 10 mm, radial expansion 1 mm")
    # each way of not withstanding, with its own words
    rows = _rows(
        "chamber_radius", 2, _linear(0.1, n=2), _linear(0.01, 9, 2), status="failed", limit=50, reason="x"
    )
    rows += _rows("chamber_radius", 3, [], [], status="running")
    rows += _rows("chamber_radius", 4, _linear(0.1, n=4), _linear(0.01, 9, 4))
    rows += _rows("chamber_radius", 5, _linear(0.1, n=1), _linear(0.01, 9, 1), limit=0.5)
    sel = rules.select_chamber_radius(rows, mu=0.03)
    assert sel == rules.Selection(
        "chamber_radius",
        None,
        R,
        (
            "r = 2: does not withstand: diverged/failed after 40 kPa (x)",
            "r = 3: does not withstand: no result (running)",
            "r = 4: does not withstand: no computed state at 100 kPa",
            "r = 5: does not withstand: limit point at 0.5 kPa (would withstand 100 kPa for mu >= 6 MPa)",
        ),
        "undetermined",
        "no studied radius withstands 100 kPa",
    )
    # a limit point at 0 kPa says nothing about the modulus that would withstand the target
    zero = rules.select_chamber_radius(_rows("chamber_radius", 5, [], [], limit=0.0), mu=0.03)
    assert zero.evidence == ("r = 5: does not withstand: limit point at 0 kPa",)


def test_input_and_pending_selections():
    assert rules.input_parameter("wall", 2.5, "paper Table 1") == rules.Selection(
        "wall",
        2.5,
        "input of the paper's FE model, not selected by a study",
        ("paper Table 1",),
        status="input",
        reason="fixed input (paper Section V-A); no study selects it",
    )
    assert rules.pending("rings", "run it") == rules.Selection(
        "rings", None, "not implemented", (), status="pending", reason="run it"
    )


def test_sensitivity_without_the_most_turns_is_undetermined():
    rows = fiber_rows({0: 10.0, 10: 16.5})
    rows += _rows("fiber_turns", 50, _linear(0.1, n=2), _linear(0.01, 9, 2), status="failed")
    assert rules.fiber_turns_sensitivity(rows) == {0.05: None, 0.10: None, 0.20: None}
    assert rules.fiber_turns_sensitivity([]) == {0.05: None, 0.10: None, 0.20: None}


def test_fiber_turns_selection_in_full():
    R = rules.FIBER_TURNS_RULE
    assert rules.select_fiber_turns([]) == rules.Selection(
        "fiber_turns", None, R, (), "undetermined", "no fiber-turns study data"
    )
    # extensions at 100 kPa: N = 0 -> 15, 10 -> 20, 20 -> 22.5 (exactly 10 % below), 50 -> 25 mm;
    # radial expansions 1 / (1 + N) mm; N = 25 stops at a limit point, N = 30 fails
    rows = []
    for n, e in {0: 15.0, 10: 20.0, 20: 22.5, 50: 25.0}.items():
        rows += _rows("fiber_turns", n, [100.0 + e * k / 5 for k in range(1, 6)], _linear(0.01 / (1 + n), 9))
    rows += _rows("fiber_turns", 25, _linear(0.2, n=3), _linear(0.01, 9, 3), limit=70)
    rows += _rows(
        "fiber_turns", 30, _linear(0.2, n=2), _linear(0.01, 9, 2), status="failed", reason="diverged"
    )
    sel = rules.select_fiber_turns(rows)
    assert (sel.parameter, sel.value, sel.rule, sel.status) == ("fiber_turns", 20.0, R, "selected")
    assert sel.reason == "N = 20: fewest turns within 10% of N = 50"
    assert sel.evidence == (
        "N = 25: does not reach 100 kPa (limit point at 70 kPa)",
        "N = 30: does not reach 100 kPa (failed after 40 kPa: diverged)",
        "N = 0: extension 15 mm (-40.0% vs N = 50), radial expansion 1 mm -> differs",
        "N = 10: extension 20 mm (-20.0% vs N = 50), radial expansion 0.0909 mm -> differs",
        "N = 20: extension 22.5 mm (-10.0% vs N = 50), radial expansion 0.0476 mm -> differs little",
        "N = 50: extension 25 mm (+0.0% vs N = 50), radial expansion 0.0196 mm -> differs little",
    )
    # the most-turned design without a state at the target: undetermined, with the evidence
    failed = [r for r in rows if r["fiber_turns"] != "50"]
    failed += _rows("fiber_turns", 50, _linear(0.2, n=2), _linear(0.01, 9, 2), status="failed", reason="")
    sel = rules.select_fiber_turns(failed)
    assert (sel.parameter, sel.value, sel.rule, sel.status) == ("fiber_turns", None, R, "undetermined")
    assert sel.reason == "the most-turned design N = 50 has no result at 100 kPa to compare with"
    assert sel.evidence[-1] == "N = 50: does not reach 100 kPa (failed after 40 kPa:)"
    # a reference that does not extend: every design is compared at +0.0 %
    flat = _rows("fiber_turns", 10, [100.0] * 5, [9.0] * 5) + _rows("fiber_turns", 50, [100.0] * 5, [9.0] * 5)
    sel = rules.select_fiber_turns(flat)
    assert sel.value == 10.0 and sel.evidence[0].startswith("N = 10: extension 0 mm (+0.0% vs N = 50)")


def test_design_curves_read_each_column_from_its_row():
    def state(p, x, y, status):
        return {"n": "3", "pressure_kpa": p, "length_mm": x, "outer_radius_mm": y, "row_status": status}

    rows = [
        {"length": "120", "outer_radius": "10"} | state("20", "121", "10.1", "converged"),
        {"length": "100", "outer_radius": "9"} | state("", "1", "1", "converged"),  # no pressure: skipped
        state("40", "123", "10.3", "volume-control"),
        state("30", "122", "10.2", "converged"),
        state("50", "9", "9", "failed"),
    ]
    c = rules.design_curves(rows, "n")[3.0]
    assert c.value == 3.0 and (c.length0, c.radius0) == (120.0, 10.0)  # the first row's design
    assert (c.trial_status, c.reason) == ("", "")
    assert c.pressures == [20.0, 30.0] and c.lengths == [121.0, 122.0]  # pressure control only
    assert [p for p, *_ in c.path] == [20.0, 40.0, 30.0]  # every computed state, in solution order
    ref = [
        {
            "n": "1",
            "pressure_kpa": "0",
            "length_mm": "99",
            "outer_radius_mm": "8.5",
            "row_status": "reference",
        }
    ]
    c = rules.design_curves(ref, "n")[1.0]
    assert (c.length0, c.radius0) == (99.0, 8.5)  # the evaluator's own 0 kPa state
    bare = rules.design_curves([{"n": "2", "reason": None}], "n")[2.0]
    assert (bare.length0, bare.radius0, bare.reason) == (100.0, 9.0, "")  # the Table 1 design
    with pytest.raises(ValueError, match=r"row without a numeric 'n': \{'n': 'x'\}"):
        rules.design_curves([{"n": "x"}], "n")


def test_fluctuation_words_and_its_two_increment_minimum():
    def c(lengths):
        return rules.design_curves(_rows("r", 1, lengths, [9.0] * len(lengths)), "r")[1.0]

    assert rules.fluctuation(c([101.0])) == (False, "too few points to judge")
    assert rules.fluctuation(c([101.0, 102.0]))[0] is False
    assert rules.fluctuation(c([101.0, 100.0])) == (True, "length decreases between two pressure steps")
    assert rules.fluctuation(c([101.0, 103.0]))[1] == "monotone, 0 change(s) of slope trend"
