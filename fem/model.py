r"""A meshed solid with its loads: the residual and consistent tangent that Newton's method needs.

The model composes one mechanics item per module:

    Discretisation   P2 displacements (+ P1 pressures)            `fem.discretisation`
    Constraints      Dirichlet conditions and ties, condensed out `fem.dirichlet`
    Solid            the hyperelastic body                         `fem.solid`
    terms            chamber pressures (`fem.chamber`), embedded fiber lines (`fem.fibers`),
                     fiber sheets (`fem.sheets`)
    dead loads       a constant force vector                       `fem.dead_load`

and assembles, at a state x and a load (P, f) (chamber pressures P, MPa, one per chamber or one
for all; load factor f of the prescribed displacements and dead loads),

    R(x) = f_int(x) + sum_terms r_t(x, P) - f f_dead,      K = dR/dx on the free dofs.

A term (fibers, sheets, contact: `fem.contact`) is an object with `dofs` (n_local, n_items) and
`arrays(x, pressures, with_tangent)` returning its item residuals (n_local, n_items) and item
tangents (n_items, n_local, n_local) (None without the tangent); a term with a history (contact)
also has `commit(x)`, which the path calls once a state has converged. The chambers' follower
pressures are assembled beside the terms, because their load vectors are also needed alone
(volume control, convergence test). All element blocks go into one fixed sparsity pattern
(`fem.pattern`); the constrained dofs are condensed out through it. Reactions are the residual
on the constrained dofs: at equilibrium f_int = P q + f f_dead + f_support.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from softcrawl.fem import sheets
from softcrawl.fem.chamber import Chamber, ChamberSpec
from softcrawl.fem.contact import ContactTerm
from softcrawl.fem.dead_load import body_force_vector, dead_load_vector
from softcrawl.fem.dirichlet import Constraints, Dirichlet
from softcrawl.fem.discretisation import FORMULATIONS, Discretisation
from softcrawl.fem.errors import SolverInputError
from softcrawl.fem.fibers import FiberLines, element_arrays, embed, fiber_state, segment_dofs, segment_forces
from softcrawl.fem.linsolve import SYMMETRY_TOL
from softcrawl.fem.pattern import Pattern
from softcrawl.fem.solid import InvertedElement, Solid

__all__ = ["FORMULATIONS", "ChamberSpec", "Dirichlet", "InvertedElement", "SolidModel"]


class _LineFiberTerm:
    """Embedded truss fibers (`fem.fibers`): segment residuals and tangents."""

    def __init__(self, fibers, n_u: int) -> None:
        self.fibers, self.n_u, self.dofs = fibers, n_u, segment_dofs(fibers)

    def arrays(self, x, pressures, with_tangent):
        return element_arrays(self.fibers, x[: self.n_u].reshape(-1, 3), with_tangent)


class _SheetTerm:
    """Fiber sheets (`fem.sheets`): facet residuals and tangents."""

    def __init__(self, quadrature, n_u: int) -> None:
        self.quadrature, self.n_u, self.dofs = quadrature, n_u, quadrature.dofs

    def arrays(self, x, pressures, with_tangent):
        return sheets.element_arrays(self.quadrature, x[: self.n_u].reshape(-1, 3), with_tangent)


def _chamber_specs(chambers) -> list[ChamberSpec]:
    """`chambers`: None, one ChamberSpec, the tags of one chamber, or a sequence of ChamberSpec."""
    if not chambers:
        return []
    if isinstance(chambers, ChamberSpec):
        return [chambers]
    if isinstance(chambers, str):
        return [ChamberSpec((chambers,))]
    items = list(chambers)
    if all(isinstance(c, str) for c in items):
        return [ChamberSpec(tuple(items))]
    if all(isinstance(c, ChamberSpec) for c in items):
        return items
    raise SolverInputError("chambers", "give the tags of one chamber or a sequence of ChamberSpec")


PRESSURE_FIELDS = ("per-material", "continuous")


def _pressure_groups(mesh, materials, pressure_fields: str):
    """Element -> pressure group (`fem.discretisation`): one group per distinct material law
    ("per-material", the default: no pressure field is continuous across a material jump), or
    None (one field for the whole body, "continuous": wrong at a material interface, kept to show
    it in tests/fem/test_multi_material.py)."""
    if pressure_fields not in PRESSURE_FIELDS:
        raise SolverInputError("pressure_fields", f"{pressure_fields!r} is not one of {PRESSURE_FIELDS}")
    if pressure_fields == "continuous" or not isinstance(materials, Mapping):
        return None
    laws: list = []
    groups = np.zeros(mesh.t.shape[1], dtype=np.int64)
    for name, law in materials.items():
        if law not in laws:
            laws.append(law)
        groups[(mesh.subdomains or {}).get(name, [])] = laws.index(law)
    return groups if len(laws) > 1 else None


class SolidModel:
    """A meshed solid with materials, Dirichlet conditions, chamber pressures, fibers, dead loads.

    mesh: `skfem.MeshTet` (straight) or `skfem.MeshTet2` (curved), with named `boundaries`.
    materials: one `NeoHookean`, or a mapping subdomain name -> `NeoHookean`.
    dirichlet: `Dirichlet` conditions. chambers: see `_chamber_specs` (None: no pressure load).
    fibers: `fem.fibers.FiberLines` (embedded truss fibers; none when None or empty).
    fiber_sheets: `fem.sheets.FiberSheet` families smeared over boundary surfaces (the homogenised
        winding, which converges under mesh refinement).
    dead_loads: mapping boundary tag -> total force (Fx, Fy, Fz) in N.
    contacts: `fem.contact.ContactSpec`s, each a set of boundary tags against a rigid surface
        with its own friction coefficient (`model.contacts` holds the terms).
    ties: linear ties of dofs with `links(space)` (`fem.periodic_tie.CyclicTie`: a wedge's cuts),
        condensed out exactly (`fem.dirichlet`).
    extra_terms: other term specifications with `build(space) -> term` (e.g.
        `fem.equal_displacement.EqualDisplacement`, a rigid plate's common translation).
    pressure_fields: "per-material" (one P1 pressure field per distinct material law, see
        `_pressure_groups`) or "continuous" (one field).
    body_forces: mapping subdomain -> force per reference volume (3,) in N/mm^3 (gravity: density
        times g); scaled by the load factor like the dead loads.
    """

    def __init__(
        self,
        mesh,
        materials,
        *,
        dirichlet: Sequence[Dirichlet] = (),
        chambers=None,
        formulation: str = "p2p1",
        intorder: int = 2,
        fibers: FiberLines | None = None,
        fiber_sheets: Sequence = (),
        dead_loads=None,
        contacts: Sequence = (),
        extra_terms: Sequence = (),
        pressure_fields: str = "per-material",
        body_forces=None,
        ties: Sequence = (),
    ) -> None:
        groups = _pressure_groups(mesh, materials, pressure_fields)
        self.space = Discretisation(mesh, formulation, intorder, groups)
        self.solid = Solid(self.space, materials)
        self.constraints = Constraints(self.space, dirichlet, ties)
        touched = np.zeros(self.space.n_dofs, dtype=bool)
        touched[self.space.element_dofs.reshape(-1)] = True
        self.constraints.pin(np.flatnonzero(~touched))  # unknowns of no element (orphan vertices)
        self.chambers = [Chamber(self.space, spec) for spec in _chamber_specs(chambers)]
        has_lines = fibers is not None and len(fibers.polylines or ()) > 0
        self.fibers = embed(self.space.basis, fibers) if has_lines else None
        self.sheets = sheets.build(mesh, fiber_sheets) if fiber_sheets else None
        self.terms = []
        if self.fibers is not None:
            self.terms.append(_LineFiberTerm(self.fibers, self.space.n_u))
        if self.sheets is not None:
            self.terms.append(_SheetTerm(self.sheets, self.space.n_u))
        self.contacts = [ContactTerm(self.space, spec) for spec in contacts]
        self.terms += self.contacts
        self.terms += [spec.build(self.space) for spec in extra_terms]
        self.dead_load = dead_load_vector(self.space, dead_loads) + body_force_vector(self.space, body_forces)
        groups = self.solid.groups + [c.u_dofs for c in self.chambers] + [t.dofs for t in self.terms]
        self.pattern = Pattern(self.constraints.free_index, groups, self.constraints.links)
        self._memo = None  # see `_at`
        self._symmetric = None  # see `symmetric_tangent`

    # ------------------------------------------------------------- the body
    mesh = property(lambda self: self.space.mesh)
    mixed = property(lambda self: self.space.mixed)
    nodes = property(lambda self: self.space.nodes)
    dx = property(lambda self: self.space.dx)
    n_u = property(lambda self: self.space.n_u)
    n_p = property(lambda self: self.space.n_p)
    n_dofs = property(lambda self: self.space.n_dofs)
    p_dofs = property(lambda self: self.space.p_dofs)
    mu = property(lambda self: self.solid.mu)
    bulk = property(lambda self: self.solid.bulk)
    free_dofs = property(lambda self: self.constraints.free_dofs)
    fixed_dofs = property(lambda self: self.constraints.fixed_dofs)
    chamber = property(lambda self: self.chambers[0].tags if self.chambers else ())

    def boundary_nodes(self, tag: str) -> np.ndarray:
        return self.space.boundary_nodes(tag)

    def initial_state(self) -> np.ndarray:
        return np.zeros(self.n_dofs)

    def apply_dirichlet(self, x: np.ndarray, factor: float) -> np.ndarray:
        """x with the prescribed dofs at `factor` times their values and the tied dofs following."""
        return self.constraints.apply(x, factor)

    def reduce(self, R: np.ndarray) -> np.ndarray:
        """A vector on all dofs (a residual, a load) as the equations of the free dofs, T^T R."""
        return self.constraints.reduce(R)

    def fold(self, v: np.ndarray) -> np.ndarray:
        """A vector on all dofs with the tied rows added to their masters' (`fem.dirichlet`)."""
        return self.constraints.fold(v)

    def step(self, x: np.ndarray, dq: np.ndarray, alpha: float = 1.0) -> np.ndarray:
        """x moved by alpha dq on the free dofs, the tied dofs following (a copy)."""
        return self.constraints.step(x, dq, alpha)

    def displacement(self, x: np.ndarray) -> np.ndarray:
        """Nodal displacements, shape (3, n_nodes)."""
        return self.space.displacement(x)

    def deformation_gradient(self, x: np.ndarray) -> np.ndarray:
        """F at the volume quadrature points, shape (3, 3, E, Q)."""
        return self.space.deformation_gradient(x)

    def pressure_field(self, x: np.ndarray) -> np.ndarray:
        """Mixed pressure at the quadrature points (E, Q); for "p2", K (J - 1)."""
        return self.solid.pressure_field(x)

    def pressures(self, pressure) -> np.ndarray:
        """One pressure per chamber (MPa) from a scalar (all chambers) or a sequence."""
        P = np.atleast_1d(np.asarray(pressure, dtype=float))
        n = len(self.chambers)
        if P.size == 1:
            return np.full(n, float(P[0]))
        if P.size != n:
            raise SolverInputError("pressure", f"{P.size} pressures for {n} chambers")
        return P

    # ------------------------------------------------------------ chambers
    def chamber_volume(self, x: np.ndarray, chamber: int = 0) -> float:
        """Enclosed cavity volume of a deformed chamber (mm^3); 0 without chambers."""
        return self.chambers[chamber].volume(x) if self.chambers else 0.0

    def pressure_load(self, x: np.ndarray, chamber: int = 0) -> np.ndarray:
        """q = dV_cav/du of one chamber on all dofs; its pressure load vector is P q."""
        if not self.chambers:
            return np.zeros(self.n_dofs)
        memo = self._at(x)
        key = ("q", chamber)
        if key not in memo:
            c = self.chambers[chamber]
            memo[key] = self._scatter(c.load(x, False)[0], c.u_dofs)
        return memo[key].copy()

    def pressure_force(self, x: np.ndarray, pressure) -> np.ndarray:
        """sum_i P_i q_i: the chamber pressures' force on all dofs."""
        P = self.pressures(pressure)
        out = np.zeros(self.n_dofs)
        for i in range(len(self.chambers)):
            if P[i] != 0.0:
                out += P[i] * self.pressure_load(x, i)
        return out

    # ----------------------------------------------------------- assembly
    def _scatter(self, element_values, dofs):
        return np.bincount(dofs.reshape(-1), weights=element_values.reshape(-1), minlength=self.n_dofs)

    def _at(self, x: np.ndarray) -> dict:
        """Results that depend on the state only (stress, body force, chamber load vectors),
        remembered for the last state x: the line search evaluates the residual at the trial
        state that the next Newton iteration assembles, and the convergence test asks for the
        pressure load at the state just assembled."""
        memo = self._memo
        if memo is None or not np.array_equal(memo["x"], x):
            memo = self._memo = {"x": x.copy()}
        return memo

    def _body_force(self, x: np.ndarray, memo: dict):
        if "f_vol" not in memo:
            memo["stress"] = self.solid.stress(x)
            memo["f_vol"] = self.solid.internal_force(memo["stress"])
        return memo["stress"], memo["f_vol"]

    def body_force(self, x: np.ndarray) -> np.ndarray:
        """The solid's own internal force div(sigma) on all dofs: no fiber, sheet, contact or
        extra term, no pressure."""
        return self._body_force(x, self._at(x))[1]

    def internal_force(self, x: np.ndarray) -> np.ndarray:
        """Body and term forces on all dofs (the constrained ones included), no pressure."""
        f = self._body_force(x, self._at(x))[1].copy()
        for term in self.terms:
            f += self._scatter(term.arrays(x, None, False)[0], term.dofs)
        return f

    def residual(self, x: np.ndarray, pressure=0.0, factor: float = 0.0) -> np.ndarray:
        """R = f_int - sum_i P_i q_i - f f_dead on all dofs (the dead loads need no tangent)."""
        return self.internal_force(x) - self.pressure_force(x, pressure) - factor * self.dead_load

    def residual_and_tangent(self, x: np.ndarray, pressure=0.0, factor: float = 0.0):
        """Full residual (all dofs) and the tangent on the free dofs (CSR).

        The element matrices of all groups are written straight into one flat array in the
        pattern's order (`fem.pattern.Pattern.views`), which one `np.bincount` scatters."""
        P = self.pressures(pressure) if self.chambers else np.zeros(0)
        values = self.pattern.new_values()
        blocks = self.pattern.views(values)
        memo = self._at(x)
        stress, f_vol = self._body_force(x, memo)
        R = f_vol - factor * self.dead_load
        self.solid.element_tangent(stress, blocks)
        k = len(self.solid.groups)
        for i, chamber in enumerate(self.chambers):
            q, dq = chamber.load(x, True)
            memo[("q", i)] = self._scatter(q, chamber.u_dofs)  # for the convergence test here
            R -= P[i] * memo[("q", i)]
            np.multiply(dq, -P[i], out=blocks[k])
            k += 1
        for term in self.terms:
            r, K = term.arrays(x, P, True)
            R += self._scatter(r, term.dofs)
            blocks[k][...] = K
            k += 1
        return R, self.pattern.assemble_values(values)

    @property
    def symmetric_tangent(self) -> bool:
        """Whether the tangent is symmetric at every state, known from the load types and decided
        once: the body, the fiber lines and the sheets derive from energies; a term that does not
        says so with `symmetric = False`; chamber pressures are symmetric when their load is
        conservative (a closed or symmetrically cut chamber: `_chambers_conservative`)."""
        if self._symmetric is None:
            terms = all(getattr(t, "symmetric", True) for t in self.terms)
            self._symmetric = terms and self._chambers_conservative()
        return self._symmetric

    def _chambers_conservative(self) -> bool:
        """The chambers' pressure tangent alone, assembled at a random state on the free dofs, is
        symmetric to round-off (~1e-16 when the load is conservative, O(1) when it is not)."""
        if not self.chambers:
            return True
        rng = np.random.default_rng(0)
        x = self.initial_state()
        x[: self.n_u] = 1e-3 * self.space.size * rng.standard_normal(self.n_u)
        x = self.apply_dirichlet(x, 0.0)
        values = np.zeros(self.pattern.size)
        blocks = self.pattern.views(values)
        k = len(self.solid.groups)
        for i, chamber in enumerate(self.chambers):
            blocks[k + i][...] = chamber.load(x, True)[1]
        return self.pattern.asymmetry(self.pattern.assemble_values(values)) < SYMMETRY_TOL

    def commit(self, x: np.ndarray) -> None:
        """A state has converged: terms with a history (contact) update it from x."""
        for term in self.terms:
            if hasattr(term, "commit"):
                term.commit(x)

    # ------------------------------------------------------------ outputs
    def fiber_tension(self, x: np.ndarray) -> np.ndarray:
        """Axial force (N) of one fiber: per segment of the line fibers, then per quadrature point
        of the fiber sheets, E A (lam - 1); empty without fibers."""
        u = x[: self.n_u].reshape(-1, 3)
        out = [np.zeros(0)]
        if self.fibers is not None:
            out.append(segment_forces(self.fibers, fiber_state(self.fibers, u))[0])
        if self.sheets is not None:
            out.append(sheets.fiber_forces(self.sheets, u).reshape(-1))
        return np.concatenate(out)

    def reaction(self, x: np.ndarray, tag: str, pressure=0.0, factor: float = 0.0) -> np.ndarray:
        """Total support force (N) on the constrained dofs of boundary `tag`, per component.

        At equilibrium f_int = P q + f f_dead + f_support, so f_support = R(x, P, f) on the
        constrained dofs."""
        f = self.residual(x, pressure, factor)
        nodes = self.boundary_nodes(tag)
        out = np.zeros(3)
        for c in range(3):
            d = 3 * nodes + c
            out[c] = f[d[np.isin(d, self.fixed_dofs)]].sum()
        return out
