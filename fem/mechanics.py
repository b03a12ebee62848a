r"""Total-Lagrangian large-strain solid on quadratic tetrahedra, with a follower chamber pressure.

Unknowns. Displacements u on the P2 nodes (dof 3*node + i, node numbering of scikit-fem's scalar
`ElementTetP2` basis) and, for the mixed formulation, a continuous P1 pressure p on the vertices
(Taylor-Hood P2-P1, inf-sup stable, so it does not lock as K/mu -> infinity). The mixed energy is

    Pi(u, p) = int_Omega [ W_iso(F) + p (J - 1) - p^2 / (2K) ] dV  -  P * V_cav(u)

and the displacement-only formulation ("p2") uses the full W(F) of `fem.neohooke` instead.

Residuals (test functions du, dp):
    R_u = int (P_iso + p J F^{-T}) : grad du dV  -  P q(u),     R_p = int (J - 1 - p/K) dp dV
Chamber pressure P is a follower load: it acts on the deformed chamber surface. With Nanson's
formula n da = cof(F) N dA, and N the outward normal of the solid (it points into the cavity),
the cavity's volume and its derivative are

    V_cav = -1/sum(w) int_Gamma sum_i w_i x_i (cof F N)_i dA,    q = dV_cav/du = -int_Gamma (cof F N) . du dA

so the pressure load is P q(u) and its consistent tangent is P dq/du with
d(cof F)_iJ / dF_kL = J (H_iJ H_kL - H_iL H_kJ), H = F^{-T}. The weights w drop the flux through
cut planes (symmetry planes through the origin contribute nothing; a plane-strain cap z = H does
unless w_z = 0). The tangent is non-symmetric element by element; Newton converges quadratically.

Dirichlet conditions fix components of u on tagged boundaries to `factor * value`; the constrained
dofs are condensed out through a fixed sparsity pattern (`fem.pattern`). Reactions are the
internal forces on the constrained dofs. Dead loads (a weight on the free end, for the static
identification of the paper's Section VII-A) are a constant nodal force vector f_dead, scaled by the
same load factor f: R = f_int - P q - f f_dead; they add nothing to the tangent.

Assembly is vectorised over all elements and quadrature points (batched matrix products), never a
per-basis-function loop: see DESIGN.md section 7 for why this matters. The pointwise algebra (F,
J, F^-T, P) runs on contiguous component arrays of the whole mesh; the element matrices are built
per chunk of elements (temporaries stay in cache) on the assembly threads (`fem.parallel`) and
written straight into the sparsity pattern's value array, only the upper half of each symmetric
element matrix (`fem.pattern.Mirrored`). On the 3,840-tet benchmark tube (19,431 DOFs, 2 cores)
an assembly went from ~230 ms to ~75 ms (one thread) against ~350 ms for a PARDISO solve
(bench/assembly_bench.py).

Why P2-P1 (measured: plane-strain tube A = 1, B = 20 mm, K/mu = 1000, geometric radial grading,
`fem.verification.tube_test`, pressure ramp to 0.5 mu and then 2 mu):

    formulation  cells (radial x around)  DOFs   Newton iterations   inner-radius error
    p2p1         6 x 4                    1123   56                  5.5e-4 (0.5 mu), 2.8e-3 (2 mu)
    p2p1         12 x 8                   4059   50                  2.3e-5 (0.5 mu), 1.4e-3 (2 mu)
    p2p1         24 x 16                  15403  37                  4.9e-7 (0.5 mu), 1.6e-3 (2 mu)
    p2           6 x 4                    1053   317, stalls at 61 kPa ~ 2 mu
                                                 (and fails at 0.5 mu alone, 182 it.)
    p2           12 x 8                   3825   324, stalls at 62 kPa

The P2-P1 error at 0.5 mu converges at observed orders 4.6 and 5.6 (nodal superconvergence); at
2 mu it levels off at ~1.5e-3, which is the K/mu = 1000 compressibility against the incompressible
analytic solution: at K/mu = 1e5 the same meshes give 4.3e-3 and 1.7e-4 (order 4.7).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
import skfem

from fem import sheets
from fem.errors import SolverInputError
from fem.fibers import element_arrays as fiber_arrays
from fem.fibers import embed as embed_fibers
from fem.fibers import segment_dofs as fiber_segment_dofs
from fem.neohooke import NeoHookean, cofactor3, det3
from fem.parallel import for_chunks
from fem.pattern import Mirrored, Pattern

FORMULATIONS = ("p2p1", "p2")

#: Elements per chunk of the volume assembly (`fem.parallel.for_chunks`): small enough for the
#: temporaries of a chunk (~10 kB per element) to stay in a core's cache.
_CHUNK = 128


def _uu_entries():
    """The 465 stored entries (r, c) of the symmetric 30 x 30 K_uu, r = 10 i + a, c = 10 k + b:
    first the upper triangles of the three diagonal blocks i = k (the entries that get c g.g),
    then the blocks i < k."""
    r, c = np.triu_indices(30)
    first = r // 10 == c // 10
    return np.concatenate([r[first], r[~first]]), np.concatenate([c[first], c[~first]])


_UU_ROWS, _UU_COLS = _uu_entries()


def _uu_gather() -> np.ndarray:
    """Indices into [K_fh (900) | M (900)] of the terms K_fh[i a, k b] and M[k a, i b] of the
    stored K_uu entries [i a, k b] (see `SolidModel._tangent_chunk`)."""
    (i, a), (k, b) = np.divmod(_UU_ROWS, 10), np.divmod(_UU_COLS, 10)
    return np.concatenate([30 * _UU_ROWS + _UU_COLS, 900 + (10 * k + a) * 30 + 10 * i + b])


_UU_GATHER = _uu_gather()


def _view(a: np.ndarray, shape) -> np.ndarray:
    """A reshaped view of `a` (an error, never a silent copy: results are written into it)."""
    v = a.view()
    v.shape = shape
    return v


@dataclass(frozen=True)
class Dirichlet:
    """Displacement components `components` on boundary `tag` equal `factor * values` (mm)."""

    tag: str
    components: tuple[int, ...] = (0, 1, 2)
    values: tuple[float, ...] = (0.0, 0.0, 0.0)

    @classmethod
    def fixed(cls, tag: str) -> Dirichlet:
        return cls(tag, (0, 1, 2), (0.0, 0.0, 0.0))

    @classmethod
    def symmetry(cls, tag: str, axis: int) -> Dirichlet:
        """Symmetry plane normal to coordinate `axis`: zero normal displacement."""
        return cls(tag, (axis,), (0.0,))

    @classmethod
    def prescribed(cls, tag: str, component: int, value: float) -> Dirichlet:
        return cls(tag, (component,), (float(value),))


class _Stress(NamedTuple):
    F: np.ndarray  # (3, 3, E, Q)
    J: np.ndarray  # (E, Q)
    H: np.ndarray  # F^-T, (3, 3, E, Q)
    p: np.ndarray  # pressure, (E, Q)
    c: np.ndarray  # mu J^-2/3, (E, Q)
    I1: np.ndarray  # F:F, (E, Q)
    P: np.ndarray  # first Piola stress, (3, 3, E, Q)


class InvertedElement(ArithmeticError):
    """A trial state with det F <= 0 somewhere: the caller cuts the step back."""


class SolidModel:
    """A meshed solid with materials, Dirichlet conditions and an optional pressurised chamber.

    mesh: `skfem.MeshTet` (straight) or `skfem.MeshTet2` (curved), with named `boundaries`.
    materials: one `NeoHookean`, or a mapping subdomain name -> `NeoHookean`.
    chamber: boundary tags that form the pressurised chamber surface (None: no pressure load).
    fibers: polylines (reference positions, mm) of embedded truss fibers (`fem.fibers`), with
        `fiber_youngs` (MPa) and `fiber_diameter` (mm); None or empty: no fibers.
    fiber_sheets: `fem.sheets.FiberSheet` families smeared over boundary surfaces (the
        homogenised alternative to line fibers, which converges under mesh refinement).
    dead_loads: mapping boundary tag -> total force (Fx, Fy, Fz) in N, spread uniformly over the
        tag's reference area (a dead traction: it keeps its direction and magnitude as the body
        deforms, like a weight). It is scaled by the load factor f of the path, like the
        prescribed displacements.
    """

    def __init__(
        self,
        mesh,
        materials,
        *,
        dirichlet=(),
        chamber=None,
        formulation="p2p1",
        intorder=2,
        volume_weights=(1.0, 1.0, 1.0),
        fibers=None,
        fiber_youngs=None,
        fiber_diameter=None,
        fiber_tension_only=False,
        dead_loads=None,
        fiber_sheets=(),
    ):
        if formulation not in FORMULATIONS:
            raise SolverInputError("formulation", f"{formulation!r} is not one of {FORMULATIONS}")
        self.mesh = mesh
        self.formulation = formulation
        self.mixed = formulation == "p2p1"
        boundaries = mesh.boundaries or {}

        self.basis = skfem.Basis(mesh, skfem.ElementTetP2(), intorder=intorder)
        self.n_nodes = self.basis.N
        self.n_u = 3 * self.n_nodes
        self.nodes = self.basis.doflocs  # (3, n_nodes) reference positions
        self.dN = np.stack([phi[0].grad for phi in self.basis.basis])  # (10, 3, E, Q)
        self.dx = self.basis.dx  # (E, Q)
        self.node_dofs = self.basis.element_dofs  # (10, E)
        n_elem, n_qp = self.dx.shape
        # Element-first layouts of the shape-function gradients g[e, q, a, J] = dN_a/dX_J for the
        # batched products of the assembly: g_aqJ[e, a, 3 q + J] and g_qJa[e, q, J, a].
        self._g_aqJ = np.ascontiguousarray(self.dN.transpose(2, 0, 3, 1)).reshape(n_elem, 10, 3 * n_qp)
        self._g_qJa = np.ascontiguousarray(self.dN.transpose(2, 3, 1, 0))
        self._elem_nodes = np.ascontiguousarray(self.node_dofs.T)  # (E, 10)
        # g_a . g_b (a <= b, `np.triu_indices(10)`) at each quadrature point: (E, Q, 55)
        ta, tb = np.triu_indices(10)
        self._gg = np.ascontiguousarray(np.einsum("aJeq,aJeq->eqa", self.dN[ta], self.dN[tb]))
        # Local displacement dofs are component-major: local 10 i + a is component i of node a.
        self.u_dofs = (3 * self.node_dofs[None, :, :] + np.arange(3)[:, None, None]).reshape(30, -1)

        self.mu, self.bulk = _material_arrays(mesh, materials, n_elem)

        if self.mixed:
            self.pbasis = skfem.Basis(mesh, skfem.ElementTetP1(), quadrature=self.basis.quadrature)
            self.Np = np.stack([np.asarray(phi[0]) for phi in self.pbasis.basis])  # (4, E, Q)
            self._Np_qc = np.ascontiguousarray(self.Np.transpose(1, 2, 0))  # (E, Q, 4)
            self.p_dofs = self.n_u + self.pbasis.element_dofs  # (4, E)
            self.n_p = self.pbasis.N
            # K_pp = -int Np_c Np_d / K dV depends on the mesh and the material only.
            Kpp = -np.einsum("ceq,deq,eq->ecd", self.Np, self.Np, self.dx / self.bulk)
            self._Kpp_upper = Kpp[(slice(None),) + np.triu_indices(4)]  # (E, 10)
        else:
            self.n_p = 0
        self.n_dofs = self.n_u + self.n_p
        self.element_dofs = np.vstack([self.u_dofs, self.p_dofs]) if self.mixed else self.u_dofs
        self._elem_dofs = np.ascontiguousarray(self.element_dofs.T)  # (E, n_local)

        # Dirichlet conditions -> constrained dofs and their values at factor 1.
        self.dirichlet = tuple(dirichlet)
        fixed, values = [], []
        for bc in self.dirichlet:
            if bc.tag not in boundaries:
                raise SolverInputError(
                    "dirichlet", f"unknown boundary tag {bc.tag!r}; known: {sorted(boundaries)}"
                )
            if len(bc.components) != len(bc.values):
                raise SolverInputError("dirichlet", f"{bc.tag}: components and values differ in length")
            nodes = self.boundary_nodes(bc.tag)
            for c, v in zip(bc.components, bc.values):
                fixed.append(3 * nodes + c)
                values.append(np.full(nodes.size, float(v)))
        if fixed:
            dofs = np.concatenate(fixed)
            vals = np.concatenate(values)
            self.fixed_dofs, first = np.unique(dofs, return_index=True)
            self.fixed_values = vals[first]
        else:
            self.fixed_dofs = np.zeros(0, dtype=np.int64)
            self.fixed_values = np.zeros(0)
        self.free_index = np.full(self.n_dofs, -1, dtype=np.int64)
        self.free_dofs = np.setdiff1d(np.arange(self.n_dofs), self.fixed_dofs)
        self.free_index[self.free_dofs] = np.arange(self.free_dofs.size)

        # Chamber surface: facet basis of the adjacent elements.
        self.chamber = tuple(chamber) if chamber else ()
        self.volume_weights = np.asarray(volume_weights, dtype=float)
        # Volume blocks (symmetric element matrices): the upper triangle of K_uu and, for the
        # mixed formulation, K_up (standing for K_pu = K_up^T too) and the upper triangle of K_pp.
        uu = Mirrored(self.u_dofs[_UU_ROWS], self.u_dofs[_UU_COLS])
        groups = (
            [uu, Mirrored.block(self.u_dofs, self.p_dofs), Mirrored.upper(self.p_dofs)]
            if self.mixed
            else [uu]
        )
        self._n_volume_groups = len(groups)
        if self.chamber:
            for tag in self.chamber:
                if tag not in boundaries:
                    raise SolverInputError(
                        "chamber", f"unknown boundary tag {tag!r}; known: {sorted(boundaries)}"
                    )
            facets = np.concatenate([boundaries[t] for t in self.chamber])
            fb = skfem.FacetBasis(mesh, skfem.ElementTetP2(), facets=facets, intorder=4)
            self.f_N = np.stack([np.asarray(phi[0]) for phi in fb.basis])  # (10, F, Qf)
            self.f_dN = np.stack([phi[0].grad for phi in fb.basis])  # (10, 3, F, Qf)
            self.f_normal = fb.normals  # (3, F, Qf) solid outward
            self.f_dx = fb.dx
            self.f_node_dofs = fb.element_dofs  # (10, F)
            n_f = self.f_dx.shape[0]
            self._f_g_aqJ = np.ascontiguousarray(self.f_dN.transpose(2, 0, 3, 1)).reshape(n_f, 10, -1)
            self._f_g_qaJ = np.ascontiguousarray(self.f_dN.transpose(2, 3, 0, 1))  # (F, Qf, 10, 3)
            self._f_nodes = np.ascontiguousarray(self.f_node_dofs.T)
            self._f_Ndx = np.ascontiguousarray((self.f_N * self.f_dx).transpose(1, 0, 2))  # (F, 10, Qf)
            self.f_u_dofs = (3 * self.f_node_dofs[:, None, :] + np.arange(3)[None, :, None]).reshape(30, -1)
            groups.append(self.f_u_dofs)
        self.fibers = None
        if fibers is not None and len(fibers) > 0:
            if fiber_youngs is None or fiber_diameter is None:
                raise SolverInputError("fibers", "embedded fibers need fiber_youngs and fiber_diameter")
            self.fibers = embed_fibers(
                self.basis,
                fibers,
                youngs=fiber_youngs,
                diameter=fiber_diameter,
                tension_only=fiber_tension_only,
            )
            self.fiber_dofs = fiber_segment_dofs(self.fibers)
            groups.append(self.fiber_dofs)
        self.sheets = sheets.build(mesh, fiber_sheets) if fiber_sheets else None
        if self.sheets is not None:
            self.sheet_dofs = self.sheets.dofs
            groups.append(self.sheet_dofs)
        self.pattern = Pattern(self.free_index, groups)
        self._memo = None  # see `_at`
        self.dead_load = self._dead_load_vector(dead_loads or {})

    # ------------------------------------------------------------------ helpers
    def _dead_load_vector(self, dead_loads) -> np.ndarray:
        """f_dead = sum_tag (F_tag / A_tag) int_tag N_a dA on the u dofs (A_tag: reference area)."""
        out = np.zeros(self.n_dofs)
        boundaries = self.mesh.boundaries or {}
        for tag, force in dead_loads.items():
            if tag not in boundaries:
                raise SolverInputError(
                    "dead_loads", f"unknown boundary tag {tag!r}; known: {sorted(boundaries)}"
                )
            force = np.asarray(force, dtype=float)
            if force.shape != (3,) or not np.all(np.isfinite(force)):
                raise SolverInputError("dead_loads", f"{tag}: give a finite total force (Fx, Fy, Fz) in N")
            fb = skfem.FacetBasis(self.mesh, skfem.ElementTetP2(), facets=boundaries[tag], intorder=4)
            weights = skfem.asm(skfem.LinearForm(lambda v, w: v), fb)  # int N_a dA per node
            out[: self.n_u] += (weights[:, None] * force[None, :] / weights.sum()).reshape(-1)
        return out

    def boundary_nodes(self, tag: str) -> np.ndarray:
        return self.basis.get_dofs(self.mesh.boundaries[tag]).flatten()

    def initial_state(self) -> np.ndarray:
        return np.zeros(self.n_dofs)

    def apply_dirichlet(self, x: np.ndarray, factor: float) -> np.ndarray:
        x = x.copy()
        x[self.fixed_dofs] = factor * self.fixed_values
        return x

    def displacement(self, x: np.ndarray) -> np.ndarray:
        """Nodal displacements, shape (3, n_nodes)."""
        return x[: self.n_u].reshape(-1, 3).T

    def deformation_gradient(self, x: np.ndarray, dN=None, node_dofs=None) -> np.ndarray:
        """F = I + grad u at the quadrature points, shape (3, 3, E, Q); `dN` (10, 3, E, Q) and
        `node_dofs` (10, E) default to the volume basis."""
        if dN is None and node_dofs is None:
            g, nodes = self._g_aqJ, self._elem_nodes
        else:
            dN = self.dN if dN is None else dN
            g = np.ascontiguousarray(dN.transpose(2, 0, 3, 1)).reshape(dN.shape[2], 10, -1)
            nodes = (self.node_dofs if node_dofs is None else node_dofs).T
        return self._deformation_gradient(x, g, nodes)

    def _deformation_gradient(self, x, g_aqJ, elem_nodes):
        """F_iJ = d_iJ + sum_a u_ai dN_a/dX_J, contiguous (3, 3, n, Q), from one (3 x 10) @ (10 x 3Q)
        product per element; g_aqJ is (n, 10, 3Q) and elem_nodes (n, 10)."""
        n, _, m = g_aqJ.shape
        u = x[: self.n_u].reshape(-1, 3)[elem_nodes]  # (n, 10, 3)
        grad_u = np.matmul(u.transpose(0, 2, 1), g_aqJ).reshape(n, 3, m // 3, 3)  # [e, i, q, J]
        F = np.ascontiguousarray(grad_u.transpose(1, 3, 0, 2))
        F[0, 0] += 1.0
        F[1, 1] += 1.0
        F[2, 2] += 1.0
        return F

    def pressure_field(self, x: np.ndarray) -> np.ndarray:
        """Mixed pressure at the quadrature points (E, Q); for "p2", K (J - 1)."""
        if self.mixed:
            return np.einsum("ce,ceq->eq", x[self.p_dofs], self.Np)
        F = self.deformation_gradient(x)
        return self.bulk * (det3(F) - 1.0)

    # ------------------------------------------------------------ volume terms
    def _stress(self, x):
        """F, J, H = F^-T, the pressure p, c = mu J^-2/3, I1 = F:F and the first Piola stress
        P = c (F - I1/3 H) + p J H at all quadrature points (p = K (J - 1) for "p2").

        Tensors are (3, 3, E, Q) and scalars (E, Q), contiguous: every component is one
        contiguous array, so the pointwise algebra runs at memory speed."""
        F = self._deformation_gradient(x, self._g_aqJ, self._elem_nodes)
        J = det3(F)
        if np.any(J <= 0.0) or not np.all(np.isfinite(J)):
            raise InvertedElement("det F <= 0")
        H = cofactor3(F)
        H /= J
        p = self.pressure_field(x) if self.mixed else self.bulk * (J - 1.0)
        I1 = np.einsum("ijeq,ijeq->eq", F, F)
        c = self.mu * J ** (-2.0 / 3.0)
        P = c * (F - (I1 / 3.0) * H) + (p * J) * H
        return _Stress(F, J, H, p, c, I1, P)

    def _element_residual(self, stress):
        """Element residuals (E, n_local) in the local order of `element_dofs`:
        R_u[i a] = int P_iJ g_aJ dV and R_p[c] = int (J - 1 - p/K) Np_c dV."""
        E, Q = self.dx.shape
        Pw = np.ascontiguousarray((stress.P * self.dx).transpose(2, 0, 3, 1)).reshape(E, 3, 3 * Q)
        Ru = np.matmul(Pw, self._g_aqJ.transpose(0, 2, 1)).reshape(E, 30)  # [e, i, (q, J)] @ [e, (q, J), a]
        if not self.mixed:
            return Ru
        w = (stress.J - 1.0 - stress.p / self.bulk) * self.dx
        return np.hstack([Ru, np.matmul(w[:, None, :], self._Np_qc)[:, 0]])

    def _element_tangent(self, stress, blocks):
        """Element matrices into blocks[0..2] (K_uu, K_up, K_pp; K_uu only for "p2"),
        over chunks of elements on the assembly threads (`fem.parallel`); see `_tangent_chunk`."""
        J, p, c, I1, dx = stress.J, stress.p, stress.c, stress.I1, self.dx
        w1 = (2.0 / 9.0) * c * I1 + p * J
        if not self.mixed:
            w1 += self.bulk * J * J
        w2 = c * I1 / 3.0 - p * J
        # (E, Q, 3, 3) arrays for the batched products of the chunks: H and the combination
        # A = -2c/3 F + w1/2 H, with V = A g (dx included in A)
        H = np.ascontiguousarray(stress.H.transpose(2, 3, 0, 1))
        A = stress.F * ((-2.0 / 3.0) * c * dx) + stress.H * (0.5 * w1 * dx)
        A = np.ascontiguousarray(A.transpose(2, 3, 0, 1))
        weights = np.stack([w2 * dx, c * dx, J * dx])
        for_chunks(
            lambda s: self._tangent_chunk(s, A[s], H[s], weights[:, s], blocks), self.dx.shape[0], _CHUNK
        )

    def _tangent_chunk(self, s, A, H, weights, blocks):
        r"""Element matrices of the elements `s` (a slice) into blocks[k][s]; A and H are
        (n, Q, 3, 3) (A as below, dx included) and weights (3, n, Q) = (w2 dx, c dx, J dx).

        Local dofs: u component i of node a is 10 i + a, then the pressure dofs c. With
        g_a = grad N_a, f_ai = F_iJ g_aJ, h_ai = H_iJ g_aJ and c = mu J^-2/3, the Neo-Hookean +
        pressure tangent (`fem.neohooke.mixed_tangent`) contracted with g_a and g_b is, per
        quadrature point (weight dx),

            K_uu[i a, k b] = c (g_a . g_b) d_ik - 2c/3 (f_ai h_bk + h_ai f_bk)
                             + w1 h_ai h_bk + w2 h_ak h_bi,
            w1 = 2c I1/9 + p J (+ K J^2 for "p2"),   w2 = c I1/3 - p J,
            K_up[i a, c] = J h_ai Np_c,   K_pu = K_up^T,   K_pp = -Np_c Np_d / K (constant).

        The quadrature sums are inside batched matrix products, one per element: with
        V = -2c/3 f + w1/2 h = A g (A = -2c/3 F + w1/2 H, formed pointwise for all elements), the
        f/h terms are K_fh = [V; h]^T [h; V] (inner dimension 2Q); the
        swapped term is M[k a, i b] = sum w2 h_ka h_ib read with i and k exchanged. K_uu is
        symmetric, so only half of it is stored (`fem.pattern.Mirrored`; the 465 entries of
        `_uu_entries`): one gather picks their K_fh and M terms. The upper triangle of
        G = sum c (g_a . g_b) (precomputed g_a . g_b) is added to the three diagonal blocks,
        which come first.
        """
        gt = self._g_qJa[s]  # gt[e, q, J, a] = dN_a/dX_J
        n, Q = H.shape[:2]
        w_sw, w_g, w_p = weights[:, :, :, None]
        Vh = np.empty((n, 3 * Q, 3, 10))  # rows [V; h; V]
        np.matmul(A, gt, out=Vh[:, :Q])  # V[e, q, i, a] = (A g_a)_i dx
        np.matmul(H, gt, out=Vh[:, Q : 2 * Q])  # h[e, q, i, a]
        Vh[:, 2 * Q :] = Vh[:, :Q]
        Vh = Vh.reshape(n, 3 * Q, 30)
        h = Vh[:, Q : 2 * Q]  # (n, Q, 30)
        terms = np.empty((n, 1800))  # [K_fh | M]
        np.matmul(Vh[:, : 2 * Q].transpose(0, 2, 1), Vh[:, Q:], out=_view(terms[:, :900], (n, 30, 30)))
        np.matmul((h * w_sw).transpose(0, 2, 1), h, out=_view(terms[:, 900:], (n, 30, 30)))
        picked = np.take(terms, _UU_GATHER, axis=1)  # (n, 465 + 465)
        Kuu = blocks[0][s]
        np.add(picked[:, :465], picked[:, 465:], out=Kuu)
        G = np.matmul(w_g.transpose(0, 2, 1), self._gg[s])  # (n, 1, 55): c (g_a . g_b), a <= b
        _view(Kuu[:, :165], (n, 3, 55))[...] += G  # the diagonal blocks' upper triangles
        if self.mixed:
            np.matmul(h.transpose(0, 2, 1), self._Np_qc[s] * w_p, out=_view(blocks[1][s], (n, 30, 4)))
            blocks[2][s] = self._Kpp_upper[s]

    # ----------------------------------------------------------- chamber terms
    def _chamber_kinematics(self, x):
        F = self._deformation_gradient(x, self._f_g_aqJ, self._f_nodes)
        cofN = -np.einsum("iJfq,Jfq->ifq", cofactor3(F), self.f_normal)  # cavity-outward n da/dA
        return F, cofN

    def chamber_volume(self, x: np.ndarray) -> float:
        """Enclosed cavity volume of the deformed chamber (mm^3)."""
        if not self.chamber:
            return 0.0
        _, cofN = self._chamber_kinematics(x)
        ue = x[: self.n_u].reshape(-1, 3)[self.f_node_dofs]  # (10, F, 3)
        X = np.einsum("iaf,afq->ifq", self.nodes[:, self.f_node_dofs], self.f_N)
        xq = X + np.einsum("afi,afq->ifq", ue, self.f_N)
        w = self.volume_weights
        return float(np.einsum("i,ifq,ifq,fq->", w, xq, cofN, self.f_dx) / w.sum())

    def _chamber_load(self, x, with_tangent: bool):
        F, cofN = self._chamber_kinematics(x)
        q = np.einsum("afq,ifq,fq->aif", self.f_N, cofN, self.f_dx).reshape(30, -1)
        if not with_tangent:
            return q, None
        J = det3(F)
        H = cofactor3(F) / J
        # d(cof F N)_i / dF_kL = -J (H_iJ H_kL - H_iL H_kJ) N_J = D[i, L, k]   (the minus: cavity
        # normal); dq[a i, b k] = int N_a D[i, L, k] dN_b/dX_L dA: per point (10 x 3) @ D[i]
        # gives E[i, b, k], then one (10 x Qf) @ (Qf x 90) product per facet.
        HN = np.einsum("iJfq,Jfq->ifq", H, self.f_normal)
        D = -J * (HN[:, None, None] * H.transpose(1, 0, 2, 3)[None] - H[:, :, None] * HN[None, None])
        D = np.ascontiguousarray(D.transpose(3, 4, 0, 1, 2))  # (F, Qf, 3, 3, 3)
        E = np.matmul(self._f_g_qaJ[:, :, None], D)  # (F, Qf, 3, 10, 3)
        n_f, n_q = E.shape[:2]
        dq = np.matmul(self._f_Ndx, E.reshape(n_f, n_q, 90)).reshape(n_f, 30, 30)
        return q, dq

    # ---------------------------------------------------------------- globals
    def _scatter(self, element_values, dofs):
        return np.bincount(dofs.reshape(-1), weights=element_values.reshape(-1), minlength=self.n_dofs)

    def _at(self, x: np.ndarray) -> dict:
        """Results that depend on the state only (stress, volume internal force, pressure load
        vector), remembered for the last state x: the line search evaluates the residual at the
        trial state that the next Newton iteration assembles, and the convergence test asks for
        the pressure load at the state just assembled."""
        memo = self._memo
        if memo is None or not np.array_equal(memo["x"], x):
            memo = self._memo = {"x": x.copy()}
        return memo

    def _volume_force(self, x: np.ndarray, memo: dict):
        if "f_vol" not in memo:
            memo["stress"] = self._stress(x)
            memo["f_vol"] = self._scatter(self._element_residual(memo["stress"]), self._elem_dofs)
        return memo["stress"], memo["f_vol"]

    def internal_force(self, x: np.ndarray) -> np.ndarray:
        """Full internal force vector (all dofs, including the constrained ones)."""
        f = self._volume_force(x, self._at(x))[1].copy()
        if self.fibers is not None:
            Rf, _ = fiber_arrays(self.fibers, x[: self.n_u].reshape(-1, 3), with_tangent=False)
            f += self._scatter(Rf, self.fiber_dofs)
        if self.sheets is not None:
            Rs, _ = sheets.element_arrays(self.sheets, x[: self.n_u].reshape(-1, 3), False)
            f += self._scatter(Rs, self.sheet_dofs)
        return f

    def pressure_load(self, x: np.ndarray) -> np.ndarray:
        """q = dV_cav/du on all dofs; the pressure load vector is P q."""
        if not self.chamber:
            return np.zeros(self.n_dofs)
        memo = self._at(x)
        if "q" not in memo:
            memo["q"] = self._scatter(self._chamber_load(x, False)[0], self.f_u_dofs)
        return memo["q"].copy()

    def residual(self, x: np.ndarray, pressure: float, factor: float = 0.0) -> np.ndarray:
        """R = f_int - P q - f f_dead on all dofs (the dead loads need no tangent)."""
        return self.internal_force(x) - pressure * self.pressure_load(x) - factor * self.dead_load

    def residual_and_tangent(self, x: np.ndarray, pressure: float, factor: float = 0.0):
        """Full residual (all dofs) and the tangent on the free dofs (CSR).

        The element matrices of all groups are written straight into one flat array in the
        pattern's order (`fem.pattern.Pattern.views`), which one `np.bincount` scatters."""
        values = self.pattern.new_values()
        blocks = self.pattern.views(values)
        memo = self._at(x)
        stress, f_vol = self._volume_force(x, memo)
        R = f_vol - factor * self.dead_load
        self._element_tangent(stress, blocks)
        k = self._n_volume_groups
        if self.chamber:
            q, dq = self._chamber_load(x, True)
            memo["q"] = self._scatter(q, self.f_u_dofs)
            R -= pressure * memo["q"]
            np.multiply(dq, -pressure, out=blocks[k])
            k += 1
        if self.fibers is not None:
            Rf, Kf = fiber_arrays(self.fibers, x[: self.n_u].reshape(-1, 3))
            R += self._scatter(Rf, self.fiber_dofs)
            blocks[k][...] = Kf
            k += 1
        if self.sheets is not None:
            Rs, Ks = sheets.element_arrays(self.sheets, x[: self.n_u].reshape(-1, 3))
            R += self._scatter(Rs, self.sheet_dofs)
            blocks[k][...] = Ks
        return R, self.pattern.assemble_values(values)

    def fiber_tension(self, x: np.ndarray) -> np.ndarray:
        """Axial force (N) of one fiber: per segment of the line fibers, then per quadrature point
        of the fiber sheets, E A (lam - 1); empty without fibers."""
        from fem.fibers import fiber_state, segment_forces

        u = x[: self.n_u].reshape(-1, 3)
        out = [np.zeros(0)]
        if self.fibers is not None:
            out.append(segment_forces(self.fibers, fiber_state(self.fibers, u))[0])
        if self.sheets is not None:
            out.append(sheets.fiber_forces(self.sheets, u).reshape(-1))
        return np.concatenate(out)

    def reaction(self, x: np.ndarray, tag: str, pressure: float = 0.0, factor: float = 0.0) -> np.ndarray:
        """Total support force (N) on the constrained dofs of boundary `tag`, per component.

        At equilibrium f_int = P q + f f_dead + f_support, so f_support = R(x, P, f) on the
        constrained dofs.
        """
        f = self.residual(x, pressure, factor)
        nodes = self.boundary_nodes(tag)
        out = np.zeros(3)
        for c in range(3):
            d = 3 * nodes + c
            mask = np.isin(d, self.fixed_dofs)
            out[c] = f[d[mask]].sum()
        return out


def _material_arrays(mesh, materials, n_elem):
    if isinstance(materials, NeoHookean):
        return np.full((n_elem, 1), materials.mu), np.full((n_elem, 1), materials.bulk)
    if not isinstance(materials, Mapping):
        raise SolverInputError("materials", "give a NeoHookean or a mapping subdomain -> NeoHookean")
    subdomains = mesh.subdomains or {}
    mu = np.full((n_elem, 1), np.nan)
    bulk = np.full((n_elem, 1), np.nan)
    for name, mat in materials.items():
        if name not in subdomains:
            raise SolverInputError("materials", f"unknown subdomain {name!r}; known: {sorted(subdomains)}")
        mu[subdomains[name]] = mat.mu
        bulk[subdomains[name]] = mat.bulk
    if np.isnan(mu).any():
        raise SolverInputError("materials", "some elements have no material")
    return mu, bulk
