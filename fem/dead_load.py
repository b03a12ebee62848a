r"""Dead loads: a total force on a boundary, spread over its reference area (a weight), and
body forces (gravity) per subdomain.

f_dead = sum_tag (F_tag / A_tag) int_tag N_a dA on the displacement dofs (A_tag: reference
area). A dead traction keeps its direction and magnitude as the body deforms, like a weight; it
is scaled by the load factor f of the path, like the prescribed displacements, and adds nothing
to the tangent: R = f_int - P q - f f_dead.
"""

from __future__ import annotations

import numpy as np
import skfem

from softcrawl.fem.discretisation import Discretisation
from softcrawl.fem.errors import SolverInputError


def dead_load_vector(space: Discretisation, dead_loads) -> np.ndarray:
    """f_dead on all dofs of `space` for `dead_loads`, a mapping tag -> (Fx, Fy, Fz) in N."""
    out = np.zeros(space.n_dofs)
    for tag, force in (dead_loads or {}).items():
        facets = space.boundary(tag, "dead_loads")
        force = np.asarray(force, dtype=float)
        if force.shape != (3,) or not np.all(np.isfinite(force)):
            raise SolverInputError("dead_loads", f"{tag}: give a finite total force (Fx, Fy, Fz) in N")
        weights = skfem.asm(skfem.LinearForm(lambda v, w: v), space.facet_basis(facets))  # int N_a dA
        out[: space.n_u] += (weights[:, None] * force[None, :] / weights.sum()).reshape(-1)
    return out


def body_force_vector(space: Discretisation, body_forces) -> np.ndarray:
    """int_Omega b N_a dV on all dofs for `body_forces`, a mapping subdomain -> b (3,) in N/mm^3
    (a weight: density (t/mm^3) times the gravity vector (mm/s^2)), constant in each subdomain."""
    out = np.zeros(space.n_dofs)
    subdomains = space.mesh.subdomains or {}
    for name, b in (body_forces or {}).items():
        b = np.asarray(b, dtype=float)
        if name not in subdomains:
            raise SolverInputError("body_forces", f"unknown subdomain {name!r}; known: {sorted(subdomains)}")
        if b.shape != (3,) or not np.all(np.isfinite(b)):
            raise SolverInputError("body_forces", f"{name}: give a finite force per volume (bx, by, bz)")
        basis = skfem.Basis(space.mesh, skfem.ElementTetP2(), intorder=2, elements=subdomains[name])
        weights = skfem.asm(skfem.LinearForm(lambda v, w: v), basis)  # int N_a dV
        out[: space.n_u] += (weights[:, None] * b[None, :]).reshape(-1)
    return out
