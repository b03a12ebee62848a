"""ePSA geometry: the silicone body with its closed air chamber, the seal head, the fiber helices.

Body. In cylindrical coordinates (rho, theta, z) the silicone occupies
    {rho <= R0, 0 <= z <= L}  minus the chamber  {rho < r0, c < z < L - c},
with R0 the outer radius, r0 the chamber radius, L the length and c the end-cap thickness; the chamber
length is l_c = L - 2 c and the silicone volume V = pi (R0^2 L - r0^2 l_c). The surface is the outer
cylinder with its two end disks plus the chamber boundary with reversed orientation (a cavity): two
closed shells, which pytetwild meshes with the cavity left empty.

Boundary tags: ``outer`` (rho = R0), ``end_bottom`` (z = 0), ``end_top`` (z = L), ``chamber_wall``
(rho = r0, c <= z <= L - c, area 2 pi r0 l_c), ``chamber_ends`` (z = c and z = L - c, rho <= r0).

Seal head. An ABS disk of radius R0 and thickness t_s on top of the body, z in [L, L + t_s]
(its own part; the air inlet is not modelled, pressure acts on the closed chamber).

Fibers. Two helices on the outer surface, N turns each way over the length:
    x_pm(z) = (R0 cos(theta_pm), R0 sin(theta_pm), z),  theta_pm = theta0 +- 2 pi N z / L,  0 <= z <= L,
of length s = N sqrt((2 pi R0)^2 + (L/N)^2) each. They are sampled with ``points_per_turn`` vertices per
turn, all exactly on rho = R0; the polyline is shorter than the helix by the factor
sin(pi/n)/(pi/n) on the circumferential part (n = points per turn), 0.07 % for n = 48.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING

import numpy as np

from softcrawl.geometry.design import EPSADesign
from softcrawl.geometry.surfaces import flipped, merge, revolve_profile, subdivide_profile
from softcrawl.geometry.tagging import RevolvedSegment

if TYPE_CHECKING:
    import pyvista as pv

DEFAULT_N_THETA = 48


def body_profile(design: EPSADesign) -> np.ndarray:
    R, L = design.outer_radius, design.length
    return np.array([[0.0, 0.0], [R, 0.0], [R, L], [0.0, L]])


def chamber_profile(design: EPSADesign) -> np.ndarray:
    r, c, L = design.chamber_radius, design.end_cap_thickness, design.length
    return np.array([[0.0, c], [r, c], [r, L - c], [0.0, L - c]])


def epsa_surface(design: EPSADesign, n_theta: int = DEFAULT_N_THETA) -> pv.PolyData:
    """Closed outward-oriented surface of the body: outer shell + reversed chamber shell."""
    h = 2 * np.pi * design.outer_radius / n_theta
    outer = revolve_profile(subdivide_profile(body_profile(design), 4 * h), n_theta)
    chamber = revolve_profile(subdivide_profile(chamber_profile(design), 4 * h), n_theta)
    return merge(outer, flipped(chamber))


def epsa_segments(
    design: EPSADesign, centre: tuple[float, float] = (0.0, 0.0), z0: float = 0.0
) -> list[RevolvedSegment]:
    """Tagged exact boundary of the body (solid on the left of each segment)."""
    R, r, c, L = design.outer_radius, design.chamber_radius, design.end_cap_thickness, design.length
    return [
        RevolvedSegment("end_bottom", (0.0, z0), (R, z0), centre),
        RevolvedSegment("outer", (R, z0), (R, z0 + L), centre, curved=True),
        RevolvedSegment("end_top", (R, z0 + L), (0.0, z0 + L), centre),
        # chamber, walked with the silicone on the left (clockwise in the chamber's own sense)
        RevolvedSegment("chamber_ends", (r, z0 + c), (0.0, z0 + c), centre),
        RevolvedSegment("chamber_wall", (r, z0 + L - c), (r, z0 + c), centre, curved=True),
        RevolvedSegment("chamber_ends", (0.0, z0 + L - c), (r, z0 + L - c), centre),
    ]


def epsa_analytic_areas(design: EPSADesign) -> dict[str, float]:
    R, r, L, lc = design.outer_radius, design.chamber_radius, design.length, design.chamber_length
    return {
        "outer": 2 * np.pi * R * L,
        "end_bottom": np.pi * R**2,
        "end_top": np.pi * R**2,
        "chamber_wall": 2 * np.pi * r * lc,
        "chamber_ends": 2 * np.pi * r**2,
    }


def seal_head_profile(design: EPSADesign) -> np.ndarray:
    R, L, t = design.outer_radius, design.length, design.seal_head_thickness
    return np.array([[0.0, L], [R, L], [R, L + t], [0.0, L + t]])


def seal_head_surface(design: EPSADesign, n_theta: int = DEFAULT_N_THETA) -> pv.PolyData:
    h = 2 * np.pi * design.outer_radius / n_theta
    return revolve_profile(subdivide_profile(seal_head_profile(design), 4 * h), n_theta)


def seal_head_segments(design: EPSADesign, centre: tuple[float, float] = (0.0, 0.0)) -> list[RevolvedSegment]:
    R, L, t = design.outer_radius, design.length, design.seal_head_thickness
    return [
        RevolvedSegment("bottom", (0.0, L), (R, L), centre),
        RevolvedSegment("side", (R, L), (R, L + t), centre, curved=True),
        RevolvedSegment("top", (R, L + t), (0.0, L + t), centre),
    ]


def fiber_helices(
    design: EPSADesign, points_per_turn: int = 48, theta0: float = 0.0
) -> tuple[np.ndarray, ...]:
    """The double helix as two (n, 3) polylines on rho = R0 (empty tuple for N = 0)."""
    N = design.fiber_turns
    if N == 0:
        return ()
    n = N * points_per_turn + 1
    z = np.linspace(0.0, design.length, n)
    out = []
    for sign in (+1.0, -1.0):
        theta = theta0 + sign * 2 * np.pi * N * z / design.length
        out.append(
            np.column_stack([design.outer_radius * np.cos(theta), design.outer_radius * np.sin(theta), z])
        )
    return tuple(out)


def helix_families(design: EPSADesign) -> tuple[tuple[object, float], ...]:
    """The double helix smeared over the outer surface: one (direction, density) per hand.

    direction(X) maps reference points (3, n) to the helix tangents (3, n),
    e_z +- tan(alpha) e_theta with tan(alpha) = 2 pi R0 N / L; density is the number of fibers
    per unit width, N / (L sin(alpha)) (one fiber of length N 2 pi R0 / sin(alpha) per hand over
    the area 2 pi R0 L). Empty for N = 0. See `fem.sheets` for the mechanics."""
    N = design.fiber_turns
    if N == 0:
        return ()
    tan_alpha = 2 * np.pi * design.outer_radius * N / design.length
    density = N / (design.length * np.sin(np.arctan(tan_alpha)))

    def hand(sign: float) -> Callable[[np.ndarray], np.ndarray]:
        def direction(X: np.ndarray) -> np.ndarray:
            rho = np.hypot(X[0], X[1])
            e_theta = np.vstack([-X[1] / rho, X[0] / rho, np.zeros_like(rho)])
            return (
                np.vstack([np.zeros((2, X.shape[1])), np.ones((1, X.shape[1]))]) + sign * tan_alpha * e_theta
            )

        return direction

    return ((hand(+1.0), density), (hand(-1.0), density))


def fiber_polydata(fibers: Sequence[np.ndarray]) -> pv.MultiBlock:
    """pyvista lines of the fibers (for plotting)."""
    import pyvista as pv

    return pv.MultiBlock([pv.lines_from_points(f) for f in fibers]) if fibers else pv.MultiBlock()
