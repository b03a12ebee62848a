r"""A new law in one file: defined here, registered with one line, fitted to the shipped tensile
data through the normal fitting function, and solved in FE.

The toy law is Psi = mu/2 x + beta x^2 (x = I1bar - 3): Psi' = mu/2 + 2 beta x, Psi'' = 2 beta,
uniaxial nominal stress P = (lam - lam^-2)(mu + 4 beta x), linear in (mu, beta). It brings no
least squares of its own, so the fit is the generic nonlinear one (`fem.laws.base`), checked
against the linear least squares written out here.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pytest

from softcrawl import materials
from softcrawl.fem.laws import LAWS, IsochoricI1Law, law_class, register_law
from softcrawl.fem.model import Dirichlet, SolidModel
from softcrawl.fem.path import load_path
from softcrawl.fem.structured import box
from softcrawl.materials.fem_law import solid_law


@dataclass(frozen=True, kw_only=True)
class QuadraticI1(IsochoricI1Law):
    """Psi = mu/2 x + beta x^2 (MPa), beta >= 0."""

    NAME = "toy-quadratic"
    FIT_PARAMS = ("mu", "beta")
    MODULI = ("mu", "beta", "bulk")
    mu: float
    beta: float
    bulk: float

    def __post_init__(self):
        self._set_numbers()
        self._validate_moduli()

    @classmethod
    def nearly_incompressible(cls, mu, beta, k_over_mu=1000.0):
        return cls(mu=mu, beta=beta, bulk=k_over_mu * mu)

    @classmethod
    def fit_start(cls, mu0):
        return (mu0, 0.01 * mu0)

    @property
    def label(self):
        return f"quadratic-in-I1 mu = {self.mu:.4g} MPa, beta = {self.beta:.4g} MPa"

    def psi(self, x):
        return 0.5 * self.mu * x + self.beta * x * x

    def psi_derivatives(self, x):
        x = np.asarray(x, dtype=float)
        return 0.5 * self.mu + 2.0 * self.beta * x, np.full_like(x, 2.0 * self.beta)


@pytest.fixture
def toy():
    register_law(QuadraticI1)  # the one line a new law needs
    yield QuadraticI1
    del LAWS[QuadraticI1.NAME]  # the registry is process-wide: leave it as found


def test_toy_law_fits_the_shipped_data_and_solves_in_fe(toy):
    data = materials.load_tensile("ecoflex-00-50")
    fit = materials.fit_tensile(data, toy.NAME)
    assert fit.model == toy.NAME and fit.param_names == ("mu", "beta")

    # The generic nonlinear fit against the linear least squares of P = g mu + 4 g x beta.
    lam, stress = materials.select_fit_points(data.stretch, data.nominal_stress)
    g, x = lam - lam**-2, lam**2 + 2 / lam - 3
    exact = np.linalg.lstsq(np.column_stack([g, 4 * g * x]), stress, rcond=None)[0]
    assert exact[1] > 0  # the data stiffen: beta is not held at its bound
    assert fit.values == pytest.approx(tuple(exact), rel=1e-5)
    assert fit.rms_error < 0.5 * materials.fit_tensile(data, "neo-hookean").rms_error

    # A material of the fitted law, through the normal path to the solver.
    material = fit.to_material(name="toy", density=1.07e-9, source="test", k_over_mu=1e4)
    law = solid_law(material, hyperelastic_only=True)
    assert law.label in material.law_label and material.to_dict()["beta"] == fit.values[1]

    # The patch-test box (fem.verification) stretched to 2: FE nominal stress against the law's.
    stretch, size = 2.0, (2.0, 2.0, 4.0)
    bcs = [
        Dirichlet.symmetry("x0", 0),
        Dirichlet.symmetry("y0", 1),
        Dirichlet.symmetry("z0", 2),
        Dirichlet.prescribed("z1", 2, (stretch - 1) * size[2]),
    ]
    model = SolidModel(box(size, (1, 1, 2)), law, dirichlet=bcs)
    res = load_path(model, [(0.0, f) for f in np.linspace(0.25, 1.0, 4)], control="displacement")
    assert res.converged, res.message
    nominal = model.reaction(res.steps[-1].x, "z1")[2] / (size[0] * size[1])
    expected = float(law.uniaxial_nominal_stress(stretch))
    # The beta term is 15 % of the stress here, so a solver that missed it would be far off; the
    # tolerance is the compressible (K/mu = 1e4) solid against the incompressible closed form
    # (observed -1.3e-4).
    assert 4.0 * law.beta * (stretch**2 + 2 / stretch - 3) > 0.1 * law.mu
    assert nominal == pytest.approx(expected, rel=3e-4)


@pytest.mark.parametrize("name", ["toy-quadratic", "mooney", "", 3])
def test_unregistered_or_unknown_law_is_a_one_line_input_error(name):
    from softcrawl.errors import InputError

    with pytest.raises(InputError) as info:
        law_class(name)
    assert info.value.parameter == "model" and "\n" not in str(info.value)
    data = materials.load_tensile("ecoflex-00-50")
    with pytest.raises(materials.MaterialError) as info:
        materials.fit_tensile(data, name)
    assert info.value.parameter == "model" and "valid: neo-hookean, yeoh, gent" in str(info.value)


def test_registration_checks_the_law(toy):
    from softcrawl.errors import InputError

    @dataclass(frozen=True, kw_only=True)
    class Nameless(IsochoricI1Law):
        mu: float
        bulk: float

    with pytest.raises(InputError) as info:
        register_law(Nameless)
    assert info.value.parameter == "law" and "NAME" in str(info.value)

    @dataclass(frozen=True, kw_only=True)
    class Impostor(QuadraticI1):
        pass

    with pytest.raises(InputError, match="taken"):
        register_law(Impostor)  # another class under a registered name
    assert register_law(toy) is toy and LAWS[toy.NAME] is toy
