r"""Strain-stiffening laws of the solver beside Neo-Hookean: Yeoh (three terms) and Gent.

Both are isochoric-in-I1 laws (`fem.neohooke.IsochoricI1Law`), so the mixed u-p kernel
(`fem.solid`) takes them through Psi' and Psi'' at x = I1bar - 3:

    Yeoh:  Psi = C10 x + C20 x^2 + C30 x^3
           Psi'  = C10 + 2 C20 x + 3 C30 x^2,   Psi'' = 2 C20 + 6 C30 x,   mu = 2 C10
    Gent:  Psi = -mu Jm / 2 ln(1 - x / Jm)      (x < Jm: the chains' locking stretch)
           Psi'  = mu / 2 / (1 - x/Jm),         Psi'' = mu / (2 Jm) / (1 - x/Jm)^2

Gent tends to Neo-Hookean as Jm -> infinity. A Yeoh law must keep Psi' > 0 for all x >= 0
(C30 >= 0 and C20 >= 0 or C20^2 < 3 C10 C30), otherwise its uniaxial stress turns down at a finite
stretch; `materials.material` checks the same condition for a `Material`.

Incompressible uniaxial tension, stretch lam, x = lam^2 + 2/lam - 3: nominal stress
P = 2 Psi'(x) (lam - lam^-2) for every law here (`uniaxial_nominal_stress`). Units: MPa.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from softcrawl.fem.errors import SolverInputError
from softcrawl.fem.neohooke import IsochoricI1Law, NeoHookean


@dataclass(frozen=True, kw_only=True)
class Yeoh(IsochoricI1Law):
    """Psi = C10 x + C20 x^2 + C30 x^3 (MPa) with bulk modulus `bulk` (MPa)."""

    c10: float
    c20: float
    c30: float
    bulk: float

    def __post_init__(self):
        for name in ("c10", "c20", "c30"):
            if not np.isfinite(getattr(self, name)):
                raise SolverInputError(name, f"must be finite, got {getattr(self, name)}")
        stable = self.c30 >= 0.0 and (self.c20 >= 0.0 or self.c20**2 < 3.0 * self.c10 * self.c30)
        if self.c10 <= 0.0 or not stable:
            raise SolverInputError(
                "c10",
                f"Yeoh ({self.c10:g}, {self.c20:g}, {self.c30:g}) MPa: need C10 > 0, C30 >= 0 and "
                "C20 >= 0 or C20^2 < 3 C10 C30 (dPsi/dI1 > 0 at every stretch)",
            )
        self._validate_moduli()

    @property
    def mu(self) -> float:
        return 2.0 * self.c10

    @classmethod
    def nearly_incompressible(cls, c10, c20, c30, k_over_mu: float = 1000.0) -> Yeoh:
        return cls(c10=c10, c20=c20, c30=c30, bulk=k_over_mu * 2.0 * c10)

    def psi(self, x):
        return x * (self.c10 + x * (self.c20 + x * self.c30))

    def psi_derivatives(self, x):
        x = np.asarray(x, dtype=float)
        return self.c10 + x * (2.0 * self.c20 + 3.0 * self.c30 * x), 2.0 * self.c20 + 6.0 * self.c30 * x


class LockingStretch(ValueError):
    """A Gent state at or past the locking stretch (I1bar - 3 >= Jm): the caller cuts back."""


@dataclass(frozen=True, kw_only=True)
class Gent(IsochoricI1Law):
    """Psi = -mu Jm/2 ln(1 - (I1bar - 3)/Jm), initial shear modulus `mu`, locking parameter `jm`."""

    mu: float
    jm: float
    bulk: float

    def __post_init__(self):
        if not np.isfinite(self.jm) or self.jm <= 0.0:
            raise SolverInputError("jm", f"Gent's locking parameter Jm must be > 0, got {self.jm}")
        self._validate_moduli()

    @classmethod
    def nearly_incompressible(cls, mu, jm, k_over_mu: float = 1000.0) -> Gent:
        return cls(mu=mu, jm=jm, bulk=k_over_mu * mu)

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


LAWS = {"neo-hookean": NeoHookean, "yeoh": Yeoh, "gent": Gent}


def uniaxial_nominal_stress(law: IsochoricI1Law, stretch) -> np.ndarray:
    """Nominal stress of incompressible uniaxial tension, P = 2 Psi'(x) (lam - lam^-2) (MPa)."""
    lam = np.asarray(stretch, dtype=float)
    return 2.0 * law.psi_derivatives(lam**2 + 2.0 / lam - 3.0)[0] * (lam - lam**-2)


def law_label(law: IsochoricI1Law) -> str:
    """A one-line name of the law and its constants, e.g. 'Yeoh (C10, C20, C30) = (...) MPa'."""
    if isinstance(law, Yeoh):
        return f"Yeoh (C10, C20, C30) = ({law.c10:.4g}, {law.c20:.4g}, {law.c30:.4g}) MPa"
    if isinstance(law, Gent):
        return f"Gent mu = {law.mu:.4g} MPa, Jm = {law.jm:.4g}"
    return f"Neo-Hookean mu = {law.mu:.4g} MPa"
