r"""Viscous stabilisation: a proximal term that lets a pseudo-time path cross a snap (record 094).

Over a sub-step of pseudo-time dt from the committed displacements u_n, the term adds to the
residual, per node i and direction, a viscous force proportional to the node's share of the volume
V_i and to its velocity in pseudo-time, and its derivative to the tangent:

    r_i = c V_i (u_i - u_n,i) / dt,          K_i = c V_i / dt I_3        (symmetric, positive),

with c the stabilisation's viscosity (N s/mm^4 per unit of pseudo-time, set along a stage by its
drive) and dt the sub-step's share of the stage's `duration` (`fem.contact_stages`). A sub-step
then solves the stationarity of Pi(u) + c/(2 dt) sum_i V_i |u_i - u_n,i|^2: one implicit step of a
gradient flow of the energy Pi in pseudo-time (a proximal step). Its tangent is K + c V / dt,
positive definite once c V_i / dt exceeds the magnitude of the body's most negative stiffness
eigenvalue, so where the static path has a limit point or a bifurcation (no equilibrium near the
last state) the sub-step still has a solution near u_n, and successive sub-steps move the body
across to the stable branch. Because the force goes with the velocity, a cut-back (dt halved)
doubles the regularisation while the force of a steady motion stays what it was: the term is
strong where the path is hard and weak where it is easy, as inertia's m / dt^2 is
(`fem.inertia`).

The price is an artificial force -c V (u - u_n) / dt on the body in every state the term is on:
`commit` keeps its resultant (`force`, N, per direction), which a momentum balance adds to the
other external forces, and a stage whose end must be a static equilibrium takes c to exactly 0
(then the term adds nothing and the solve is the static one). Without a time step (dt None: a
pseudo-time stage with no duration) the term adds nothing either. V_i is the node's lumped
volume (`fem.inertia.lumped_masses` at unit density), so c does not depend on the mesh: the term
is Abaqus's "automatic stabilization" with the volume in place of the mass.

`commit(x)` (a converged sub-step) keeps that resultant, sets u_n <- u(x) and ends the sub-step;
`rest(x)` sets u_n without a sub-step (a run's start, or a state read back: the committed state is
the last converged one) and the resultant to 0.
"""

from __future__ import annotations

import numpy as np

from softcrawl.fem.errors import SolverInputError
from softcrawl.fem.inertia import lumped_masses
from softcrawl.fem.rigid_surfaces import positive


class Stabilisation:
    """Viscous stabilisation on every node of the body (module docstring); a term of
    `fem.model.SolidModel` (`extra_terms`) whose coefficient starts at 0 (off)."""

    symmetric = True
    name = "stabilisation"

    def build(self, space) -> Stabilisation:
        volumes = lumped_masses(space, 1.0)
        nodes = np.flatnonzero(volumes > 0)
        self.volume = volumes[nodes]
        self.dofs = 3 * nodes[None, :] + np.arange(3)[:, None]  # (3, n): one item per node
        self.u_n = np.zeros(self.dofs.shape)
        self.coefficient = 0.0
        self.time_step: float | None = None
        self.force = np.zeros(3)  # resultant on the body in the last committed sub-step, N
        return self

    def set_coefficient(self, c: float) -> None:
        """c (N s/mm^4) for the sub-steps that follow; 0 switches the term off."""
        if not (np.isfinite(c) and c >= 0):
            raise SolverInputError("stabilisation.coefficient", f"a finite c >= 0 in N s/mm^4, not {c!r}")
        self.coefficient = float(c)

    def set_time_step(self, dt: float | None) -> None:
        """The pseudo-time (s) of the sub-step about to be solved (None: the term is off)."""
        self.time_step = None if dt is None else positive(dt, "stabilisation.time_step")

    def _weights(self) -> np.ndarray:
        if self.time_step is None:
            return np.zeros_like(self.volume)
        return self.coefficient * self.volume / self.time_step

    def rest(self, x: np.ndarray) -> None:
        """Commit the state x without a sub-step: u_n = u(x), no resultant."""
        self.u_n = x[self.dofs].copy()
        self.force = np.zeros(3)

    def commit(self, x: np.ndarray) -> None:
        """A converged sub-step: keep the resultant -sum_i c V_i (u_i - u_n,i) / dt, u_n <- u(x),
        and end the sub-step."""
        u = x[self.dofs]
        self.force = -(self._weights() * (u - self.u_n)).sum(axis=1)
        self.u_n = u.copy()
        self.time_step = None

    def arrays(self, x, pressures=None, with_tangent=True):
        """Node residuals (3, n) and tangents (n, 3, 3); zero when c = 0 or without a time step."""
        cv = self._weights()
        r = cv * (x[self.dofs] - self.u_n)
        K = cv[:, None, None] * np.eye(3) if with_tangent else None
        return r, K
