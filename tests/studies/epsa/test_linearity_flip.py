"""The linearity claim at the flip (issue 32): `nonlinearity` against a hand-computed value, and
`linearity_claim` decided by each clause alone (closer to linear or not, the N = 0 curve, enough
common points)."""

import pytest

from softcrawl.studies.epsa import linearity as L
from softcrawl.studies.epsa.rules import DesignCurve


def curve(lengths, pressures=(20.0, 40.0), length0=100.0):
    return DesignCurve(
        value=0.0,
        trial_status="completed",
        reason="",
        limit_pressure=None,
        length0=length0,
        radius0=9.0,
        pressures=list(pressures),
        lengths=list(lengths),
        radii=[9.0] * len(lengths),
        path=[],
    )


def test_nonlinearity_by_hand():
    # points (0, 100), (20, 101), (40, 104): line fit slope 0.1, residuals 1/3, -2/3, 1/3
    c = curve((101.0, 104.0))
    rms = ((1 / 9 + 4 / 9 + 1 / 9) / 3) ** 0.5
    assert L.nonlinearity(c) == pytest.approx(rms / 4.0, rel=1e-12)
    assert L.nonlinearity(curve((102.0, 104.0))) == pytest.approx(0.0, abs=1e-12)
    assert L.nonlinearity(c, up_to_kpa=20.0) is None  # two points only
    assert L.nonlinearity(c, up_to_kpa=40.0 - 1e-10) == L.nonlinearity(c)  # within the 1e-9 margin
    assert L.nonlinearity(curve((100.0, 100.0))) is None  # no extension
    shrink = curve((99.0, 96.0))
    assert L.nonlinearity(shrink) == pytest.approx(rms / 4.0, rel=1e-12)  # |extension|


def rows_of(curves):
    """Rows of the grid study as `design_curves` reads them: fiber_turns, pressure, length."""
    out = []
    for n, (pressures, lengths) in curves.items():
        out.append(
            {
                "fiber_turns": n,
                "pressure_kpa": 0.0,
                "length_mm": 100.0,
                "outer_radius_mm": 9.0,
                "row_status": "reference",
            }
        )
        for p, x in zip(pressures, lengths):
            out.append(
                {
                    "fiber_turns": n,
                    "pressure_kpa": p,
                    "length_mm": x,
                    "outer_radius_mm": 9.0,
                    "row_status": "converged",
                }
            )
    return out


P3 = (20.0, 40.0, 60.0)


def test_claim_holds_only_when_every_fibered_design_is_closer():
    bare = (P3, (101.0, 104.0, 109.0))
    straight = (P3, (101.0, 102.0, 103.0))
    bent = (P3, (101.0, 105.0, 112.0))
    s = L.linearity_claim(rows_of({0.0: bare, 3.0: straight}))
    assert s.value == 1.0 and "holds" in s.reason and "not" not in s.reason
    s = L.linearity_claim(rows_of({0.0: bare, 3.0: straight, 5.0: bent}))
    assert s.value == 0.5 and "does not hold" in s.reason
    assert any("not closer to linear" in e for e in s.evidence)
    assert L.linearity_claim(rows_of({0.0: bare, 5.0: bent})).value == 0.0
    same = L.linearity_claim(rows_of({0.0: bare, 3.0: bare}))
    assert same.value == 0.0  # equal is not closer (<, not <=)


def test_common_pressures_bound_the_comparison():
    bare = ((20.0, 40.0), (101.0, 104.0))
    long = (P3, (101.0, 102.0, 200.0))  # linear up to 40 kPa, far off at 60
    s = L.linearity_claim(rows_of({0.0: bare, 3.0: long}))
    assert s.value == 1.0 and "up to 40 kPa" in s.evidence[0]


def test_without_the_unreinforced_curve_or_comparable_curves_it_is_undetermined():
    s = L.linearity_claim(rows_of({3.0: (P3, (101.0, 102.0, 103.0))}))
    assert s.value is None and s.status == "undetermined"
    short = ((20.0,), (101.0,))
    s = L.linearity_claim(rows_of({0.0: (P3, (101.0, 104.0, 109.0)), 3.0: short}))
    assert s.value is None and "fewer than 3 common points" in s.evidence[0]
    s = L.linearity_claim(rows_of({0.0: (P3, (101.0, 104.0, 109.0))}))
    assert s.value is None and s.reason == "no comparable curves"


RULE = "each fibered design's nonlinearity below the unreinforced (N = 0) one's over their common pressures"


def test_nonlinearity_margins_and_a_small_extension():
    c = curve((101.0, 104.0))
    # the 1e-9 kPa margin is inclusive, and not wider
    assert L.nonlinearity(c, up_to_kpa=40.0 - 1e-9) == L.nonlinearity(c)
    wide = curve((101.0, 104.0, 109.0), pressures=(20.0, 40.0, 40.5))
    assert L.nonlinearity(wide, up_to_kpa=40.0) == L.nonlinearity(c)
    # an extension under 1 mm is still an extension: (0, 100), (20, 100.1), (40, 100.4)
    small = curve((100.1, 100.4))
    # residuals 1/30, -2/30, 1/30 mm about the line of slope 0.01 mm/kPa
    assert L.nonlinearity(small) == pytest.approx(((1 + 4 + 1) / 900 / 3) ** 0.5 / 0.4, rel=1e-9)


def test_the_claims_selections_in_full():
    bare = (P3, (101.0, 104.0, 109.0))
    none = L.linearity_claim(rows_of({3.0: (P3, (101.0, 102.0, 103.0))}))
    assert none == L.Selection("linearity", None, RULE, (), "undetermined", "no unreinforced (N = 0) curve")
    short = ((20.0,), (101.0,))
    few = L.linearity_claim(rows_of({0.0: bare, 3.0: short}))
    assert few == L.Selection(
        "linearity",
        None,
        RULE,
        ("N = 3: fewer than 3 common points up to 20 kPa",),
        "undetermined",
        "no comparable curves",
    )
    # a design without enough common points is skipped, the next one still compared
    straight = (P3, (101.0, 102.0, 103.0))
    both = L.linearity_claim(rows_of({0.0: bare, 2.0: short, 3.0: straight}))
    assert both.value == 1.0 and len(both.evidence) == 2
    # the bare curve short of points, the fibered one not: not comparable either
    s = L.linearity_claim(rows_of({0.0: short, 3.0: straight}))
    assert s.value is None and s.reason == "no comparable curves"
    held = L.linearity_claim(rows_of({0.0: bare, 3.0: straight}))
    mine = L.nonlinearity(L.design_curves(rows_of({3.0: straight}), "fiber_turns")[3.0], 60.0)
    assert held.parameter == "linearity" and held.rule == RULE and held.status == "selected"
    assert held.reason == "the paper's claim holds"
    assert held.evidence[0].startswith(f"N = 3: nonlinearity {mine:.3g} vs N = 0 ")
    assert held.evidence[0].endswith(" up to 60 kPa -> closer to linear")
    bent = (P3, (101.0, 105.0, 112.0))
    half = L.linearity_claim(rows_of({0.0: bare, 3.0: straight, 5.0: bent}))
    assert half.reason == "the paper's claim does not hold for every design"
    assert half.evidence[1].endswith(" up to 60 kPa -> not closer to linear")


def test_the_reference_is_bounded_by_the_common_pressures_too():
    bare = (P3, (101.0, 102.0, 150.0))  # linear up to 40 kPa, far off at 60
    short = ((20.0, 40.0), (101.0, 103.0))  # a bend below 40 kPa
    s = L.linearity_claim(rows_of({0.0: bare, 3.0: short}))
    assert s.value == 0.0 and s.evidence[0].endswith("up to 40 kPa -> not closer to linear")
    # an unreinforced curve with no extension has no nonlinearity: nothing to compare
    flat = (P3, (100.0, 100.0, 100.0))
    s = L.linearity_claim(rows_of({0.0: flat, 3.0: (P3, (101.0, 102.0, 103.0))}))
    assert s.value is None and s.evidence == ("N = 3: fewer than 3 common points up to 60 kPa",)
    # equal curves: not closer, and the evidence says so
    same = L.linearity_claim(rows_of({0.0: bare, 3.0: bare}))
    assert same.evidence[0].endswith("-> not closer to linear")
