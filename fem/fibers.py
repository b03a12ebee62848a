r"""Embedded (tied) fibers: truss segments whose end points follow the solid.

Each fiber point X_k sits in a host tetrahedron e_k at reference coordinates xi_k; its position
follows the solid's P2 displacement through the element shape functions (the embedded-element
or *Tie* idea of the paper's Abaqus model):

    x_k = X_k + sum_a N_a(xi_k) u_a       (a over the 10 nodes of e_k)

A segment (k, l) of reference length L0 and current vector d = x_l - x_k, l = |d|, n = d / l,
stretch lam = l / L0, carries the axial force (linear elastic, Biot strain)

    N = E A (lam - 1)                     (tension-only: N = max(N, 0))

with energy E A L0 (lam - 1)^2 / 2. Its force on x_l is N n (and -N n on x_k); its tangent in
(x_k, x_l) is k_s [[1, -1], [-1, 1]] (x) (E A / L0 n n^T + N / l (I - n n^T)); both are mapped to
the host nodes with the weights N_a(xi). A = pi d_f^2 / 4 from the fiber diameter.

Locating fiber points. Fibers lie on the curved outer surface, where scikit-fem's isoparametric
element finder does not converge; we take the 16 tetrahedra with the nearest centroids, keep the
one whose straight (vertex) tetrahedron has the largest smallest barycentric coordinate, and refine
xi by Newton's method on that element's quadratic map. A point may lie a sagitta (O(h^2)) outside
its host's reference tetrahedron; the shape functions extrapolate smoothly over that distance.
Points farther than `max_outside` (barycentric) from every host raise a `SolverInputError`.

Limits. A line tied to a 3D continuum has a logarithmically singular compliance: the solid
around a zero-thickness fiber is resolved more softly on every finer mesh, so results with line
fibers do not converge under refinement (Table 1 ePSA at 100 kPa: extension 56.8 / 61.7 /
64.3 mm at h = 10 / 5 / 3.33 mm). `fem.sheets` smears the winding into fiber families on the
surface, which converges; the lines remain for the paper's embedded-element model and for
strand-level fiber forces.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import skfem
from scipy.spatial import cKDTree

from softcrawl.fem.errors import SolverInputError


@dataclass(frozen=True)
class FiberLines:
    """Fibers to embed: reference polylines (each (n, 3), mm), Young's modulus (MPa), diameter
    (mm), and whether they carry tension only."""

    polylines: tuple = field(repr=False)
    youngs: float
    diameter: float
    tension_only: bool = False


@dataclass(frozen=True)
class FiberSet:
    """Fiber polylines embedded in a P2 basis (all arrays concern fiber points or segments)."""

    points: np.ndarray = field(repr=False)  # (n, 3) reference positions
    segments: np.ndarray = field(repr=False)  # (s, 2) point indices
    fiber_of_segment: np.ndarray = field(repr=False)  # (s,) polyline index
    host_nodes: np.ndarray = field(repr=False)  # (n, 10) scalar P2 node numbers
    weights: np.ndarray = field(repr=False)  # (n, 10) shape-function values
    youngs: float  # MPa
    area: float  # mm^2
    tension_only: bool = False

    @property
    def reference_lengths(self) -> np.ndarray:
        d = self.points[self.segments[:, 1]] - self.points[self.segments[:, 0]]
        return np.linalg.norm(d, axis=1)

    @property
    def n_segments(self) -> int:
        return self.segments.shape[0]


def embed(basis: skfem.CellBasis, lines: FiberLines, max_outside: float = 0.05) -> FiberSet:
    """Locate every polyline point in `basis` (scalar ElementTetP2) and build the fiber set."""
    polylines, youngs, diameter, tension_only = (
        lines.polylines,
        lines.youngs,
        lines.diameter,
        lines.tension_only,
    )
    if not np.isfinite(youngs) or youngs <= 0:
        raise SolverInputError("fiber_youngs", f"must be positive, got {youngs} MPa")
    if not np.isfinite(diameter) or diameter <= 0:
        raise SolverInputError("fiber_diameter", f"must be positive, got {diameter} mm")
    polylines = [np.asarray(p, dtype=float) for p in polylines if len(p) >= 2]
    if not polylines:
        raise SolverInputError("fibers", "no fiber polyline with two or more points")
    points = np.vstack(polylines)
    segs, owner, start = [], [], 0
    for i, p in enumerate(polylines):
        k = np.arange(start, start + len(p) - 1)
        segs.append(np.column_stack([k, k + 1]))
        owner.append(np.full(len(p) - 1, i))
        start += len(p)
    hosts, xi = _locate(basis, points, max_outside)
    phi = _shape_values(basis.elem, xi)  # (10, n)
    return FiberSet(
        points,
        np.vstack(segs),
        np.concatenate(owner),
        basis.element_dofs[:, hosts].T.copy(),
        phi.T.copy(),
        float(youngs),
        float(np.pi * diameter**2 / 4),
        bool(tension_only),
    )


def _shape_values(elem, xi):
    return np.stack([elem.lbasis(xi, i)[0] for i in range(elem.doflocs.shape[0])])


def _shape_gradients(elem, xi):
    return np.stack([elem.lbasis(xi, i)[1] for i in range(elem.doflocs.shape[0])])  # (10, 3, n)


def _locate(basis, points, max_outside):
    verts = basis.mesh.p[:, basis.mesh.t]  # (3, 4, E) straight tets
    tree = cKDTree(verts.mean(axis=1).T)
    _, cand = tree.query(points, k=min(16, verts.shape[2]))
    hosts, xi, excess = _refine(basis, points, np.atleast_2d(cand))
    lost = np.flatnonzero(excess > 1e-6)
    if lost.size:  # elongated cells: the nearest centroids can miss the host; search them all
        inside = np.array([_straight_containing(verts, p) for p in points[lost]])
        h2, xi2, ex2 = _refine(basis, points[lost], inside)
        better = ex2 < excess[lost]
        hosts[lost[better]], xi[:, lost[better]], excess[lost[better]] = (
            h2[better],
            xi2[:, better],
            ex2[better],
        )
    if excess.max() > max_outside:
        k = int(excess.argmax())
        raise SolverInputError(
            "fibers",
            f"fiber point {points[k].round(4).tolist()} lies outside the "
            f"solid (barycentric excess {excess[k]:.3g} > {max_outside})",
        )
    return hosts, xi


def _straight_containing(verts, p, n=4):
    """The n tets of all whose straight barycentric coordinates at p are the least negative."""
    D = np.moveaxis(verts[:, 1:, :] - verts[:, :1, :], -1, 0)  # (E, 3, 3): columns v_j - v0
    lam = np.linalg.solve(D, (p[:, None] - verts[:, 0, :]).T[..., None])[..., 0]
    worst = np.minimum(1 - lam.sum(axis=1), lam.min(axis=1))
    return np.argsort(-worst)[:n]


def _refine(basis, points, cand):
    """Best host among candidate elements `cand` (n, k) and the reference coordinates of each
    point on its quadratic map; returns hosts (n,), xi (3, n) and the barycentric excess (n,)."""
    verts = basis.mesh.p[:, basis.mesh.t]
    # barycentric coordinates in each candidate's straight tetrahedron
    v0 = verts[:, 0, :][:, cand]  # (3, n, k)
    D = verts[:, 1:, :][:, :, cand] - v0[:, None]  # (3, 3, n, k): columns v_j - v0
    Dm = np.moveaxis(D, (0, 1), (-2, -1))  # (n, k, 3, 3)
    rhs = np.moveaxis(points.T[:, :, None] - v0, 0, -1)  # (n, k, 3)
    lam123 = np.linalg.solve(Dm, rhs[..., None])[..., 0]  # (n, k, 3)
    lam = np.concatenate([1 - lam123.sum(-1, keepdims=True), lam123], axis=-1)
    n_try = min(4, cand.shape[1])
    order = np.argsort(-lam.min(axis=-1), axis=1)[:, :n_try]  # most-inside straight tets first
    rows = np.arange(points.shape[0])[:, None]
    hosts = cand[rows, order].reshape(-1)  # (n * n_try,)
    xi = lam123[rows, order].reshape(-1, 3).T.copy()  # (3, n * n_try) initial guesses
    target = np.repeat(points, n_try, axis=0).T
    # Newton on each candidate's quadratic map x(xi) = sum_a X_a N_a(xi)
    X = basis.doflocs[:, basis.element_dofs[:, hosts]]  # (3, 10, m)
    for _ in range(10):
        N = _shape_values(basis.elem, xi)  # (10, m)
        dN = _shape_gradients(basis.elem, xi)  # (10, 3, m)
        r = target - np.einsum("ian,an->in", X, N)
        Jm = np.einsum("ian,ajn->nij", X, dN)
        step = np.linalg.solve(Jm, r.T[..., None])[..., 0].T
        xi += step
        if np.abs(step).max() < 1e-13:
            break
    excess = -np.minimum(np.vstack([1 - xi.sum(0), xi]).min(axis=0), 0).reshape(-1, n_try)
    pick = excess.argmin(axis=1)
    sel = np.arange(points.shape[0]) * n_try + pick
    return hosts[sel], xi[:, sel], excess[np.arange(points.shape[0]), pick]


def fiber_state(fibers: FiberSet, u_nodes: np.ndarray):
    """Current fiber point positions (n, 3) from nodal displacements (n_nodes, 3)."""
    du = np.einsum("na,nai->ni", fibers.weights, u_nodes[fibers.host_nodes])
    return fibers.points + du


def segment_forces(fibers: FiberSet, x_points: np.ndarray):
    """Axial force N (s,), unit direction n (s, 3), current length l (s,), reference length L0 (s,)."""
    d = x_points[fibers.segments[:, 1]] - x_points[fibers.segments[:, 0]]
    l = np.linalg.norm(d, axis=1)
    L0 = fibers.reference_lengths
    N = fibers.youngs * fibers.area * (l / L0 - 1.0)
    if fibers.tension_only:
        N = np.maximum(N, 0.0)
    return N, d / l[:, None], l, L0


def element_arrays(fibers: FiberSet, u_nodes: np.ndarray, with_tangent=True):
    """Segment residual (60, s) and tangent (s, 60, 60) on the 2 x 10 host nodes x 3 components.

    Local dof order: (end, node a, component i) -> 30 * end + 3 * a + i.
    """
    xp = fiber_state(fibers, u_nodes)
    N, n, l, L0 = segment_forces(fibers, xp)
    W = np.stack([fibers.weights[fibers.segments[:, 0]], fibers.weights[fibers.segments[:, 1]]])  # (2, s, 10)
    sign = np.array([-1.0, 1.0])
    f_end = sign[:, None, None] * (N[:, None] * n)[None]  # (2, s, 3)
    R = np.einsum("esa,esi->eais", W, f_end).reshape(60, -1)
    if not with_tangent:
        return R, None
    EA = fibers.youngs * fibers.area
    k_axial = np.where(N > 0, EA, 0.0) if fibers.tension_only else np.full_like(N, EA)
    nn = np.einsum("si,sj->sij", n, n)
    k3 = (k_axial / L0)[:, None, None] * nn + (N / l)[:, None, None] * (np.eye(3) - nn)  # (s, 3, 3)
    SW = (sign[:, None, None] * W).transpose(1, 0, 2).reshape(-1, 20)  # (s, end a)
    K = SW[:, :, None, None, None] * SW[:, None, None, :, None] * k3[:, None, :, None, :]
    K = K.reshape(-1, 60, 60)  # s, (end a i), (end b j)
    return R, K


def segment_dofs(fibers: FiberSet) -> np.ndarray:
    """(60, s) global displacement dofs of the two host elements of each segment."""
    nodes = np.stack([fibers.host_nodes[fibers.segments[:, 0]], fibers.host_nodes[fibers.segments[:, 1]]])
    return (3 * nodes[:, :, :, None] + np.arange(3)).transpose(0, 2, 3, 1).reshape(60, -1)
