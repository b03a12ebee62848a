"""The paper's-material scan: the Neo-Hookean window follows from P_lim = k_r mu (closed-end tube
theory), a stiffening shape removes limit points, and the r = 5 / r = 6 ratio explains why no
shape reproduces every Fig. 8 observation."""

from __future__ import annotations

import pytest

from softcrawl.fem.laws import Gent, NeoHookean
from softcrawl.fem.tube_theory import closed_end_limit
from softcrawl.studies.material import paper_material as PM


def test_neo_hookean_window_is_the_intersection_of_the_observations():
    w = PM.shape_window("neo-hookean", "-", NeoHookean(mu=1.0, bulk=1000.0))
    k4, k5, k6 = (closed_end_limit(NeoHookean(mu=1.0, bulk=1000.0), r, 9.0)[1] for r in (4.0, 5.0, 6.0))
    assert w.withstand_mu[0] == pytest.approx(0.1 / k4, rel=1e-9)  # r = 4 is the binding radius
    assert w.fail_mu[5.0] == pytest.approx((0.08 / k5, 0.1 / k5), rel=1e-9)
    assert w.window_all is None  # r = 5 and r = 6 cannot both fail in [80, 100) kPa
    assert w.window_r5 == pytest.approx((0.08 / k5, 0.1 / k5), rel=1e-9)
    assert w.window_r5[0] == pytest.approx(0.1818, abs=5e-4) and w.window_r5[1] == pytest.approx(
        0.2272, abs=5e-4
    )
    assert w.centre == pytest.approx(0.2045, abs=5e-4)


def test_a_stiff_gent_shape_has_no_limit_at_small_radii_and_no_window():
    w = PM.shape_window("gent", "Jm=20", Gent(mu=1.0, jm=20.0, bulk=1000.0))
    assert w.k[2.0] is None and w.k[5.0] is None and w.k[6.0] is not None
    assert w.window_all is None and w.window_r5 is None and w.centre is None
    assert "<= 1.25" in PM.why_not_all([w, PM.shape_window("neo-hookean", "-", NeoHookean(mu=1.0, bulk=1e3))])


def test_the_tube_length_does_not_fluctuate_at_the_window_centre():
    from softcrawl.studies.epsa import rules

    lengths = PM.length_curve(NeoHookean(mu=1.0, bulk=1000.0), 0.2045, 4.0)
    assert len(lengths) == 5 and all(b > a for a, b in zip([100.0] + lengths, lengths))
    curve = rules.DesignCurve(
        4.0, "completed", "", None, 100.0, 9.0, [20, 40, 60, 80, 100], lengths, [9.0] * 5
    )
    assert rules.fluctuation(curve)[0] is False
