"""Constant-curvature kinematics of the three-ePSA body (paper Section III-C/D, eqs. 4-15).

Geometry (docs/DESIGN.md#units-and-conventions). The body axis is z at the rear foot; ePSA i sits at angle
psi_i on
a circle of radius d, psi = (90, 210, 330) deg. A configuration (kappa, theta, phi) is the
curvature, the bending angle and the direction of bending (phi measured from x, towards y).

Forward kinematics (eqs. 4-6). With Q = l1^2 + l2^2 + l3^2 - l1 l2 - l1 l3 - l2 l3,

    kappa = 2 sqrt(Q) / (d (l1 + l2 + l3)),   theta = 2 sqrt(Q) / (3 d),
    phi   = atan2(l2 + l3 - 2 l1, sqrt(3) (l2 - l3)).

Eq. (6) prints tan^-1 of the ratio; the quadrant is fixed by atan2 with the numerator and
denominator as printed, which is the exact inverse of the arc-length law below (checked:
l = (110, 125, 140) mm gives phi = 2 pi/3). Q is evaluated as ((l1-l2)^2 + (l1-l3)^2 +
(l2-l3)^2)/2 to avoid cancellation for nearly equal lengths. theta = kappa l_c with
l_c = (l1 + l2 + l3)/3 the centreline length.

Tip transform (eq. 9): T = Rz(phi) [Ry(theta), p] Rz(-phi), tip position
p = ((1 - cos theta)/kappa cos phi, (1 - cos theta)/kappa sin phi, sin theta / kappa). We evaluate
it as l_c * ((1 - cos theta)/theta, sin theta/theta) with sinc-based forms, so kappa -> 0 (straight)
needs no division by kappa: p -> (0, 0, l_c).

Exact inverse kinematics. From the tip (x, y, z): phi = atan2(y, x) (eq. 10); with r = sqrt(x^2 +
y^2), the tip of an arc of curvature kappa satisfies r = (1 - cos theta)/kappa, z = sin theta/kappa,
so tan(theta/2) = r/z and

    theta = 2 atan2(r, z),   kappa = 2 r / (r^2 + z^2),   l_c = theta / kappa,
    l_i = l_c - theta d cos(psi_i - phi)            ( = l_c (1 - kappa d cos(psi_i - phi)) ).

l_c = (r^2 + z^2) atan2(r, z)/r is evaluated with a series of atan(u)/u near r = 0, again without
dividing by kappa. At r = 0 phi is undefined and irrelevant (theta = 0). Valid for theta < 2 pi.

Deviation from the printed IK. Eq. (11) takes theta = atan(z / sqrt(x^2+y^2)), the elevation of the
tip, which is not the bending angle of an arc (theta/2 is the angle between the chord and z);
eqs. (13)-(15) use the chord 2 sin(l_c kappa/2)/kappa instead of the arc length and offsets
d sin(phi), d sin(60 deg + phi), d sin(30 deg + phi) that do not match psi = (90, 210, 330) deg.
For l = (110, 125, 140) mm, d = 14 mm they give (103.1, 117.2, 109.1) mm instead of the input
(`printed_ik_lengths` reproduces them for the record). The exact inverse above is used everywhere.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from softcrawl.analytic.errors import ModelInputError
from softcrawl.analytic.limits import MAX_LENGTH_MM, length_mm

PSI = np.deg2rad([90.0, 210.0, 330.0])


@dataclass(frozen=True)
class Configuration:
    """Arc configuration: curvature (1/mm), bending angle (rad), bending direction (rad), l_c (mm)."""

    kappa: float
    theta: float
    phi: float
    length: float


def _sinc(x: ArrayLike) -> np.ndarray:
    """sin(x)/x, stable at 0."""
    return np.sinc(np.asarray(x, dtype=float) / np.pi)


def _versinc(x: ArrayLike) -> np.ndarray:
    """(1 - cos x)/x = 2 sin^2(x/2)/x = (x/2) sinc(x/2)^2, stable at 0."""
    x = np.asarray(x, dtype=float)
    return 0.5 * x * _sinc(0.5 * x) ** 2


def _atan_over(u: ArrayLike) -> np.ndarray:
    """atan(u)/u, stable at 0 (series below |u| < 1e-4)."""
    u = np.asarray(u, dtype=float)
    small = np.abs(u) < 1e-4
    us = np.where(small, 1.0, u)
    return np.where(small, 1.0 - u * u / 3.0 + u**4 / 5.0, np.arctan(us) / us)


def _array(values: ArrayLike, parameter: str) -> np.ndarray:
    """`values` as a float array, or a `ModelInputError` (text, or integers beyond the float range)."""
    try:
        return np.asarray(values, dtype=float)
    except (TypeError, ValueError, OverflowError):
        raise ModelInputError(parameter, "must be numbers (mm) within the float range") from None


def forward(lengths: ArrayLike, d: float = 14.0) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Lengths (..., 3) in mm -> (kappa, theta, phi, l_c) arrays (eqs. 4-6)."""
    l = _array(lengths, "lengths")
    if l.shape[-1] != 3:
        raise ModelInputError("lengths", "need three ePSA lengths")
    d = length_mm(d, "d")
    if np.any(~np.isfinite(l)) or np.any(l <= 0) or np.any(l > MAX_LENGTH_MM):
        raise ModelInputError("lengths", f"must be finite and in (0, {MAX_LENGTH_MM:g}] mm")
    l1, l2, l3 = l[..., 0], l[..., 1], l[..., 2]
    q = 0.5 * ((l1 - l2) ** 2 + (l1 - l3) ** 2 + (l2 - l3) ** 2)
    s = np.sqrt(q)
    total = l1 + l2 + l3
    kappa = 2.0 * s / (d * total)
    theta = 2.0 * s / (3.0 * d)
    phi = np.arctan2(l2 + l3 - 2.0 * l1, np.sqrt(3.0) * (l2 - l3))
    return kappa, theta, phi, total / 3.0


def configuration(lengths: ArrayLike, d: float = 14.0) -> Configuration:
    k, t, p, lc = forward(lengths, d)
    return Configuration(float(k), float(t), float(p), float(lc))


def arc_point(theta: ArrayLike, phi: ArrayLike, length: ArrayLike) -> np.ndarray:
    """Position at bending angle theta along an arc of length `length` from the base (eq. 9's p).

    All arguments broadcast; returns (..., 3). theta = kappa * length.
    """
    theta = np.asarray(theta, dtype=float)
    phi = np.asarray(phi, dtype=float)
    length = np.asarray(length, dtype=float)
    rho = length * _versinc(theta)
    z = length * _sinc(theta)
    return np.stack(np.broadcast_arrays(rho * np.cos(phi), rho * np.sin(phi), z), axis=-1)


def arc_rotation(theta: ArrayLike, phi: ArrayLike) -> np.ndarray:
    """Rotation part of eq. (9), Rz(phi) Ry(theta) Rz(-phi), shape (..., 3, 3)."""
    theta = np.asarray(theta, dtype=float)
    phi = np.asarray(phi, dtype=float)
    theta, phi = np.broadcast_arrays(theta, phi)
    ct, st, cp, sp = np.cos(theta), np.sin(theta), np.cos(phi), np.sin(phi)
    r = np.empty(theta.shape + (3, 3))
    r[..., 0, 0] = cp * cp * ct + sp * sp
    r[..., 0, 1] = cp * sp * (ct - 1.0)
    r[..., 0, 2] = cp * st
    r[..., 1, 0] = cp * sp * (ct - 1.0)
    r[..., 1, 1] = sp * sp * ct + cp * cp
    r[..., 1, 2] = sp * st
    r[..., 2, 0] = -cp * st
    r[..., 2, 1] = -sp * st
    r[..., 2, 2] = ct
    return r


def planar_arc(kappa: ArrayLike, length: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Lateral and axial offsets of a planar arc of signed curvature kappa at arc length `length`.

    The bend-plane form of `arc_point` for phi = +-90 deg: lateral = length (1 - cos theta)/theta
    sign(kappa), axial = length sin(theta)/theta, theta = kappa length; both broadcast.
    """
    th = kappa * length
    return length * _versinc(np.abs(th)) * np.sign(kappa), length * _sinc(th)


def transform(lengths: ArrayLike, d: float = 14.0) -> np.ndarray:
    """Homogeneous tip transform T (eq. 9) for one set of lengths, 4 x 4."""
    k, t, p, lc = forward(lengths, d)
    T = np.eye(4)
    T[:3, :3] = arc_rotation(t, p)
    T[:3, 3] = arc_point(t, p, lc)
    return T


def tip(lengths: ArrayLike, d: float = 14.0) -> np.ndarray:
    """Tip position (..., 3) in mm."""
    k, t, p, lc = forward(lengths, d)
    return arc_point(t, p, lc)


def inverse_configuration(tip_xyz: ArrayLike) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Tip position (..., 3) -> (kappa, theta, phi, l_c); exact inverse of `arc_point`."""
    x = _array(tip_xyz, "tip")
    if x.shape[-1] != 3 or np.any(~np.isfinite(x)) or np.any(np.abs(x) > MAX_LENGTH_MM):
        raise ModelInputError("tip", f"need a finite (x, y, z) within +-{MAX_LENGTH_MM:g} mm")
    r = np.hypot(x[..., 0], x[..., 1])
    z = x[..., 2]
    if np.any((r == 0) & (z <= 0)):
        raise ModelInputError("tip", "a tip on the -z axis or at the origin is not an arc end")
    phi = np.where(r > 0, np.arctan2(x[..., 1], x[..., 0]), 0.0)
    theta = 2.0 * np.arctan2(r, z)
    rr = r * r + z * z
    kappa = 2.0 * r / rr
    # l_c = rr * atan2(r, z) / r, stable as r -> 0 with z > 0.
    zpos = z > 0
    zs = np.where(zpos, z, 1.0)
    rs = np.where(r > 0, r, 1.0)
    lc = np.where(zpos, rr / zs * _atan_over(r / zs), rr * np.arctan2(r, z) / rs)
    return kappa, theta, phi, lc


def inverse(tip_xyz: ArrayLike, d: float = 14.0) -> np.ndarray:
    """Tip position (..., 3) in mm -> ePSA lengths (..., 3) in mm (exact IK)."""
    d = length_mm(d, "d")
    kappa, theta, phi, lc = inverse_configuration(tip_xyz)
    lengths = lc[..., None] - (theta * d)[..., None] * np.cos(PSI - np.asarray(phi)[..., None])
    if np.any(lengths <= 0):
        raise ModelInputError("tip", "the tip needs a non-positive ePSA length")
    return lengths


def lengths_from_configuration(
    kappa: ArrayLike, phi: ArrayLike, lc: ArrayLike, d: float = 14.0
) -> np.ndarray:
    """l_i = l_c (1 - kappa d cos(psi_i - phi)), (..., 3)."""
    kappa = np.asarray(kappa, dtype=float)[..., None]
    phi = np.asarray(phi, dtype=float)[..., None]
    lc = np.asarray(lc, dtype=float)[..., None]
    return lc * (1.0 - kappa * d * np.cos(PSI - phi))


def printed_ik_lengths(kappa: float, phi: float, lc: float, d: float = 14.0) -> np.ndarray:
    """Eqs. (13)-(15) exactly as printed (for documentation; they do not invert eqs. 4-6)."""
    chord = 2.0 * np.sin(lc * kappa / 2.0)
    return np.array(
        [
            chord * (1.0 / kappa - d * np.sin(phi)),
            chord * (1.0 / kappa + d * np.sin(np.pi / 3 + phi)),
            chord * (1.0 / kappa - d * np.sin(np.pi / 6 + phi)),
        ]
    )
