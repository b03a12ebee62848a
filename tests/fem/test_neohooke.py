"""Neo-Hookean stress and tangent against finite differences; material validation."""

import numpy as np
import pytest

from softcrawl.fem.errors import SolverInputError
from softcrawl.fem.laws import NeoHookean
from softcrawl.fem.neohooke import cauchy_stress, von_mises


@pytest.mark.parametrize("k_over_mu", [2.0, 1000.0])
def test_stress_and_tangent_match_finite_differences(k_over_mu):
    mat = NeoHookean.nearly_incompressible(0.03, k_over_mu)
    rng = np.random.default_rng(3)
    F = np.eye(3)[:, :, None] + 0.25 * rng.standard_normal((3, 3, 7))
    P, A = mat.stress(F), mat.tangent(F)
    h = 1e-6
    for k in range(3):
        for l in range(3):
            dF = np.zeros_like(F)
            dF[k, l] = h
            dW = (mat.energy(F + dF) - mat.energy(F - dF)) / (2 * h)
            dP = (mat.stress(F + dF) - mat.stress(F - dF)) / (2 * h)
            assert np.allclose(dW, P[k, l], rtol=1e-6, atol=1e-9 * k_over_mu)
            assert np.allclose(dP, A[:, :, k, l], rtol=1e-6, atol=1e-8 * k_over_mu)


def test_stress_free_reference_and_uniaxial_limit():
    mat = NeoHookean.nearly_incompressible(0.03, 1e6)
    assert np.abs(mat.stress(np.eye(3)[:, :, None])).max() < 1e-15
    lam = 1.5
    F = np.diag([lam**-0.5, lam**-0.5, lam])[:, :, None]
    sigma = cauchy_stress(mat.stress(F), F)
    # incompressible uniaxial Cauchy stress difference: mu (lam^2 - 1/lam)
    assert sigma[2, 2, 0] - sigma[0, 0, 0] == pytest.approx(0.03 * (lam**2 - 1 / lam), rel=1e-9)
    assert von_mises(sigma)[0] == pytest.approx(0.03 * (lam**2 - 1 / lam), rel=1e-9)


@pytest.mark.parametrize(
    "mu, bulk, parameter",
    [
        (0.0, 1.0, "mu"),
        (-0.03, 30.0, "mu"),
        (np.nan, 30.0, "mu"),
        (0.03, 0.0, "bulk"),
        (0.03, -1.0, "bulk"),
        (0.03, 0.01, "bulk"),
    ],
)
def test_unphysical_material_names_the_parameter(mu, bulk, parameter):
    with pytest.raises(SolverInputError) as err:
        NeoHookean(mu=mu, bulk=bulk)
    assert err.value.parameter == parameter


def test_mixed_tangent_is_the_sum_of_isochoric_and_pressure_parts():
    from softcrawl.fem.neohooke import det3, inv_transpose3, iso_tangent, mixed_tangent, pressure_tangent

    rng = np.random.default_rng(5)
    F = np.eye(3)[:, :, None] + 0.2 * rng.standard_normal((3, 3, 4))
    J, H, p = det3(F), inv_transpose3(F), rng.standard_normal(4)
    assert np.allclose(
        mixed_tangent(F, 0.03, p, J, H),
        iso_tangent(F, 0.03, J, H) + pressure_tangent(p, J, H),
        rtol=1e-13,
        atol=1e-15,
    )
