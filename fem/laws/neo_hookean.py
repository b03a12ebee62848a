r"""Neo-Hookean: the law linear in I1, the solver's default and its fast path.

    Psi = mu/2 x,   x = I1bar - 3,   Psi' = mu/2,   Psi'' = 0,

with shear modulus mu and bulk modulus K (MPa). Incompressible uniaxial tension, stretch lam:
nominal stress P = mu (lam - lam^-2), linear in mu, so the fit to a tensile test is a linear least
squares, mu = sum(w^2 g P) / sum(w^2 g^2) with g = lam - lam^-2 and weights w.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from softcrawl.fem.laws.base import DEFAULT_K_OVER_MU, IsochoricI1Law, finite


@dataclass(frozen=True, kw_only=True)
class NeoHookean(IsochoricI1Law):
    """Shear modulus `mu` and bulk modulus `bulk`, both in MPa: Psi = mu/2 (I1bar - 3)."""

    NAME = "neo-hookean"
    FIT_PARAMS = ("mu",)
    MODULI = ("mu", "bulk")
    LINEAR_IN_I1 = True
    mu: float
    bulk: float

    def __post_init__(self):
        self._set_numbers()
        self._validate_moduli()

    @classmethod
    def nearly_incompressible(cls, mu: float, k_over_mu: float = DEFAULT_K_OVER_MU) -> NeoHookean:
        mu = finite(mu, "mu")
        return cls(mu=mu, bulk=k_over_mu * mu)

    @property
    def label(self) -> str:
        return f"Neo-Hookean mu = {self.mu:.4g} MPa"

    def psi(self, x):
        return 0.5 * self.mu * x

    def psi_derivatives(self, x):
        x = np.asarray(x, dtype=float)
        return np.full_like(x, 0.5 * self.mu), np.zeros_like(x)

    def uniaxial_nominal_stress(self, stretch) -> np.ndarray:
        """P = mu (lam - lam^-2) (MPa)."""
        lam = np.asarray(stretch, dtype=float)
        return self.mu * (lam - lam**-2)

    @classmethod
    def fit_uniaxial(cls, stretch, stress, weights):
        """Linear least squares of mu (module docstring)."""
        g = stretch - stretch**-2
        w = weights
        return (float((w * g) @ (w * stress) / ((w * g) @ (w * g))),), ()
