r"""Yeoh (three terms): the strain-stiffening law of the full-range silicone fits.

    Psi = C10 x + C20 x^2 + C30 x^3,   x = I1bar - 3,
    Psi' = C10 + 2 C20 x + 3 C30 x^2,   Psi'' = 2 C20 + 6 C30 x,   mu = 2 C10   (MPa).

Stability: Psi' > 0 for every x >= 0 iff C10 > 0, C30 >= 0 and (C20 >= 0 or C20^2 < 3 C10 C30)
(`is_stable`); otherwise the uniaxial stress turns down at a finite stretch, which a
path-following solver would find. A `Yeoh` is checked on construction.

Incompressible uniaxial tension, stretch lam: P = 2 (lam - lam^-2)(C10 + 2 C20 x + 3 C30 x^2),
x = lam^2 + 2/lam - 3, linear in the constants (`design_matrix`), so the fit is a linear least
squares; if its result is unstable it is refitted with C10 > 0, C30 >= 0 (C20 free), and if C20 is
then too negative with C20 >= 0 as well, which is always stable (a conservative choice, not the
best stable fit). Each refit is a note of the fit. A negative C20 captures the softening of the
initial slope typical of silicones.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from softcrawl.fem.errors import SolverInputError
from softcrawl.fem.laws.base import DEFAULT_K_OVER_MU, IsochoricI1Law, finite


def is_stable(c10: float, c20: float, c30: float) -> bool:
    """True if Psi' = C10 + 2 C20 x + 3 C30 x^2 > 0 for all x >= 0 (module docstring)."""
    return c10 > 0.0 and c30 >= 0.0 and (c20 >= 0.0 or c20 * c20 < 3.0 * c10 * c30)


def design_matrix(lam: np.ndarray) -> np.ndarray:
    """Columns of the uniaxial nominal stress per C10, C20, C30."""
    x = lam**2 + 2.0 / lam - 3.0
    g = 2.0 * (lam - lam**-2)
    return np.column_stack([g, 2.0 * g * x, 3.0 * g * x**2])


@dataclass(frozen=True, kw_only=True)
class Yeoh(IsochoricI1Law):
    """Psi = C10 x + C20 x^2 + C30 x^3 (MPa) with bulk modulus `bulk` (MPa)."""

    NAME = "yeoh"
    FIT_PARAMS = ("C10", "C20", "C30")
    MODULI = ("c10", "c20", "c30", "bulk")
    c10: float
    c20: float
    c30: float
    bulk: float

    def __post_init__(self):
        self._set_numbers()
        if not is_stable(self.c10, self.c20, self.c30):
            raise SolverInputError(
                "c10",
                f"Yeoh (C10, C20, C30) = ({self.c10:g}, {self.c20:g}, {self.c30:g}) MPa is unstable: need "
                "C10 > 0, C30 >= 0 and C20 >= 0 or C20^2 < 3 C10 C30 (dPsi/dI1 > 0 at every stretch)",
            )
        self._validate_moduli()

    @property
    def mu(self) -> float:
        return 2.0 * self.c10

    @classmethod
    def nearly_incompressible(cls, c10, c20, c30, k_over_mu: float = DEFAULT_K_OVER_MU) -> Yeoh:
        c10 = finite(c10, "c10")
        return cls(c10=c10, c20=c20, c30=c30, bulk=k_over_mu * (2.0 * c10))

    @property
    def label(self) -> str:
        return f"Yeoh (C10, C20, C30) = ({self.c10:.4g}, {self.c20:.4g}, {self.c30:.4g}) MPa"

    def record(self) -> dict:
        return {"yeoh_c": [self.c10, self.c20, self.c30]}

    def psi(self, x):
        return x * (self.c10 + x * (self.c20 + x * self.c30))

    def psi_derivatives(self, x):
        x = np.asarray(x, dtype=float)
        return self.c10 + x * (2.0 * self.c20 + 3.0 * self.c30 * x), 2.0 * self.c20 + 6.0 * self.c30 * x

    def uniaxial_nominal_stress(self, stretch) -> np.ndarray:
        """P = 2 (lam - lam^-2)(C10 + 2 C20 x + 3 C30 x^2) (MPa)."""
        lam = np.atleast_1d(np.asarray(stretch, dtype=float))
        stress = design_matrix(lam.ravel()) @ np.array([self.c10, self.c20, self.c30])
        return stress.reshape(np.shape(stretch))

    @classmethod
    def fit_uniaxial(cls, stretch, stress, weights, stable: bool = True):
        """Linear least squares with the stability refits of the module docstring; with
        `stable=False` the unconstrained constants, which may be unstable."""
        design = design_matrix(stretch) * weights[:, None]
        stress_w = stress * weights
        c = np.linalg.lstsq(design, stress_w, rcond=None)[0]
        notes: list[str] = []
        if stable and not is_stable(*c):
            notes.append(
                f"unconstrained fit (C10, C20, C30) = ({', '.join(f'{v:.4g}' for v in c)})"
                " is unstable at large strain; refitted with C10 > 0, C30 >= 0"
            )
            c = _bounded_lstsq(design, stress_w, c20_min=-np.inf)
            if not is_stable(*c):
                notes.append(f"C20 = {c[1]:.4g} < 0 with C20^2 >= 3 C10 C30; refitted with C20 >= 0")
                c = _bounded_lstsq(design, stress_w, c20_min=0.0)
        return tuple(float(v) for v in c), tuple(notes)


def _bounded_lstsq(design: np.ndarray, stress: np.ndarray, c20_min: float) -> np.ndarray:
    from scipy.optimize import lsq_linear

    # C10 > 0 strictly: a tiny positive floor far below any elastomer's modulus.
    lower = [1e-12, c20_min, 0.0]
    upper = [np.inf, np.inf, np.inf]
    return lsq_linear(design, stress, bounds=(lower, upper), method="bvls").x
