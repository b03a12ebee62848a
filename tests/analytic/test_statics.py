"""ePSA statics, prototype parameters, the 60 kPa jumps, loads, friction, speed and dynamics."""

import numpy as np
import pytest

from softcrawl.analytic import dynamics, loads
from softcrawl.analytic.errors import ModelInputError
from softcrawl.analytic.prototype import EPSA_MASS_T, actuator_set, nominal_epsa, prototype_epsa
from softcrawl.analytic.statics import G_STANDARD
from softcrawl.paper import F_EPSA_MAX_N, ROBOT_MASS_T


def test_units_boundary_n_per_m_to_n_per_mm():
    a = prototype_epsa(1)
    assert a.k_p(0.0) == pytest.approx(0.2668)  # 266.8 N/m
    assert a.k_p(100.0) == pytest.approx((91.25 + 62.19) * 1e-3)
    assert a.f_p(100.0) == pytest.approx(14.63 - 6.534)
    # y = f_p/k_p in m for the printed units equals our mm value / 1000.
    y_m = (0.1463 * 100 - 6.534) / (0.9125 * 100 + 62.19)
    assert a.extension(100.0, g=0.0) == pytest.approx(1000 * y_m, rel=1e-12)


@pytest.mark.parametrize("index, jump", [(1, 0.6392), (2, -3.0035), (3, 2.5811)])
def test_jump_at_60_kpa_pinned(index, jump):
    a = prototype_epsa(index)
    lo, hi, d = a.length_jump(g=0.0)
    assert d == pytest.approx(jump, abs=1e-4)
    # both branches as evaluated by the model: P = 60 is on the lower branch (printed "P <= 60")
    assert float(a.length(60.0, g=0.0)) == pytest.approx(lo, rel=1e-14)
    assert float(a.length(60.0 + 1e-9, g=0.0)) == pytest.approx(hi, abs=1e-6)


def test_jump_with_gravity_and_nominal():
    # m g changes the jump only slightly (the k_p's differ a little between branches).
    assert prototype_epsa(1).length_jump(G_STANDARD)[2] == pytest.approx(0.6392, abs=0.1)
    assert nominal_epsa().length_jump(0.0)[2] == pytest.approx(0.1746, abs=1e-4)


def test_statics_values_and_mass():
    a = prototype_epsa(1)
    assert a.mass == pytest.approx(70.2e-6 / 3)
    assert float(a.length(100.0, g=0.0)) == pytest.approx(152.763, abs=1e-3)
    with_g = float(a.length(100.0))
    assert with_g == pytest.approx(100 + (8.096 - EPSA_MASS_T * 9810) / 0.15344, rel=1e-9)
    assert float(a.blocked_force(100.0, g=0.0)) == pytest.approx(8.096)
    with pytest.raises(ModelInputError) as e:
        a.length(-5.0)
    assert e.value.parameter == "pressure"


@pytest.mark.parametrize("index", [1, 2, 3])
def test_inverse_statics_roundtrip_and_jump_policy(index):
    a = prototype_epsa(index)
    for p in np.linspace(0.0, 100.0, 41):
        length = float(a.length(p, g=0.0))
        q = a.pressure_for_length(length, g=0.0)
        assert float(a.length(q, g=0.0)) == pytest.approx(length, abs=1e-9)
        assert q <= p + 1e-9  # the smallest pressure wins
    lo, hi, d = a.length_jump(0.0)
    if d > 0:  # a length inside the gap maps to the breakpoint, or raises when strict
        assert a.pressure_for_length(0.5 * (lo + hi), g=0.0) == 60.0
        with pytest.raises(ModelInputError):
            a.pressure_for_length(0.5 * (lo + hi), g=0.0, strict=True)
    else:  # a length reached twice takes the lower branch
        assert a.pressure_for_length(0.5 * (lo + hi), g=0.0) < 60.0
    with pytest.raises(ModelInputError) as e:
        a.pressure_for_length(200.0, g=0.0)
    assert e.value.parameter == "length"


def test_theoretical_load_eq27():
    assert loads.theoretical_load(F_EPSA_MAX_N, ROBOT_MASS_T, 10000.0) * 1e3 == pytest.approx(2.456, abs=5e-4)
    assert loads.theoretical_load(F_EPSA_MAX_N, ROBOT_MASS_T, 9810.0) * 1e3 == pytest.approx(2.505, abs=5e-4)
    assert loads.theoretical_load(8.42, 70.2e-6, 10000.0) == pytest.approx(2.4558e-3, rel=1e-12)


def test_friction_eq26_consistent_with_eq25():
    a = prototype_epsa(2)
    f_mu = 1.7
    y_out = float(a.extension(80.0, g=0.0))
    y_in = float(loads.extension_with_friction(a, 80.0, f_mu))
    assert float(loads.friction_from_extensions(a.k_p(80.0), y_out, y_in)) == pytest.approx(f_mu)


def test_crawl_speed_estimate():
    acts = actuator_set("nominal")
    free = loads.crawl_speed(acts, 100.0, 0.0)
    assert free.stride_mm == pytest.approx(53.22, abs=0.01)
    assert free.speed_mm_s == pytest.approx(26.61, abs=0.01)
    paper = loads.crawl_speed(acts, 100.0, 15.3)
    assert 9.0 < paper.speed_mm_s < 10.0  # the paper measured 18.3 mm/s: see the report
    f = loads.friction_for_speed(acts, 100.0, 18.3)
    assert loads.crawl_speed(acts, 100.0, f).speed_mm_s == pytest.approx(18.3, rel=1e-9)


def test_dynamics_settles_to_statics():
    a = prototype_epsa(1)
    r = dynamics.step_response(a, 80.0, duration_s=4.0)
    assert r.y[-1] == pytest.approx(float(a.extension(80.0)), rel=1e-3)
    assert r.y[0] == pytest.approx(float(a.extension(0.0)))
    g = dynamics.gait_response(a, 100.0, cycles=2)
    assert g.t[-1] == pytest.approx(4.0)
    assert g.y.max() < float(a.extension(100.0)) + 1e-6


def test_gait_stride_below_static_stride():
    a = nominal_epsa()
    dyn = dynamics.gait_stride(a, 100.0, 1.5, 0.5, cycles=2)
    static = float(a.extension(100.0, 0.0) - a.extension(0.0, 0.0))
    assert 0.8 * static < dyn < static
