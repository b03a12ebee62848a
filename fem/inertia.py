r"""Inertia: a lumped mass and backward Euler in time, so that a load path can cross a sudden slide
(docs/decisions/089-inertia.md).

Mass. The consistent scalar mass of a P2 element, M_e,ij = int_e rho N_i N_j dV, is lumped by
diagonal scaling (Hinton, Rock and Zienkiewicz, "HRZ"), because the row sums of a P2 tetrahedron
give its corner nodes negative masses:

    m_e,i = rho_e V_e M_e,ii / sum_k M_e,kk,        m_i = sum_e m_e,i,

every m_i > 0 and sum_i m_i = sum_e rho_e V_e, the body's mass at the solver's quadrature (the
mass that gravity loads: `studies.crawl_fe.mass`). On a straight P2 tetrahedron (exact
quadrature) a corner carries 1/36 of the element's mass and a mid-edge node 4/27.

Time. Over a sub-step of dt (s) from the committed state (u_n, v_n), backward Euler

    v_{n+1} = (u_{n+1} - u_n) / dt,     a_{n+1} = (v_{n+1} - v_n) / dt = (u_{n+1} - u_n - dt v_n) / dt^2

adds, per node and direction, the inertia force to the residual and its derivative to the tangent:

    r_i = m_i a_i,          K_i = m_i / dt^2 I_3        (symmetric, positive).

The commit of a converged sub-step sets v_n <- (u - u_n) / dt, u_n <- u, and ends the sub-step (the
term adds nothing until the next time step is set: a residual evaluated for outputs is the static
one). A sub-step without a duration (dt None: a pseudo-time stage such as a frictionless insertion)
is quasi-static: the term adds nothing and its commit leaves the body at rest (v_n = 0).
`rest(x)` puts the body at rest at x (a run's start).

What the scheme does (tests/fem/test_inertia.py). The momentum balance is exact: sum_i m_i v_i
changes by the sum of the external forces times dt in every step, whatever dt, because the internal
forces sum to zero. Under a constant force F on a free body of mass M the centre of mass moves
F T^2 / (2 M) (1 + 1/N) in N steps over T: first order in dt. An oscillator of angular frequency
omega loses a factor (1 + omega^2 dt^2)^(-1/2) of its amplitude per step: unconditionally stable
and dissipative. That is what it is used for: in a quasi-static crawl (sub-steps of 0.1 s, forces
of mN against tens of N) it adds nothing measurable, and where the path cannot follow a foot's
sudden slide the cut-back sub-steps make m / dt^2 dominate, every Newton solve is regular, and the
slide's kinetic energy is damped out once the steps grow back. Units: density t/mm^3, mm, s, N.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from softcrawl.fem.errors import SolverInputError
from softcrawl.fem.rigid_surfaces import positive


def element_densities(mesh, densities) -> np.ndarray:
    """rho per element (t/mm^3) from one density or a mapping subdomain -> density; an element of
    no named subdomain has none (0)."""
    n = mesh.t.shape[1]
    if not isinstance(densities, Mapping):
        return np.full(n, positive(densities, "inertia.densities"))
    out = np.zeros(n)
    subdomains = mesh.subdomains or {}
    for name, value in densities.items():
        if name not in subdomains:
            raise SolverInputError("inertia.densities", f"no subdomain {name!r} in the mesh")
        out[np.asarray(subdomains[name])] = positive(value, f"inertia.densities[{name!r}]")
    return out


def lumped_masses(space, densities) -> np.ndarray:
    """The HRZ-lumped mass of every node (t), shape (n_nodes,) (module docstring); `space`: a
    `fem.discretisation.Discretisation`."""
    rho = element_densities(space.mesh, densities)
    shape = np.stack([np.asarray(phi[0]) for phi in space.basis.basis])  # (10, E, Q)
    diagonal = np.einsum("ieq,eq->ie", shape**2, space.dx)  # M_e,ii / rho_e
    element = rho * space.dx.sum(axis=1)  # rho_e V_e
    shares = diagonal / diagonal.sum(axis=0)
    return np.bincount(space.node_dofs.reshape(-1), (shares * element).reshape(-1), minlength=space.n_nodes)


@dataclass(frozen=True)
class Inertia:
    """The body's inertia: one density (t/mm^3) or a mapping subdomain -> density (elements of no
    named subdomain are massless); a term of `fem.model.SolidModel` (`extra_terms`)."""

    densities: object

    def build(self, space) -> InertiaTerm:
        return InertiaTerm(space, self)


class InertiaTerm:
    """Lumped mass with backward Euler (module docstring): the nodes that carry mass, per direction."""

    symmetric = True
    name = "inertia"

    def __init__(self, space, spec: Inertia) -> None:
        masses = lumped_masses(space, spec.densities)
        nodes = np.flatnonzero(masses > 0)
        self.spec, self.mass = spec, masses[nodes]
        self.dofs = 3 * nodes[None, :] + np.arange(3)[:, None]  # (3, n): one item per node
        self.u_n = np.zeros(self.dofs.shape)
        self.v_n = np.zeros(self.dofs.shape)
        self.time_step: float | None = None

    @property
    def total_mass(self) -> float:
        """sum_i m_i (t)."""
        return float(self.mass.sum())

    def set_time_step(self, dt: float | None) -> None:
        """The duration (s) of the sub-step about to be solved (None: quasi-static)."""
        self.time_step = None if dt is None else positive(dt, "inertia.time_step")

    def rest(self, x: np.ndarray) -> None:
        """The body at rest at state x (committed: u_n = u(x), v_n = 0)."""
        self.u_n = x[self.dofs].copy()
        self.v_n = np.zeros(self.dofs.shape)

    def set_history(self, u_n: np.ndarray, v_n: np.ndarray) -> None:
        """A committed state read back (a checkpoint): displacements and velocities, shape (3, n)."""
        if np.shape(u_n) != self.dofs.shape or np.shape(v_n) != self.dofs.shape:
            raise SolverInputError("inertia.history", f"arrays of shape {self.dofs.shape} expected")
        self.u_n, self.v_n = np.array(u_n, dtype=float), np.array(v_n, dtype=float)

    def velocity(self) -> np.ndarray:
        """The committed nodal velocities (mm/s), shape (3, n)."""
        return self.v_n.copy()

    def kinetic_energy(self) -> float:
        """1/2 sum_i m_i |v_i|^2 at the committed state (mJ = N mm)."""
        return float(0.5 * (self.mass * (self.v_n**2).sum(axis=0)).sum())

    def momentum(self) -> np.ndarray:
        """sum_i m_i v_i at the committed state (t mm/s = N s), per direction."""
        return (self.mass * self.v_n).sum(axis=1)

    def arrays(self, x, pressures=None, with_tangent=True):
        """Node residuals (3, n) and tangents (n, 3, 3); zero without a time step."""
        dt = self.time_step
        n = self.mass.size
        if dt is None:
            return np.zeros(self.dofs.shape), (np.zeros((n, 3, 3)) if with_tangent else None)
        a = (x[self.dofs] - self.u_n - dt * self.v_n) / dt**2
        r = self.mass * a
        K = (self.mass / dt**2)[:, None, None] * np.eye(3) if with_tangent else None
        return r, K

    def commit(self, x: np.ndarray) -> None:
        """A converged sub-step (module docstring): v_n, u_n move on, and the sub-step ends."""
        u = x[self.dofs]
        dt = self.time_step
        self.v_n = np.zeros(self.dofs.shape) if dt is None else (u - self.u_n) / dt
        self.u_n = u.copy()
        self.time_step = None
