r"""The squeezed skirt: stability of the foot inserted into a pipe, against the mesh.

A 78 mm skirt in a 60 mm pipe is hoop-compressed (its tip at r / rho0 ~ 0.71-0.77): a shell
under hoop compression wrinkles. This module takes the foot of `studies.foot.model` (revolved
mesh, P2-P1, the frictionless insertion of the foot study) and asks of its inserted state:
  force     the wall's normal force on the foot (N, both faces: the "insertion force");
  stability the number of unstable modes, neg(K) - neg(K_pp) (`fem.stability`), at the end of
            the frictionless insertion (friction would make the tangent non-symmetric);
  lobes     the dominant circumferential harmonic n of the lowest mode (`lobe_spectrum`).

Fundamental state on a fine mesh (`map_axisymmetric`). The perfect foot and its mesh are
invariant under rotation by one sector, so the path of the insertion is axisymmetric until it
branches: u = u_r(rho, z) e_r + u_z(rho, z) e_z, p = p(rho, z). On meshes that share the section
(same cells through the skirt, same cell size) and differ only in sectors, the inserted state is
computed on the coarse one (`SOURCE_SECTORS`) and carried to the fine one node by node: a fine
node whose (rho, z) is a node of the coarse mesh's theta = 0 plane takes its u_r, u_z, p
(vertices, midsides in the section and on the revolved faces); the others (midsides of interior
circumferential and diagonal edges) take the mean of their edge's ends. One load step of Newton
at the pipe's wall (with the Uzawa updates of the foot study) then puts it in equilibrium on the
fine mesh. Newton keeps the symmetry of its start to round-off, so it lands on the fundamental
(axisymmetric) branch, stable or not. Checked once on the default mesh (48 x 3): the carried
state gives the direct insertion's force (199.00 N) and unstable count (9)
(docs/decisions/068-squeezed-skirt.md).

Following the path past the bifurcation (`seeded_mesh`). The lowest unstable mode phi,
scaled to `SEED_MM` at its largest nodal displacement, is added to the reference geometry
(X <- X + a phi on every P2 node); the imperfect foot is inserted from clear of the wall as in
the foot study. It then follows the branch that the mode starts instead of the fundamental one.

Self-contact (`self_gap`). Where a crease folds onto itself, two parts of the skirt's surface
that were apart meet. The closest approach of two boundary nodes of the skirt (front, back,
rim) that started more than `APART_MM` apart (beyond the 3 mm thickness: front and back faces
of the same section are not a fold) measures it. It is a node-to-node distance, so it is above
the true face-to-face gap by at most the sagitta of a facet; a gap of a few tenths of a mm or
more means no self-contact is needed.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree
from skfem import MeshTet2

from softcrawl.analytic.pipe import Pipe
from softcrawl.fem.contact_stages import Stage, run_stages
from softcrawl.fem.cyclic import CyclicStability, cyclic_stability, cyclic_symmetry
from softcrawl.fem.rigid_surfaces import CylinderWall
from softcrawl.fem.stability import Stability, stability
from softcrawl.geometry.foot_meshers import mesh_foot_with
from softcrawl.studies.foot.model import (
    AUGMENT,
    FOOT_NEWTON,
    MAX_CUTBACKS,
    MIN_STEP_FRACTION,
    foot_model,
    insertion_wall,
)

#: Sectors of the mesh on which the axisymmetric inserted state is computed before it is carried
#: to a finer one (the fewest at which the contact faces' quadrature works, `studies.crawl.mesh`).
SOURCE_SECTORS = 24
#: ... except with these cells through the skirt: 24 sectors x 6 cells gives cells too flat for
#: the curved P2 facets' quadrature (`fem.discretisation.Discretisation.facet_basis` refuses it).
SOURCE_SECTORS_BY_CELLS = {6: 32}
#: Largest nodal displacement (mm) of the seeded mode: half the imperfection the first review
#: tried with cos(n theta) shapes (0.1 mm), 1/60 of the skirt's thickness.
SEED_MM = 0.05
#: Two skirt nodes are "apart" (a fold, not the skirt's own thickness) beyond this (mm).
APART_MM = 4.5
#: Node pairs closer than this (mm) are searched for the gap; none: the gap is above it.
GAP_SEARCH_MM = 6.0
SKIRT_TAGS = ("front", "back", "rim")
TOL_MATCH = 1e-6  # mm: two nodes at the same (rho, z)


def source_sectors(cells: int) -> int:
    """Sectors of the mesh whose insertion is carried to finer ones with `cells` cells."""
    return SOURCE_SECTORS_BY_CELLS.get(cells, SOURCE_SECTORS)


def foot_mesh(design, sectors: int, cells: int) -> MeshTet2:
    """The revolved foot with `sectors` sectors and `cells` cells through the skirt (P2, curved)."""
    return mesh_foot_with(design, "revolved", sectors=sectors, thickness_layers=cells).to_skfem(2)


def seeded_mesh(mesh: MeshTet2, shape: np.ndarray, amplitude: float = SEED_MM) -> MeshTet2:
    """`mesh` with every P2 node moved by `amplitude` * shape / max |shape| (shape (3, n_nodes),
    in the node order of the mesh's P2 basis, which is that of its dof locations)."""
    scale = amplitude / np.linalg.norm(shape, axis=0).max()
    doflocs = np.ascontiguousarray(np.asarray(mesh.doflocs) + scale * shape)
    return MeshTet2(
        doflocs, np.ascontiguousarray(mesh.t), _boundaries=mesh.boundaries, _subdomains=mesh.subdomains
    )


def insert(model, design, pipe: Pipe, steps: int, max_wall_s=None, on_step=None):
    """The foot study's frictionless insertion (the wall shrinks to the pipe): StagedResult.
    `on_step(step)` runs after each converged sub-step, while the wall is where that step put
    it (a force evaluated later would be against the final wall)."""
    wall_at = insertion_wall(pipe, design.tip_radius + 0.5)
    stage = Stage("insert", surfaces={i: wall_at for i in range(len(model.contacts))}, steps=steps)
    return run_stages(
        model,
        [stage],
        options=FOOT_NEWTON,
        max_cutbacks=MAX_CUTBACKS,
        max_wall_s=max_wall_s,
        min_step_fraction=MIN_STEP_FRACTION,
        on_step=on_step,
        **AUGMENT,
    )


def settle(model, pipe: Pipe, x0: np.ndarray):
    """Equilibrium at the pipe's wall from the state x0 (one load step, Uzawa updates)."""
    wall = CylinderWall(pipe.radius)
    stage = Stage("settle", surfaces={i: (lambda s: wall) for i in range(len(model.contacts))}, steps=1)
    return run_stages(model, [stage], x0=x0, options=FOOT_NEWTON, max_cutbacks=MAX_CUTBACKS, **AUGMENT)


def normal_force(model, x) -> float:
    return float(sum(c.report(x).normal_force for c in model.contacts))


def state_stability(model, x) -> Stability:
    _, K = model.residual_and_tangent(x, 0.0, 0.0)
    return stability(K, model.free_dofs, model.n_u)


def cyclic_state_stability(model, x, sectors: int) -> tuple[Stability, CyclicStability]:
    """`state_stability` by cyclic symmetry (`fem.cyclic`: the same count, one harmonic at a time),
    and the per-harmonic result. The Stability's eigenvalues are the lowest found over all
    harmonics, each as often as it occurs in the whole mesh (twice for 0 < n < N/2: the waves
    Re and Im of omega^{n s} phi), with their modes on the free displacement dofs; every
    negative one is there, then the lowest positive ones found, up to the count + 4."""
    _, K = model.residual_and_tangent(x, 0.0, 0.0)
    pv = model.space.pressure_vertex if model.n_p else None
    sym = cyclic_symmetry(model.nodes, sectors, model.free_dofs, model.n_u, pv)
    cs = cyclic_stability(K, sym)
    iu = np.flatnonzero(np.asarray(model.free_dofs) < model.n_u)
    found = sorted((float(lam), h.n, i) for h in cs.harmonics for i, lam in enumerate(h.eigenvalues))
    lams, modes = [], []
    for lam, n, i in found:
        if len(lams) >= cs.n_unstable + 4:
            break
        h = cs.harmonics[n]
        for part in ("real", "imag")[: h.multiplicity]:
            lams.append(lam)
            modes.append(sym.mode_on_free_dofs(h.modes[:, i], n, part)[iu])
    st = Stability(
        cs.n_unstable, cs.tangent, cs.pressure_block, np.array(lams), np.column_stack(modes), cs.asymmetry
    )
    return st, cs


def mode_field(model, vector: np.ndarray) -> np.ndarray:
    """A mode on the free displacement dofs -> nodal displacements (3, n_nodes)."""
    full = np.zeros(model.n_dofs)
    free = np.asarray(model.free_dofs)
    full[free[free < model.n_u]] = vector
    return model.displacement(full)


def _cylindrical(nodes):
    rho = np.hypot(nodes[0], nodes[1])
    theta = np.arctan2(nodes[1], nodes[0])
    return rho, theta, nodes[2]


def lobe_spectrum(nodes: np.ndarray, u: np.ndarray, n_max: int | None = None) -> np.ndarray:
    """Power of each circumferential harmonic n = 0..n_max of the field u (3, n) at `nodes`:
    nodes are grouped into rings of equal (rho, z); on each ring the cylindrical components
    (u_r, u_theta, u_z) are projected on exp(i n theta); the powers are summed over rings and
    components. The dominant n is the lobe count."""
    rho, theta, z = _cylindrical(nodes)
    c, s = np.cos(theta), np.sin(theta)
    comps = np.stack([c * u[0] + s * u[1], -s * u[0] + c * u[1], u[2]])
    key = np.round(np.column_stack([rho, z]) / TOL_MATCH).astype(np.int64)
    _, ring, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    ring = ring.reshape(-1)
    n_max = n_max if n_max is not None else int(counts.max() // 2)
    power = np.zeros(n_max + 1)
    harmonics = np.arange(n_max + 1)
    for r in np.flatnonzero(counts >= 8):
        idx = np.flatnonzero(ring == r)
        phase = np.exp(-1j * np.outer(harmonics, theta[idx]))  # (n, m)
        coeff = phase @ comps[:, idx].T / idx.size  # (n, 3)
        power += np.sum(np.abs(coeff) ** 2, axis=1)
    return power


@dataclass(frozen=True)
class Gap:
    """Closest approach (mm) of two skirt nodes that started more than `APART_MM` apart, the
    tags they lie on and their reference distance; inf when none came within `GAP_SEARCH_MM`."""

    gap: float
    tags: tuple[str, str]
    apart: float


def self_gap(model, x) -> Gap:
    tag_of = {}
    for tag in SKIRT_TAGS:
        for node in model.boundary_nodes(tag):
            tag_of.setdefault(int(node), tag)
    nodes = np.array(sorted(tag_of))
    X = model.nodes[:, nodes].T
    xd = X + model.displacement(x)[:, nodes].T
    pairs = cKDTree(xd).query_pairs(GAP_SEARCH_MM, output_type="ndarray")
    if pairs.size == 0:
        return Gap(float("inf"), ("", ""), float("nan"))
    ref = np.linalg.norm(X[pairs[:, 0]] - X[pairs[:, 1]], axis=1)
    pairs, ref = pairs[ref > APART_MM], ref[ref > APART_MM]
    if pairs.size == 0:
        return Gap(float("inf"), ("", ""), float("nan"))
    d = np.linalg.norm(xd[pairs[:, 0]] - xd[pairs[:, 1]], axis=1)
    i = int(np.argmin(d))
    a, b = nodes[pairs[i]]
    return Gap(float(d[i]), (tag_of[int(a)], tag_of[int(b)]), float(ref[i]))


def _edge_ends(mesh) -> np.ndarray:
    """(2, n_edges) vertex pairs of the P2 edge nodes, in the basis' order (vertices, then edges)."""
    return np.asarray(mesh.edges)


def map_axisymmetric(source, x_source: np.ndarray, target) -> np.ndarray:
    """The axisymmetric state x_source of model `source` carried to model `target`, whose mesh
    has the same section and more sectors (module docstring); raises if a section node is missing."""
    rho_s, th_s, z_s = _cylindrical(source.nodes)
    u_s = source.displacement(x_source)
    plane = (np.abs(th_s) < 1e-9) & (rho_s > 0)
    ur = np.cos(th_s[plane]) * u_s[0, plane] + np.sin(th_s[plane]) * u_s[1, plane]
    uz = u_s[2, plane]
    tree = cKDTree(np.column_stack([rho_s[plane], z_s[plane]]))
    rho, th, z = _cylindrical(target.nodes)
    dist, near = tree.query(np.column_stack([rho, z]))
    hit = dist < TOL_MATCH
    u = np.zeros((3, target.nodes.shape[1]))
    u[0, hit] = ur[near[hit]] * np.cos(th[hit])
    u[1, hit] = ur[near[hit]] * np.sin(th[hit])
    u[2, hit] = uz[near[hit]]
    mesh = target.mesh
    n_v = mesh.nvertices
    if not hit[:n_v].all():
        raise ValueError("the target mesh's section is not the source's: a vertex has no match")
    ends = _edge_ends(mesh)
    miss = np.flatnonzero(~hit)
    u[:, miss] = 0.5 * (u[:, ends[0, miss - n_v]] + u[:, ends[1, miss - n_v]])
    x = target.initial_state()
    x[: target.n_u] = u.T.reshape(-1)
    if target.n_p:
        # P1 pressures on vertices: the source's theta = 0 vertex at the same (rho, z)
        p_src = np.full(len(rho_s), np.nan)
        p_src[source.space.pressure_vertex] = x_source[source.n_u :]
        p_plane = p_src[plane]
        vert = target.space.pressure_vertex
        x[target.n_u :] = p_plane[near[vert]]
        if np.isnan(x[target.n_u :]).any():
            raise ValueError("a pressure vertex of the target has no source pressure")
    return target.apply_dirichlet(x, 0.0)


def build_model(mesh, material, design):
    """The foot study's model (two contact faces against the wall, hub top held), no drag."""
    return foot_model(mesh, material, design, 0.0, 0.0)
