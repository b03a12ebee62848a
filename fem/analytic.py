r"""Closed-form solutions for incompressible Neo-Hookean solids (shear modulus mu),
docs/decisions/010-verification.md.

Uniaxial stretch lam, free lateral faces: nominal stress  P = mu (lam - lam^-2).
Thick tube, plane strain, radii A < B, inner stretch la = a/A, lb^2 = (la^2 A^2 + B^2 - A^2)/B^2:
    P = mu [ ln(la/lb) + (lb^-2 - la^-2)/2 ]          (monotone in la)
  wrapped in a hoop fiber sheet of stiffness c (N/mm, `fem.sheets`) on r = B: the sheet's hoop
  force per unit length T = c (lb - 1) acts on the outer surface as a pressure T / b (b = lb B),
    P = mu [ ln(la/lb) + (lb^-2 - la^-2)/2 ] + c (lb - 1) / (lb B)
Thick sphere, radii A < B, lb^3 = 1 + (la^3 - 1)(A/B)^3, F(l) = -1/l - 1/(4 l^4):
    P = 2 mu [ F(la) - F(lb) ]                        (has a maximum: the limit point)
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq, minimize_scalar


def uniaxial_nominal_stress(mu, stretch):
    return mu * (stretch - stretch**-2)


def tube_outer_stretch(la, A, B):
    return np.sqrt((la**2 * A**2 + B**2 - A**2) / B**2)


def tube_pressure(mu, la, A, B, hoop_sheet=0.0):
    lb = tube_outer_stretch(la, A, B)
    return mu * (np.log(la / lb) + 0.5 * (lb**-2 - la**-2)) + hoop_sheet * (lb - 1) / (lb * B)


def tube_inner_stretch(mu, pressure, A, B, hoop_sheet=0.0):
    """Inverse of `tube_pressure` (monotone), by bracketing."""
    if pressure <= 0:
        return 1.0
    hi = 2.0
    while tube_pressure(mu, hi, A, B, hoop_sheet) < pressure:
        hi *= 2
        if hi > 1e6:
            raise ValueError("pressure above the tube's asymptote")
    return brentq(lambda la: tube_pressure(mu, la, A, B, hoop_sheet) - pressure, 1.0, hi, xtol=1e-14)


def sphere_outer_stretch(la, A, B):
    return np.cbrt(1 + (la**3 - 1) * (A / B) ** 3)


def sphere_pressure(mu, la, A, B):
    def F(l):
        return -1 / l - 1 / (4 * l**4)

    return 2 * mu * (F(la) - F(sphere_outer_stretch(la, A, B)))


def sphere_limit(mu, A, B):
    """(inner stretch, pressure) at the pressure maximum."""
    res = minimize_scalar(
        lambda la: -sphere_pressure(mu, la, A, B),
        bounds=(1.0, 5.0),
        method="bounded",
        options={"xatol": 1e-12},
    )
    return float(res.x), float(-res.fun)


def sphere_cavity_volume_octant(la, A):
    return np.pi / 6 * (la * A) ** 3
