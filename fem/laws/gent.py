r"""Gent: a strain-stiffening law with a locking stretch.

    Psi = -mu Jm / 2 ln(1 - x / Jm),   x = I1bar - 3 < Jm (the chains' locking stretch),
    Psi' = mu / 2 / (1 - x/Jm),   Psi'' = mu / (2 Jm) / (1 - x/Jm)^2,

initial shear modulus mu (MPa), locking parameter Jm (dimensionless). Gent tends to Neo-Hookean
as Jm -> infinity. At x >= Jm the law is undefined: `check_state` raises `LockingStretch`, which
the solver treats as an inverted state and cuts the step back.

Incompressible uniaxial tension, stretch lam: P = mu (lam - lam^-2) / (1 - x/Jm),
x = lam^2 + 2/lam - 3. For a fixed Jm the stress is linear in mu, so the fit is a bounded scalar
search on log Jm, between 1.0001 x_max (the data's largest x: Gent is undefined past Jm) and 1e6
(where Gent is Neo-Hookean to within x_max/1e6), around a linear least squares of mu.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from softcrawl.fem.errors import SolverInputError
from softcrawl.fem.laws.base import DEFAULT_K_OVER_MU, IsochoricI1Law, finite


class LockingStretch(ValueError):
    """A Gent state at or past the locking stretch (I1bar - 3 >= Jm): the caller cuts back."""


@dataclass(frozen=True, kw_only=True)
class Gent(IsochoricI1Law):
    """Psi = -mu Jm/2 ln(1 - (I1bar - 3)/Jm), initial shear modulus `mu`, locking parameter `jm`."""

    NAME = "gent"
    FIT_PARAMS = ("mu", "Jm")
    MODULI = ("mu", "bulk")
    mu: float
    jm: float
    bulk: float

    def __post_init__(self):
        self._set_numbers()
        if self.jm <= 0.0:
            raise SolverInputError("jm", f"Gent's locking parameter Jm must be > 0, got {self.jm}")
        self._validate_moduli()

    @classmethod
    def nearly_incompressible(cls, mu, jm, k_over_mu: float = DEFAULT_K_OVER_MU) -> Gent:
        mu = finite(mu, "mu")
        return cls(mu=mu, jm=jm, bulk=k_over_mu * mu)

    @property
    def label(self) -> str:
        return f"Gent mu = {self.mu:.4g} MPa, Jm = {self.jm:.4g}"

    def record(self) -> dict:
        return {"gent_jm": self.jm}

    @property
    def x_limit(self) -> float:
        return self.jm

    def check_state(self, x) -> None:
        if np.any(np.asarray(x) >= self.jm):
            raise LockingStretch(f"I1bar - 3 reached Gent's Jm = {self.jm:g}")

    def psi(self, x):
        return -0.5 * self.mu * self.jm * np.log1p(-np.asarray(x) / self.jm)

    def psi_derivatives(self, x):
        s = 1.0 / (1.0 - np.asarray(x, dtype=float) / self.jm)
        return 0.5 * self.mu * s, (0.5 * self.mu / self.jm) * s * s

    def uniaxial_nominal_stress(self, stretch) -> np.ndarray:
        """P = mu (lam - lam^-2) / (1 - x/Jm) (MPa)."""
        lam = np.asarray(stretch, dtype=float)
        return self.mu * (lam - lam**-2) / (1.0 - (lam**2 + 2.0 / lam - 3.0) / self.jm)

    @classmethod
    def fit_uniaxial(cls, stretch, stress, weights):
        """Scalar search on log Jm around the linear least squares of mu (module docstring)."""
        from scipy.optimize import minimize_scalar

        x = stretch**2 + 2.0 / stretch - 3.0
        g = stretch - stretch**-2

        def best_mu(jm: float) -> tuple[float, float]:
            a = weights * g / (1.0 - x / jm)
            mu = float(a @ (weights * stress) / (a @ a))
            return mu, float(np.sum((mu * a - weights * stress) ** 2))

        lo, hi = np.log(1.0001 * x.max()), np.log(1e6)
        found = minimize_scalar(lambda t: best_mu(np.exp(t))[1], bounds=(lo, hi), method="bounded")
        jm = float(np.exp(found.x))
        return (best_mu(jm)[0], jm), ()
