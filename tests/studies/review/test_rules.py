"""Selection rules of Table 1 on synthetic study tables (no FE)."""

from __future__ import annotations

import pytest

from studies.review import rules


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
    # a curved (non-linear) response is not admissible
    rows = [r for r in fiber_rows() if r["fiber_turns"] != "20"]
    rows += _rows("fiber_turns", 20, [101, 104, 110, 116, 124], _linear(0.001, 9))
    assert rules.select_fiber_turns(rows).value == 25.0
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
    curve = rules.design_curves(_rows("chamber_radius", 3, lengths, _linear(0.01, 9)), "chamber_radius")[3.0]
    assert rules.fluctuation(curve)[0] is expected


def test_linearity():
    curve = rules.design_curves(_rows("fiber_turns", 20, _linear(0.1), _linear(0.01, 9)), "fiber_turns")[20.0]
    assert rules.linearity_r2(curve) == pytest.approx(1.0)
