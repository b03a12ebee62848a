r"""Inflation of an incompressible thick tube for any law W(I1) (Psi' from the law's
`psi_derivatives`): plane strain and closed ends (docs/decisions/010-verification.md).

Reference radii A < B, inner radius a = la A, uniform axial stretch lz. Incompressibility gives
the current radius of the material at R,

    r^2 = a^2 + (R^2 - A^2) / lz,    lam_t = r / R,  lam_z = lz,  lam_r = 1 / (lam_t lz),

and with I1 = lam_r^2 + lam_t^2 + lz^2 the principal Cauchy stress differences of W(I1) are
s_t - s_r = 2 W'(I1) (lam_t^2 - lam_r^2) and s_z - s_r = 2 W'(I1) (lz^2 - lam_r^2). Radial
equilibrium ds_r/dr = (s_t - s_r)/r with s_r(a) = -P, s_r(b) = 0 gives (r dr = R dR / lz)

    P = int_A^B 2 W'(I1) (lam_t^2 - lam_r^2) R / (lz r^2) dR.                         (1)

Plane strain is lz = 1. With closed ends the wall carries the cap load P pi a^2; the axial force
N = 2 pi int s_z r dr, rewritten with (1) (Haughton and Ogden 1979), makes the condition

    N - P pi a^2 = pi int_A^B 2 W'(I1) (2 lz^2 - lam_t^2 - lam_r^2) R / lz dR = 0,       (2)

which gives lz(la). P(la) along (2) may have a maximum: the tube's limit (burst) pressure. For
Neo-Hookean W' = mu/2 and P/mu depends on the geometry alone. Integrals: Gauss-Legendre over R
with `N_GAUSS` points (exact to ~1e-12 for these smooth integrands).
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq, minimize_scalar

N_GAUSS = 64
_XG, _WG = np.polynomial.legendre.leggauss(N_GAUSS)


def _stretches(la, lz, A, B):
    R = 0.5 * (B - A) * _XG + 0.5 * (B + A)
    r2 = (la * A) ** 2 + (R**2 - A**2) / lz
    lt2 = r2 / R**2
    lr2 = 1.0 / (lt2 * lz * lz)
    return R, r2, lt2, lr2, 0.5 * (B - A) * _WG


def _psi1(law, lt2, lr2, lz):
    """W'(I1) of the incompressible state (I1bar = I1, J = 1)."""
    return law.psi_derivatives(lt2 + lr2 + lz * lz - 3.0)[0]


def pressure(law, la, A, B, lz=1.0) -> float:
    """Internal pressure (MPa) of eq. (1) at inner stretch `la` and axial stretch `lz`."""
    R, r2, lt2, lr2, w = _stretches(la, lz, A, B)
    return float(np.sum(w * 2.0 * _psi1(law, lt2, lr2, lz) * (lt2 - lr2) * R / (lz * r2)))


def reduced_axial_force(law, la, lz, A, B) -> float:
    """N - P pi a^2 (N) of eq. (2); zero for a closed-end tube."""
    R, _, lt2, lr2, w = _stretches(la, lz, A, B)
    return float(np.pi * np.sum(w * 2.0 * _psi1(law, lt2, lr2, lz) * (2 * lz * lz - lt2 - lr2) * R / lz))


def inner_x(la, lz) -> float:
    """I1 - 3 at the inner wall, the largest in the tube (the inner wall is stretched most)."""
    return la * la + 1.0 / (la * la * lz * lz) + lz * lz - 3.0


def admissible(law, la, lz=1.0) -> bool:
    """True unless the state passes the law's locking stretch (Gent's Jm) at the inner wall."""
    return inner_x(la, lz) < law.x_limit


def closed_end_axial_stretch(law, la, A, B) -> float:
    """lz solving eq. (2) at inner stretch `la` (bracketed: the force is negative at lz = 1 for
    la > 1 and grows with lz; a locked state counts as a positive force)."""
    if la == 1.0:
        return 1.0

    def f(lz):
        return reduced_axial_force(law, la, lz, A, B) if admissible(law, la, lz) else 1e30

    hi = 1.5
    while f(hi) < 0.0:
        hi *= 1.5
        if hi > 1e3:
            raise ValueError(f"no closed-end axial stretch at la = {la}")
    return brentq(f, 1.0, hi, xtol=1e-13)


def closed_end_pressure(law, la, A, B) -> tuple[float, float]:
    """(P, lz) of the closed-end tube at inner stretch `la`."""
    lz = closed_end_axial_stretch(law, la, A, B)
    return pressure(law, la, A, B, lz), lz


def inner_stretch(law, P, A, B, lz=1.0, la_max=50.0) -> float:
    """Inner stretch at pressure P (MPa) on the rising branch of eq. (1) at fixed lz."""
    if P <= 0.0:
        return 1.0
    return brentq(lambda la: pressure(law, la, A, B, lz) - P, 1.0, la_max, xtol=1e-13)


def closed_end_limit(law, A, B, la_max=8.0) -> tuple[float, float] | None:
    """(la, P) at the first pressure maximum of the closed-end tube, None if P(la) rises
    monotonically up to `la_max` (a strain-stiffening law may remove the limit point)."""
    grid = np.linspace(1.0, la_max, 141)[1:]
    grid = grid[[admissible(law, la) for la in grid]]  # Gent: up to its locking stretch
    ps = np.array([closed_end_pressure(law, la, A, B)[0] for la in grid])
    k = int(np.argmax(np.diff(ps) < 0.0)) if np.any(np.diff(ps) < 0.0) else -1
    if k < 0:
        return None
    lo, hi = grid[max(k - 1, 0)], grid[min(k + 1, grid.size - 1)]
    found = minimize_scalar(
        lambda la: -closed_end_pressure(law, la, A, B)[0],
        bounds=(lo, hi),
        method="bounded",
        options={"xatol": 1e-10},
    )
    return float(found.x), float(-found.fun)


def closed_end_window(law, A, B, P, la_max=8.0) -> dict:
    """The closed-end tube against pressure P: does it reach P on its first rising branch
    (`withstands`), and its limit point if any."""
    limit = closed_end_limit(law, A, B, la_max)
    return {"withstands": limit is None or limit[1] >= P, "limit": limit}
