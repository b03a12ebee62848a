"""Identification recovers known k_p, f_p from noisy synthetic data (paper Section VII-A)."""

import numpy as np
import pytest

from softcrawl.analytic.errors import ModelInputError
from softcrawl.analytic.identification import fit_piecewise, identify, synthetic_table
from softcrawl.analytic.prototype import prototype_epsa

PRESSURES = np.arange(10.0, 101.0, 10.0)  # the paper's 10 kPa steps
LOADS = [0.0, 0.5, 1.0, 2.0]  # N


@pytest.mark.parametrize("index", [1, 2, 3])
def test_recovers_prototype_parameters_with_noise(index):
    """Tolerance: 0.2 mm noise, 3 repeats, 4 loads -> k_p within 4 %, f_p within 4 % + 0.03 N.

    Over 600 seeds (200 per actuator) the worst k_p error was 3.6 % (95th percentile 2.5 %).
    """
    a = prototype_epsa(index)
    P, W, y = synthetic_table(a, PRESSURES, LOADS, repeats=3, noise_mm=0.2, seed=index)
    r = identify(P, W, y, mass_t=a.mass)
    np.testing.assert_allclose(r.k_p(PRESSURES), a.k_p(PRESSURES), rtol=0.04)
    np.testing.assert_allclose(r.f_p(PRESSURES), a.f_p(PRESSURES), rtol=0.04, atol=0.03)
    # step 1 alone is exact without noise
    P0, W0, y0 = synthetic_table(a, PRESSURES, LOADS)
    r0 = identify(P0, W0, y0, mass_t=a.mass)
    np.testing.assert_allclose(r0.per_pressure.k_p, a.k_p(PRESSURES), rtol=1e-10)
    np.testing.assert_allclose(r0.k_p.high.slope, a.k_p.high.slope, rtol=1e-8)
    np.testing.assert_allclose(r0.f_p.low.intercept, a.f_p.low.intercept, atol=1e-10)


def test_fitted_breakpoint_is_60():
    a = prototype_epsa(2)
    P, W, y = synthetic_table(a, PRESSURES, LOADS, repeats=3, noise_mm=0.05, seed=7)
    r = identify(P, W, y, mass_t=a.mass, breakpoint=None)
    assert r.k_p.breakpoint_kpa == 60.0
    assert r.f_p.breakpoint_kpa == 60.0


def test_single_line_and_errors():
    x = np.arange(0.0, 100.0, 10.0)
    f = fit_piecewise(x, 3.0 * x + 1.0, piecewise=False)
    assert f.low.slope == pytest.approx(3.0) and f.high is None
    with pytest.raises(ModelInputError) as e:
        identify([10, 10], [1.0, 1.0], [1.0, 2.0])
    assert e.value.parameter == "table"
    with pytest.raises(ModelInputError) as e:
        fit_piecewise(x, x, breakpoint=5.0)
    assert e.value.parameter == "breakpoint"
