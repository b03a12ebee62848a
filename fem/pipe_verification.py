r"""The verification case of the contact term against the elbow's torus wall (`fem.pipe_surfaces`).

contact-elbow: a tile of material (2 mm along the pipe, 1 mm around it, 1 mm thick; Neo-Hookean,
mu = 1 MPa, K = 3 MPa) lies on the outer wall of a 90 deg elbow (pipe radius r = 10 mm, bend radius
R = 25 mm) at the middle of the bend, its base on the torus (its P2 nodes mapped onto the torus
coordinates, 2 um into the wall). It is pressed by a dead force F = p A (p = 0.2 MPa on the
reference top area A = 2 mm^2) along the outward normal of the wall at the tile's centre, and it
is held by nothing else: no Dirichlet condition, no friction.

Closed form. A frictionless wall pushes along its normal only, and every normal of a torus lies
in a meridian plane, which contains the torus axis: the contact forces have no moment about the
torus axis, M_axis = 0 for any pressure distribution. At equilibrium the contact forces balance
the load, N_vec = sum n p_N dA = -F (three components, exactly). The error is the larger of
|N_vec + F| / |F| and |M_axis| / (|F| (R + r)).

The case tests the torus in the consistent tangent: the body's rotation about the torus axis
leaves every gap unchanged (the wall is invariant under it, and n . w = 0), so only the curvature
term p_N C, with the torus's curvature cos(theta) / rho along the pipe, gives that rigid mode its
stiffness (sum p_N dA rho cos(theta) per radian squared, the dead load's restoring moment). Without
that curvature the tangent is singular in it and the press does not converge. The details give
Newton's observed order in the last increment (a frictionless press in which every base point
stays in contact: quadratic), and sum p_N dA / |F| (> 1: the normals spread over the curved base).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import skfem

from softcrawl.fem.contact import ContactSpec
from softcrawl.fem.contact_stages import Stage, run_stages
from softcrawl.fem.contact_verification import MATERIAL, convergence_order
from softcrawl.fem.model import SolidModel
from softcrawl.fem.newton import NewtonOptions
from softcrawl.fem.pipe_surfaces import ElbowPipe
from softcrawl.fem.structured import box
from softcrawl.fem.verification import CaseResult


def elbow_tile(pipe: ElbowPipe, at: float, size=(2.0, 1.0, 1.0), cells=(4, 2, 2), theta=0.0, depth=0.002):
    """A P2 tile on the wall of `pipe`: the box (xi, eta, zeta) mapped to the centreline's arc
    length at + xi - size[0] / 2 (`ElbowPipe.frame`: the legs or the torus), angle
    theta + (eta - size[1] / 2) / r around the pipe (0: the outer side of the bend) and distance
    r + depth - zeta from the centreline: its base "z0" lies `depth` into the wall, its top is "z1".
    All P2 nodes are mapped, so the base follows the wall to the P2 interpolation error."""
    straight = box(size, cells)
    m2 = replace(skfem.MeshTet2.from_mesh(straight), _boundaries=straight.boundaries)
    xi, eta, zeta = m2.doflocs - np.array([size[0] / 2, size[1] / 2, 0.0])[:, None]
    c, _, u = pipe.frame(at + xi)
    th = (theta + eta / pipe.radius)[:, None]
    d = (pipe.radius + depth - zeta)[:, None]
    x = c + d * (np.cos(th) * u + np.sin(th) * pipe.torus_axis)
    return replace(m2, doflocs=np.ascontiguousarray(x.T))


def elbow_test(pressure=0.2, penalty=100.0, steps=1, tolerance=1e-8) -> CaseResult:
    """The tile pressed on the elbow's outer wall (module docstring)."""
    pipe = ElbowPipe(radius=10.0, bend_radius=25.0, entry=20.0)
    size = (2.0, 1.0, 1.0)
    middle = pipe.entry + pipe.bend_radius * pipe.bend_angle / 2
    mesh = elbow_tile(pipe, middle, size)
    outward = pipe.frame([middle])[2][0]  # u at the tile's centre, the wall's normal there (theta = 0)
    load = pressure * size[0] * size[1] * outward
    spec = ContactSpec(("z0",), pipe, penalty=penalty, max_initial_penetration=0.003)
    model = SolidModel(mesh, MATERIAL, dead_loads={"z1": tuple(load)}, contacts=[spec])
    res = run_stages(
        model,
        [Stage("press", factor=1.0, steps=steps)],
        penetration_tol=1e-8,
        max_augment=8,
        options=NewtonOptions(tol=1e-11),
    )
    if not res.converged:
        return CaseResult("contact-elbow", np.inf, tolerance, {"message": res.message})
    term = model.contacts[0]
    st = term.state(res.x)
    dA = term.dA.reshape(-1)
    forces = st.normal * (st.pressure * dA)[:, None]
    resultant = forces.sum(axis=0)
    arm = term.positions(res.x) - pipe.torus_centre
    moment_axis = float(np.cross(arm, forces).sum(axis=0) @ pipe.torus_axis)
    F = float(np.linalg.norm(load))
    errors = {
        "resultant": float(np.linalg.norm(resultant + load) / F),
        "moment_about_torus_axis": abs(moment_axis) / (F * (pipe.bend_radius + pipe.radius)),
    }
    rep = term.report(res.x)
    return CaseResult(
        "contact-elbow",
        max(errors.values()),
        tolerance,
        {
            "load_N": F,
            "normal_force_vector": resultant.tolist(),
            "normal_force_sum_over_load": rep.normal_force / F,
            "max_penetration": rep.max_penetration,
            "contact_fraction": rep.contact_fraction,
            "errors": errors,
            "order_last_increment": convergence_order(res.steps[-1].residuals),
            "residuals_last": list(res.steps[-1].residuals),
            "dofs": model.n_dofs,
        },
    )


CASES = {"contact-elbow": elbow_test}
