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
