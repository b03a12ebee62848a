"""Fits recover a known law (issue 32): synthetic uniaxial data from each registered law with
known constants, fitted by `softcrawl.materials.fitting.fit_uniaxial`, give back the constants,
the derived shear modulus (mu = 2 C10 for Yeoh) and the bulk modulus K = DEFAULT_K_OVER_MU mu."""

import numpy as np
import pytest

from softcrawl.fem.laws import LAWS
from softcrawl.fem.laws.base import DEFAULT_K_OVER_MU
from softcrawl.materials.fitting import fit_uniaxial

TRUE = {
    "neo-hookean": dict(mu=0.06),
    "yeoh": dict(c10=0.03, c20=0.004, c30=0.0005),
    "gent": dict(mu=0.05, jm=12.0),
}


@pytest.mark.parametrize("name", sorted(TRUE))
def test_synthetic_data_from_a_known_law_is_recovered(name):
    cls = LAWS[name]
    law = cls.nearly_incompressible(**TRUE[name])
    lam = np.linspace(1.02, 2.0, 40)
    fit = fit_uniaxial(lam, law.uniaxial_nominal_stress(lam), name)
    assert fit.model == name and fit.n_points == 40
    truth = {"neo-hookean": (0.06,), "yeoh": (0.03, 0.004, 0.0005), "gent": (0.05, 12.0)}[name]
    np.testing.assert_allclose(fit.values, truth, rtol=1e-4)
    mu = {"neo-hookean": 0.06, "yeoh": 2 * 0.03, "gent": 0.05}[name]
    assert fit.law.mu == pytest.approx(mu, rel=1e-4)
    assert fit.law.bulk == pytest.approx(DEFAULT_K_OVER_MU * mu, rel=1e-4)
    assert fit.rms_error < 1e-6 * mu and fit.r_squared == pytest.approx(1.0, abs=1e-9)
    assert fit.strain_range == (pytest.approx(0.02), pytest.approx(1.0))


def test_a_known_law_is_recovered_with_relative_weighting_and_noise_costs_what_it_should():
    law = LAWS["neo-hookean"].nearly_incompressible(mu=0.1)
    lam = np.linspace(1.05, 1.9, 30)
    stress = law.uniaxial_nominal_stress(lam)
    fit = fit_uniaxial(lam, stress, "neo-hookean", weighting="relative")
    assert fit.law.mu == pytest.approx(0.1, rel=1e-6) and fit.weighting == "relative"
    noisy = stress * (1 + 0.01 * np.where(np.arange(lam.size) % 2, 1.0, -1.0))
    fit = fit_uniaxial(lam, noisy, "neo-hookean")
    assert fit.law.mu == pytest.approx(0.1, rel=0.01)
    assert 0.003 < fit.relative_rms_error < 0.02 and 0.003 < fit.rms_pointwise_relative_error < 0.02


@pytest.mark.parametrize("name", sorted(TRUE))
def test_the_derived_moduli_of_a_fitted_law_are_its_small_strain_ones(name):
    """A fitted material's derived constants from a known law: E = 9 K mu / (3 K + mu) (3 mu
    when K >> mu), nu = (3K - 2mu) / (2 (3K + mu)), lambda = K - 2 mu / 3; and the small-strain
    relations back from (E, nu) give mu and K again."""
    from softcrawl.materials.material import (
        Material,
        bulk_modulus_from_youngs,
        shear_modulus_from_youngs,
        shear_modulus_nearly_incompressible,
    )

    law = LAWS[name].nearly_incompressible(**TRUE[name])
    lam = np.linspace(1.02, 2.0, 40)
    fit = fit_uniaxial(lam, law.uniaxial_nominal_stress(lam), name)
    m = Material(name="fitted", law=fit.law, density=1.07e-9)
    mu = {"neo-hookean": 0.06, "yeoh": 2 * 0.03, "gent": 0.05}[name]
    k = DEFAULT_K_OVER_MU
    E = 9 * k * mu / (3 * k + 1)
    assert m.youngs_modulus == pytest.approx(E, rel=1e-4) and m.youngs_modulus == pytest.approx(
        3 * mu, rel=2e-3
    )
    nu = (3 * k - 2) / (2 * (3 * k + 1))
    assert m.poisson_ratio == pytest.approx(nu, rel=1e-9) and m.k_over_mu == pytest.approx(k, rel=1e-9)
    assert m.lame_lambda == pytest.approx((k - 2 / 3) * mu, rel=1e-4)
    assert shear_modulus_from_youngs(m.youngs_modulus, m.poisson_ratio) == pytest.approx(m.mu, rel=1e-12)
    assert bulk_modulus_from_youngs(m.youngs_modulus, m.poisson_ratio) == pytest.approx(m.bulk, rel=1e-9)
    assert shear_modulus_nearly_incompressible(m.youngs_modulus, k) == pytest.approx(m.mu, rel=1e-12)


def test_small_strain_relations_by_hand():
    from softcrawl.materials.material import bulk_modulus_from_youngs, shear_modulus_from_youngs

    assert shear_modulus_from_youngs(2600.0, 0.3) == pytest.approx(1000.0)
    assert bulk_modulus_from_youngs(2400.0, 0.3) == pytest.approx(2000.0)
    assert bulk_modulus_from_youngs(3.0, 0.0) == pytest.approx(1.0)
