r"""Fiber sheets: a family of parallel fibers smeared over a boundary surface of the solid.

Why. A fiber modelled as a line tied to a 3D continuum (`fem.fibers`) has a logarithmically
singular compliance: the silicone next to a zero-thickness line is loaded without bound, so mesh
refinement keeps resolving more bulging between the lines and the extension of the fibered ePSA
does not settle (56.8 / 61.7 / 64.3 mm at h = 10 / 5 / 3.33 mm, results/epsa-convergence). When
the fiber spacing is small against the wall, the fibers act as a membrane that is stiff along the
fiber direction only: the homogenised limit of the winding, which converges under refinement in
the usual way.

Model. A family is a unit reference direction field a(X) tangent to the surface Gamma and a line
density rho (fibers per unit width, 1/mm); every fiber has the axial stiffness E A (N). Along a
fiber the stretch is lam = |F a|, with F the solid's deformation gradient at the surface (the
sheet is tied to the solid), and the fiber force is E A (lam - 1) (Biot strain, as the trusses of
`fem.fibers`). The sheet's energy per unit reference area is

    psi(F) = c (lam - 1)^2 / 2,        c = E A rho   (N/mm)

with, writing n = F a / lam and T = c (lam - 1) (force per unit width),

    dpsi/dF_iJ = T n_i a_J,
    d2psi/dF_iJ dF_kL = a_J a_L k_ik,   k = c n n^T + T / lam (I - n n^T).

Discretised with the P2 shape functions N_a of the element next to each facet, s_a = grad N_a . a,
the facet residual and tangent are

    R_ai = int_Gamma T n_i s_a dA,      K_ai,bk = int_Gamma s_a s_b k_ik dA,

the truss formulas with the segment difference (N_b(end) - N_a(start)) / L0 replaced by s_a.
Tension-only fibers drop T and c where lam < 1.

A double helix of N turns per fiber over the length L of a cylinder of radius R is two families,
a_pm = (e_z +- tan(alpha) e_theta) cos(alpha) with tan(alpha) = 2 pi R N / L, each of density
rho = N / (L sin(alpha)): one fiber of length N 2 pi R / sin(alpha) per family over the area
2 pi R L (`geometry.epsa_shape.helix_sheet`).

The direction field is given on the exact surface; on the discrete (curved P2) facets it is
projected on the facet's tangent plane and normalised at each quadrature point.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from softcrawl.fem import p2_mapping
from softcrawl.fem.errors import SolverInputError


@dataclass(frozen=True)
class FiberSheet:
    """One fiber family smeared over the boundary `tag`.

    direction: callable (3, n) reference points -> (3, n) fiber directions (need not be unit).
    axial_stiffness: E A of one fiber (N); density: fibers per unit width (1/mm).
    """

    tag: str
    direction: Callable[[np.ndarray], np.ndarray] = field(repr=False)
    axial_stiffness: float
    density: float
    tension_only: bool = False

    def __post_init__(self):
        if not callable(self.direction):
            raise SolverInputError("fiber_sheet.direction", "must be a callable of the points (3, n)")
        for name in ("axial_stiffness", "density"):
            value = getattr(self, name)
            try:
                ok = np.isfinite(float(value)) and float(value) > 0
            except (TypeError, ValueError):
                ok = False
            if not ok:
                raise SolverInputError(f"fiber_sheet.{name}", f"must be a positive number, got {value!r}")
            object.__setattr__(self, name, float(value))

    @property
    def stiffness(self) -> float:
        """c = E A rho, the sheet's stiffness per unit width along the fibers (N/mm)."""
        return self.axial_stiffness * self.density


@dataclass(frozen=True)
class SheetQuadrature:
    """The sheets' facets and quadrature data (all families concatenated along the facet axis)."""

    s: np.ndarray = field(repr=False)  # (F, Q, 10): grad N_a . a at each point
    a: np.ndarray = field(repr=False)  # (F, Q, 3): unit reference directions
    c_dx: np.ndarray = field(repr=False)  # (F, Q): c times the area weight
    nodes: np.ndarray = field(repr=False)  # (F, 10): scalar P2 nodes of the facet's element
    axial: np.ndarray = field(repr=False)  # (F,): E A of the family (fiber force = E A (lam - 1))
    tension_only: np.ndarray = field(repr=False)  # (F,) bool
    reference_area: float  # summed over families
    facets: np.ndarray = field(default=None, repr=False)  # (F,): the mesh facet of each row (output)
    family: np.ndarray = field(default=None, repr=False)  # (F,): index of the FiberSheet (output)

    @property
    def dofs(self) -> np.ndarray:
        """(30, F) displacement dofs, local order 3 a + i (node a, component i)."""
        return (3 * self.nodes.T[:, None, :] + np.arange(3)[None, :, None]).reshape(30, -1)


def build(mesh, sheets, intorder: int = 4) -> SheetQuadrature:
    """Quadrature data of `sheets` (a sequence of `FiberSheet`) on `mesh` (P2 displacements)."""
    boundaries = mesh.boundaries or {}
    parts = []
    for index, sheet in enumerate(sheets):
        if not isinstance(sheet, FiberSheet):
            raise SolverInputError("fiber_sheets", f"expected FiberSheet items, got {type(sheet).__name__}")
        if sheet.tag not in boundaries or len(boundaries[sheet.tag]) == 0:
            raise SolverInputError(
                "fiber_sheet.tag", f"unknown or empty boundary tag {sheet.tag!r}; known: {sorted(boundaries)}"
            )
        fb = p2_mapping.facet_basis(mesh, boundaries[sheet.tag], intorder=intorder)
        X = np.asarray(fb.global_coordinates())  # (3, F, Q)
        d = np.asarray(sheet.direction(X.reshape(3, -1)), dtype=float)
        if d.shape != (3, X[0].size):
            raise SolverInputError(
                "fiber_sheet.direction",
                f"{sheet.tag}: the direction field must "
                f"return shape (3, {X[0].size}) for (3, {X[0].size}) points, got {d.shape}",
            )
        d = d.reshape(X.shape)
        n = fb.normals
        d = d - np.einsum("ifq,ifq->fq", d, n)[None] * n  # on the facet's tangent plane
        norm = np.linalg.norm(d, axis=0)
        if not np.all(np.isfinite(norm)) or norm.min() < 1e-9:
            raise SolverInputError(
                "fiber_sheet.direction",
                f"{sheet.tag}: the direction field is zero, normal to the surface or not finite somewhere",
            )
        a = d / norm
        dN = np.stack([phi[0].grad for phi in fb.basis])  # (10, 3, F, Q)
        parts.append(
            dict(
                s=np.einsum("aJfq,Jfq->fqa", dN, a),
                a=a.transpose(1, 2, 0),
                c_dx=sheet.stiffness * fb.dx,
                nodes=fb.element_dofs.T,
                axial=np.full(fb.dx.shape[0], sheet.axial_stiffness),
                tension_only=np.full(fb.dx.shape[0], sheet.tension_only),
                area=float(fb.dx.sum()),
                facets=np.asarray(boundaries[sheet.tag]),
                family=np.full(fb.dx.shape[0], index),
            )
        )
    if not parts:
        raise SolverInputError("fiber_sheets", "no fiber sheet given")
    cat = {k: np.ascontiguousarray(np.concatenate([p[k] for p in parts])) for k in parts[0] if k != "area"}
    return SheetQuadrature(
        cat["s"],
        cat["a"],
        cat["c_dx"],
        cat["nodes"],
        cat["axial"],
        cat["tension_only"],
        sum(p["area"] for p in parts),
        cat["facets"],
        cat["family"],
    )


def stretch(sq: SheetQuadrature, u_nodes: np.ndarray):
    """F a (F, Q, 3), the fiber stretch lam = |F a| and the strain lam - 1 (F, Q) from nodal
    displacements (n, 3). With g = grad u . a, lam^2 - 1 = 2 a.g + g.g, so the strain is
    (lam^2 - 1) / (lam + 1): exactly zero in the undeformed state (|a| = 1 only to round-off,
    and a round-off force would be a residual that Newton cannot remove under zero load)."""
    g = np.matmul(sq.s, u_nodes[sq.nodes])  # (F, Q, 10) @ (F, 10, 3)
    lam2_minus_1 = 2.0 * np.einsum("fqi,fqi->fq", sq.a, g) + np.einsum("fqi,fqi->fq", g, g)
    lam = np.sqrt(1.0 + lam2_minus_1)
    return sq.a + g, lam, lam2_minus_1 / (lam + 1.0)


def fiber_forces(sq: SheetQuadrature, u_nodes: np.ndarray) -> np.ndarray:
    """Force of one fiber, E A (lam - 1), at every quadrature point (F, Q) (N)."""
    _, _, strain = stretch(sq, u_nodes)
    force = sq.axial[:, None] * strain
    return np.where(sq.tension_only[:, None], np.maximum(force, 0.0), force)


def element_arrays(sq: SheetQuadrature, u_nodes: np.ndarray, with_tangent: bool = True):
    """Facet residual (30, F) and tangent (F, 30, 30), local dof 3 a + i."""
    Fa, lam, strain = stretch(sq, u_nodes)
    n = Fa / np.maximum(lam, 1e-12)[..., None]  # a fiber crushed to a point has no direction
    slack = sq.tension_only[:, None] & (strain < 0.0)
    T_dx = np.where(slack, 0.0, sq.c_dx * strain)  # T dA
    R = np.einsum("fqa,fq,fqi->fai", sq.s, T_dx, n).reshape(-1, 30).T
    if not with_tangent:
        return R, None
    c_dx = np.where(slack, 0.0, sq.c_dx)
    nn = n[..., :, None] * n[..., None, :]
    k = c_dx[..., None, None] * nn + (T_dx / np.maximum(lam, 1e-12))[..., None, None] * (
        np.eye(3) - nn
    )  # (F, Q, 3, 3)
    K = np.einsum("fqa,fqb,fqik->faibk", sq.s, sq.s, k, optimize=True)
    return R, K.reshape(-1, 30, 30)
