r"""Contact of a deformable body with a rigid analytic surface, with Coulomb friction: a model term.

Discretisation. The contact law (`fem.contact_law`) is evaluated at the quadrature points of the
body's boundary facets (the tags of a `ContactSpec`), on the curved P2 facets, in the
reference configuration: the force per reference area f(x) at a point x = X + u(X) gives the
facet residual and tangent

    r_ai = -int_Gamma0 N_a f_i dA,          K_ai,bk = int_Gamma0 N_a N_b (-df/dx)_ik dA

over the six P2 nodes of the facet (node-to-surface on P2 facets would give wrong, even
negative, corner forces: the P2 corner weights of a uniform pressure are zero). The blocks sit
on the dofs of elements of the body, so they reuse the body's sparsity pattern. Being a
penalty, the pressure needs a penetration -g = p_N / eps_N; the augmented-Lagrangian (Uzawa)
loop (`augment`, driven by `fem.contact_stages`) removes it at a converged load.

History. `commit(x)` (after an accepted increment, `fem.path` and `fem.contact_stages`) updates
the stick points; `augment(x)` updates the multipliers (the Uzawa loop at one load re-solves
with the friction history of the increment's start, then commits once). Nothing changes during
Newton iterations. Several terms may act in one model (each foot face with its own friction
coefficient, each against the same or another surface).

Outputs (`report`): contact pressure per facet (area average of p_N per reference area), the
contact area (reference and current, |cof(F) N| dA at active points), the slip fraction per
facet, total normal force (sum of p_N dA, and the vector sum) and friction force.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from softcrawl.fem.contact_law import committed_stick, evaluate, viscous_share
from softcrawl.fem.corrugated_pipe import CorrugatedPipe
from softcrawl.fem.discretisation import Discretisation, element_first
from softcrawl.fem.errors import SolverInputError
from softcrawl.fem.neohooke import cofactor3
from softcrawl.fem.pipe_surfaces import ElbowPipe
from softcrawl.fem.rigid_surfaces import CylinderWall, Plane, positive

#: The rigid surfaces a contact term accepts: each gives project(x) -> (gap, normal, curvature).
SURFACES = (Plane, CylinderWall, ElbowPipe, CorrugatedPipe)


@dataclass(frozen=True)
class ContactSpec:
    """Boundary `tags` of the body against a rigid `surface` (`SURFACES`: `Plane`, `CylinderWall`,
    `ElbowPipe`, `CorrugatedPipe`).

    penalty: eps_N, normal penalty (MPa/mm: pressure per mm of penetration);
    tangential_penalty: eps_T (MPa/mm), default eps_N; mu: Coulomb coefficient (>= 0);
    max_initial_penetration: largest penetration (mm) accepted in the reference state (an
    oversized body must be brought in by moving the surface, `fem.contact_stages`);
    intorder: facet quadrature order; name: labels outputs;
    smoothing: gap band (mm) over which the normal law's kink is rounded (`fem.contact_law`;
    0, the default: the exact kink);
    slip_band: width w of the rounded Coulomb cone, a share of the Coulomb radius mu p_N, in
    [0, 1) (`fem.contact_law`; 0, the default: the exact cone);
    slip_viscosity: eta (MPa s/mm), the traction above the cone per mm/s of slip speed
    (`fem.contact_law`, viscous slip; 0, the default: Coulomb). It acts in the stages that have
    a duration (`fem.contact_stages.Stage.duration`), which give each sub-step its time.
    """

    tags: tuple[str, ...]
    surface: Plane | CylinderWall | ElbowPipe | CorrugatedPipe
    penalty: float
    mu: float = 0.0
    tangential_penalty: float | None = None
    max_initial_penetration: float = 0.0
    intorder: int = 4
    name: str = "contact"
    smoothing: float = 0.0
    slip_band: float = 0.0
    slip_viscosity: float = 0.0

    def __post_init__(self):
        tags = (self.tags,) if isinstance(self.tags, str) else tuple(self.tags)
        if not tags:
            raise SolverInputError("contact.tags", "give at least one boundary tag")
        object.__setattr__(self, "tags", tags)
        if not isinstance(self.surface, SURFACES):
            raise SolverInputError(
                "contact.surface", "must be a Plane, a CylinderWall, an ElbowPipe or a CorrugatedPipe"
            )
        object.__setattr__(self, "penalty", positive(self.penalty, "contact.penalty"))
        if self.tangential_penalty is not None:
            eps_t = positive(self.tangential_penalty, "contact.tangential_penalty")
            object.__setattr__(self, "tangential_penalty", eps_t)
        check_mu(self.mu)
        object.__setattr__(self, "mu", float(self.mu))
        if not (np.isfinite(self.max_initial_penetration) and self.max_initial_penetration >= 0):
            raise SolverInputError("contact.max_initial_penetration", "must be a number >= 0")
        if not (np.isfinite(self.smoothing) and self.smoothing >= 0):
            raise SolverInputError("contact.smoothing", "must be a gap band >= 0 (mm)")
        if not (np.isfinite(self.slip_band) and 0.0 <= self.slip_band < 1.0):
            raise SolverInputError(
                "contact.slip_band",
                f"must be a share of the Coulomb radius in [0, 1), got {self.slip_band!r}",
            )

        if not (np.isfinite(self.slip_viscosity) and self.slip_viscosity >= 0):
            raise SolverInputError(
                "contact.slip_viscosity", f"must be a viscosity >= 0 (MPa s/mm), got {self.slip_viscosity!r}"
            )

    @property
    def eps_t(self) -> float:
        return self.penalty if self.tangential_penalty is None else self.tangential_penalty


def check_mu(mu) -> float:
    try:
        ok = np.isfinite(float(mu)) and float(mu) >= 0
    except (TypeError, ValueError):
        ok = False
    if not ok:
        raise SolverInputError("contact.mu", f"the friction coefficient must be >= 0, got {mu!r}")
    return float(mu)


@dataclass(frozen=True)
class ContactReport:
    """Contact outputs at one state (forces in N, areas in mm^2, pressures in MPa)."""

    name: str
    normal_force: float  # sum p_N dA0
    normal_force_vector: np.ndarray  # (3,)
    friction_force: np.ndarray  # (3,)
    area_reference: float  # active reference area
    area_current: float  # active deformed area
    contact_fraction: float  # active / total reference area of the tags
    max_pressure: float
    max_penetration: float
    slip_fraction: float  # slipping / active area
    facet_pressure: np.ndarray = field(repr=False)  # (F,) mean p_N over each facet
    facet_slip: np.ndarray = field(repr=False)  # (F,) slipping share of each facet's area
    facet_active: np.ndarray = field(repr=False)  # (F,) active share of each facet's area

    @property
    def mean_pressure(self) -> float:
        """Normal force over the deformed contact area (MPa); 0 without contact."""
        return self.normal_force / self.area_current if self.area_current > 0 else 0.0


#: A P2 shape function that vanishes on a facet is zero there only to the round-off of scikit-fem's
#: inverse isoparametric map (its Newton tolerance is 1e-12; 1.2e-12 was seen on a mirrored
#: revolved foot), while the six that live on the facet reach 0.1-1 at the quadrature points.
ON_FACET_TOL = 1e-8


class ContactTerm:
    """A `ContactSpec` on a body discretised by `space`: a term of `fem.model.SolidModel`."""

    #: The tangent is not symmetric with friction (the slip direction couples to the normal), and
    #: friction can be switched on between stages (`set_friction`) after a solver has chosen its
    #: factorisation from `fem.model.SolidModel.symmetric_tangent`: never declared symmetric.
    symmetric = False

    def __init__(self, space: Discretisation, spec: ContactSpec) -> None:
        self.space, self.spec = space, spec
        self.surface, self.mu = spec.surface, spec.mu
        facets = np.unique(np.concatenate([space.boundary(t, "contact.tags") for t in spec.tags]))
        self.facets = facets
        fb = space.facet_basis(facets, intorder=spec.intorder, parameter="contact.tags")
        N = np.stack([np.asarray(phi[0]) for phi in fb.basis])  # (10, F, Q)
        on_facet = np.abs(N).max(axis=2) > ON_FACET_TOL  # the six P2 nodes of each facet
        if not np.all(on_facet.sum(axis=0) == 6):
            raise SolverInputError("contact.tags", "expected six P2 nodes on every facet")
        local = np.argsort(~on_facet, axis=0, kind="stable")[:6]  # (6, F)
        cols = np.arange(N.shape[1])
        self.N = N[local, cols[None, :]]  # (6, F, Q)
        self.nodes = fb.element_dofs[local, cols[None, :]]  # (6, F)
        self.dofs = (3 * self.nodes[:, None, :] + np.arange(3)[None, :, None]).reshape(18, -1)
        self.dA = fb.dx  # (F, Q) reference area weights
        X = space.nodes[:, self.nodes]  # (3, 6, F)
        self.X = np.einsum("iaf,afq->fqi", X, self.N).reshape(-1, 3)
        self._normal0 = fb.normals  # (3, F, Q) reference outward normals
        self._g_aqJ = element_first(np.stack([phi[0].grad for phi in fb.basis]))
        self._elem_nodes = np.ascontiguousarray(fb.element_dofs.T)
        n = self.X.shape[0]
        self.seconds = 0.0  # spent in `arrays` (the term's share of the assembly)
        self.multiplier = np.zeros(n)
        self.stick = self.X.copy()
        self._solved = None  # (positions, stick points) of the last commit, for `report`
        self.time_step = None  # s, the current sub-step's duration (None: pseudo-time)
        g = self.surface.project(self.X)[0]
        limit = spec.max_initial_penetration + 1e-9 * max(space.size, 1.0)
        if g.min() < -limit:
            raise SolverInputError(
                "contact.max_initial_penetration",
                f"{spec.name}: the reference state penetrates the surface by {-g.min():.4g} mm "
                f"(> {spec.max_initial_penetration:g} mm); start with the surface clear of the body",
            )

    # -------------------------------------------------------------- state
    def positions(self, x: np.ndarray) -> np.ndarray:
        """Spatial positions of the contact points (F * Q, 3)."""
        u = x[: self.space.n_u].reshape(-1, 3)[self.nodes]  # (6, F, 3)
        return self.X + np.einsum("afi,afq->fqi", u, self.N).reshape(-1, 3)

    def state(self, x: np.ndarray, with_tangent: bool = False):
        return self._evaluate(self.positions(x), self.stick, with_tangent)

    def _evaluate(self, pos: np.ndarray, stick: np.ndarray, with_tangent: bool):
        s = self.spec
        return evaluate(
            pos,
            self.surface,
            self.multiplier,
            stick,
            s.penalty,
            s.eps_t,
            self.mu,
            with_tangent,
            s.smoothing,
            s.slip_band,
            self.kappa,
        )

    @property
    def kappa(self) -> float:
        """The viscous share of the slip over the current sub-step (`fem.contact_law.viscous_share`)."""
        return viscous_share(self.spec.slip_viscosity, self.spec.eps_t, self.time_step)

    def set_time_step(self, dt: float | None) -> None:
        """The duration (s) of the sub-step about to be solved (None: pseudo-time, no viscosity)."""
        self.time_step = dt

    def arrays(self, x, pressures=None, with_tangent=True):
        """Facet residuals (18, F) and tangents (F, 18, 18), local dof 3 a + i; its time is added
        to `seconds`."""
        t0 = time.perf_counter()
        try:
            return self._arrays(x, with_tangent)
        finally:
            self.seconds += time.perf_counter() - t0

    def _arrays(self, x, with_tangent):
        st = self.state(x, with_tangent)
        n_f, n_q = self.dA.shape
        Ndx = self.N * self.dA[None]  # (6, F, Q)
        f = st.force.reshape(n_f, n_q, 3)
        r = -np.einsum("afq,fqi->aif", Ndx, f).reshape(18, n_f)
        if not with_tangent:
            return r, None
        K = st.stiffness.reshape(n_f, n_q, 3, 3)
        K = np.einsum("afq,bfq,fqik->faibk", Ndx, self.N, K, optimize=True).reshape(n_f, 18, 18)
        return r, K

    # ------------------------------------------------------------ history
    def commit(self, x: np.ndarray) -> None:
        """A converged state: update the stick points (never called inside Newton). With a rounded
        cone the return to r = 1 lowers the traction of slipping points by up to mu p_N w / 8
        (`fem.contact_law`); `report` at this x therefore uses the stick points x was solved with
        (the forces the residual balanced)."""
        pos = self.positions(x)
        st = self._evaluate(pos, self.stick, False)
        self._solved = (pos, self.stick)
        kappa, eps_t = self.kappa, self.spec.eps_t
        self.stick = pos if self.mu == 0.0 else committed_stick(st, pos, self.stick, eps_t, self.mu, kappa)

    def augment(self, x: np.ndarray, relax: float = 1.0) -> float:
        """Uzawa update at a converged state: lambda <- lambda + relax (p_N - lambda), the full
        update lambda <- p_N at relax = 1 (the friction history is left to `commit`, once the
        loop at this load is done). Returns the largest penetration (mm) of the state before the
        update."""
        st = self.state(x)
        self.multiplier = self.multiplier + relax * (st.pressure - self.multiplier)
        return float(max(0.0, -st.gap[st.active].min())) if st.active.any() else 0.0

    def set_surface(self, surface) -> None:
        """Move the rigid surface (staged insertion); the history stays."""
        self.surface = surface

    def set_friction(self, mu: float, x: np.ndarray) -> None:
        """Change the friction coefficient; stick points restart at the current positions."""
        self.mu = check_mu(mu)
        self.stick, self._solved = self.positions(x), None

    def reset_multipliers(self) -> None:
        self.multiplier = np.zeros_like(self.multiplier)

    # ------------------------------------------------------------ outputs
    def report(self, x: np.ndarray) -> ContactReport:
        """The outputs at x; at the last committed state, with the history it was solved with."""
        pos = self.positions(x)
        solved = self._solved
        stick = solved[1] if solved is not None and np.array_equal(solved[0], pos) else self.stick
        st = self._evaluate(pos, stick, False)
        n_f, n_q = self.dA.shape
        dA = self.dA.reshape(-1)
        F = self.space.deformation_gradient(x, self._g_aqJ, self._elem_nodes)  # (3, 3, F, Q)
        # Nanson: da = |cof(F) N| dA, with N the unit reference normal and dA the reference weight
        stretch = np.linalg.norm(np.einsum("iJfq,Jfq->ifq", cofactor3(F), self._normal0), axis=0).reshape(-1)
        da = stretch * dA
        act = st.pressure > 0.0
        # at the Coulomb limit (after a commit, slipping points sit exactly on it)
        slip = (
            act & (np.linalg.norm(st.friction, axis=1) >= (1 - 1e-6) * self.mu * st.pressure) & (self.mu > 0)
        )
        per_facet = lambda v: (v * dA).reshape(n_f, n_q).sum(axis=1) / self.dA.sum(axis=1)  # noqa: E731
        area0 = float(dA[act].sum())
        return ContactReport(
            name=self.spec.name,
            normal_force=float((st.pressure * dA).sum()),
            normal_force_vector=(st.normal * (st.pressure * dA)[:, None]).sum(axis=0),
            friction_force=(st.friction * dA[:, None]).sum(axis=0),
            area_reference=area0,
            area_current=float(da[act].sum()),
            contact_fraction=area0 / float(dA.sum()),
            max_pressure=float(st.pressure.max(initial=0.0)),
            max_penetration=float(max(0.0, -st.gap.min())),
            slip_fraction=float(dA[slip].sum()) / area0 if area0 > 0 else 0.0,
            facet_pressure=per_facet(st.pressure),
            facet_slip=per_facet(slip.astype(float)),
            facet_active=per_facet(act.astype(float)),
        )
