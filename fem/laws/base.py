r"""The protocol every hyperelastic law of the solver follows: `IsochoricI1Law`.

Every law is decoupled and isochoric-in-I1 (docs/decisions/001-materials.md):

    W(F) = Psi(x) + K/2 (J - 1)^2,   x = I1bar - 3,  I1bar = J^{-2/3} I1,  I1 = F:F,  J = det F.

A law states Psi and its derivatives Psi'(x), Psi''(x) (what the mixed u-p kernel `fem.solid`
takes); this base turns them into stress and tangent (`fem.neohooke` has the tensor algebra):
with c = 2 Psi' J^{-2/3}, D = F - I1/3 H, d = 4 Psi'' J^{-4/3}, H = F^{-T},

    P = c D + K (J - 1) J H,
    A = c [Neo-Hookean bracket] + d D (x) D + K J^2 H (x) H + K (J - 1) J (H (x) H - H (.) H).

Incompressible uniaxial tension at stretch lam has x = lam^2 + 2/lam - 3 and the nominal stress

    P = 2 Psi'(x) (lam - lam^-2)   (MPa),

which `uniaxial_nominal_stress` evaluates for any law (a law may give the same in closed form).
Fitting a law to a tensile test (`materials.fitting`) needs of the law its constants' names
(`FIT_PARAMS`), their construction (`from_fit`, a nearly incompressible law K = k mu), and either
its own least squares (`fit_uniaxial`) or a start (`fit_start`) and bounds (`FIT_BOUNDS`) for the
generic nonlinear one here. `MODULI` names the constants with units of stress: `with_mu` scales
them together (the same curve shape at another initial shear modulus).
"""

from __future__ import annotations

import dataclasses
import math
from typing import ClassVar

import numpy as np

from softcrawl.fem.errors import SolverInputError
from softcrawl.fem.neohooke import det3, general_iso_tangent, inv_transpose3, outer, pressure_tangent

#: Default K/mu of a fitted law (nu = 0.4995, docs/decisions/001-materials.md: K/mu >= 1000).
DEFAULT_K_OVER_MU = 1000.0


def finite(value: object, parameter: str) -> float:
    """`value` as a finite float, or a `SolverInputError` naming `parameter` (never an
    OverflowError for a huge integer)."""
    try:
        number = float(value)
    except (TypeError, ValueError, OverflowError):
        raise SolverInputError(parameter, f"must be a finite number, got {value!r:.40}") from None
    if not math.isfinite(number):
        raise SolverInputError(parameter, f"must be finite, got {number!r}")
    return number


class IsochoricI1Law:
    """Base of the solver's laws: W = Psi(I1bar) + K/2 (J - 1)^2 (module docstring).

    A law is a frozen dataclass with `mu` (initial shear modulus, 2 Psi'(0)) and `bulk` (MPa)
    that defines `psi(x)` and `psi_derivatives(x) -> (Psi', Psi'')` at x = I1bar - 3 >= 0
    (arrays), `label`, and the class attributes `NAME` (its registry name, `fem.laws.LAWS`),
    `FIT_PARAMS` and `MODULI`. Laws with `LINEAR_IN_I1` (Neo-Hookean) take the solver's fast
    path, which skips the Psi'' term. `check_state(x)` raises ValueError where the law is
    undefined (Gent's locking stretch).
    """

    NAME: ClassVar[str]
    #: Names of the constants a uniaxial fit determines, in the order of `nearly_incompressible`.
    FIT_PARAMS: ClassVar[tuple[str, ...]]
    #: Fields with units of stress (scaled together by `with_mu`).
    MODULI: ClassVar[tuple[str, ...]]
    #: (lower, upper) bounds of the generic fit, one per FIT_PARAMS; None: every constant >= 0.
    FIT_BOUNDS: ClassVar[tuple[tuple[float, ...], tuple[float, ...]] | None] = None
    LINEAR_IN_I1: ClassVar[bool] = False
    mu: float
    bulk: float

    # -- the law ------------------------------------------------------------------------------

    def psi(self, x: np.ndarray) -> np.ndarray:
        raise NotImplementedError

    def psi_derivatives(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        raise NotImplementedError

    @property
    def label(self) -> str:
        """One line naming the law and its constants, e.g. 'Neo-Hookean mu = 0.03 MPa'."""
        raise NotImplementedError

    def check_state(self, x: np.ndarray) -> None:
        """Raise ValueError where the law is undefined (nothing for most laws)."""

    @property
    def x_limit(self) -> float:
        """Supremum of the admissible I1bar - 3 (infinite unless the law locks, as Gent does)."""
        return float("inf")

    @property
    def poisson_ratio(self) -> float:
        return (3 * self.bulk - 2 * self.mu) / (2 * (3 * self.bulk + self.mu))

    def uniaxial_nominal_stress(self, stretch) -> np.ndarray:
        """Nominal stress of incompressible uniaxial tension, P = 2 Psi'(x) (lam - lam^-2) (MPa)."""
        lam = np.asarray(stretch, dtype=float)
        return 2.0 * self.psi_derivatives(lam**2 + 2.0 / lam - 3.0)[0] * (lam - lam**-2)

    def record(self) -> dict:
        """The law's constants besides mu and bulk, by name (the material record's fields)."""
        fields = (f.name for f in dataclasses.fields(self))
        return {name: getattr(self, name) for name in fields if name not in ("mu", "bulk")}

    # -- fitting ------------------------------------------------------------------------------

    @classmethod
    def from_fit(cls, values, k_over_mu: float = DEFAULT_K_OVER_MU) -> IsochoricI1Law:
        """The nearly incompressible law (K = k_over_mu mu) of fitted constants `values`."""
        return cls.nearly_incompressible(*values, k_over_mu=k_over_mu)

    @classmethod
    def fit_start(cls, mu0: float) -> tuple[float, ...]:
        """Start of the generic fit from mu0, the Neo-Hookean least-squares modulus."""
        raise NotImplementedError(f"{cls.__name__} defines neither fit_uniaxial nor fit_start")

    @classmethod
    def fit_uniaxial(cls, stretch: np.ndarray, stress: np.ndarray, weights: np.ndarray):
        """(constants, notes) minimising |weights (P(stretch) - stress)|: the generic nonlinear
        least squares (scipy's trust-region reflective) from `fit_start` within `FIT_BOUNDS`."""
        from scipy.optimize import least_squares

        g = weights * (stretch - stretch**-2)
        mu0 = float(g @ (weights * stress) / (g @ g))
        bounds = cls.FIT_BOUNDS or ((0.0,) * len(cls.FIT_PARAMS), (np.inf,) * len(cls.FIT_PARAMS))

        def residual(values):
            return weights * (cls.from_fit(values).uniaxial_nominal_stress(stretch) - stress)

        found = least_squares(residual, cls.fit_start(mu0), bounds=bounds, x_scale="jac", xtol=1e-12)
        return tuple(float(v) for v in found.x), ()

    # -- stress and tangent -------------------------------------------------------------------

    def _set_numbers(self) -> None:
        """Every field as a finite float (a frozen dataclass's __post_init__ calls this first)."""
        for f in dataclasses.fields(self):
            object.__setattr__(self, f.name, finite(getattr(self, f.name), f.name))

    def _validate_moduli(self) -> None:
        if self.mu <= 0:
            raise SolverInputError("mu", f"shear modulus must be positive, got {self.mu} MPa")
        if self.bulk <= 0:
            raise SolverInputError("bulk", f"bulk modulus must be positive, got {self.bulk} MPa")
        if self.bulk < 2.0 / 3.0 * self.mu:
            raise SolverInputError(
                "bulk", f"K = {self.bulk} MPa < 2/3 mu gives a negative Poisson ratio; use K >= 2/3 mu"
            )

    def _state(self, F):
        J, H = det3(F), inv_transpose3(F)
        I1 = np.einsum("ij...,ij...->...", F, F)
        x = J ** (-2.0 / 3.0) * I1 - 3.0
        self.check_state(x)
        return J, H, I1, x

    def energy(self, F: np.ndarray) -> np.ndarray:
        J, _, _, x = self._state(F)
        return self.psi(x) + 0.5 * self.bulk * (J - 1) ** 2

    def stress(self, F: np.ndarray) -> np.ndarray:
        """First Piola stress P = dW/dF of the full (displacement-only) energy."""
        J, H, I1, x = self._state(F)
        d1, _ = self.psi_derivatives(x)
        return (2.0 * d1 * J ** (-2 / 3)) * (F - I1 / 3 * H) + self.bulk * (J - 1) * J * H

    def tangent(self, F: np.ndarray) -> np.ndarray:
        """A = dP/dF of the full energy."""
        J, H, I1, x = self._state(F)
        d1, d2 = self.psi_derivatives(x)
        A = general_iso_tangent(F, 2.0 * d1 * J ** (-2 / 3), 4.0 * d2 * J ** (-4 / 3), J, H)
        return A + self.bulk * J * J * outer(H, H) + pressure_tangent(self.bulk * (J - 1), J, H)


def with_mu(law, mu: float):
    """A copy of `law` with initial shear modulus `mu`: every field of `law.MODULI` scaled by
    mu / law.mu (mu itself set to `mu`), the rest (K/mu, the curve's shape) kept."""
    scale = mu / law.mu
    return dataclasses.replace(law, **{f: mu if f == "mu" else getattr(law, f) * scale for f in law.MODULI})
