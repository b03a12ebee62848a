"""Small structured models with closed-form solutions: the plane-strain thick tube and the
thick-sphere octant (docs/decisions/010-verification.md), and measures on them.

The verification cases (`fem.verification`), the benchmarks and the tests build their models here.
"""

from __future__ import annotations

import numpy as np

from softcrawl.fem import analytic
from softcrawl.fem.laws import NeoHookean
from softcrawl.fem.model import ChamberSpec, Dirichlet, SolidModel
from softcrawl.fem.path import load_path
from softcrawl.fem.structured import sphere_octant, tube_sector

MU = 0.03  # MPa, Ecoflex 00-50 default (docs/decisions/001-materials.md)


def tube_model(
    inner=1.0,
    outer=20.0,
    n_radial=12,
    n_angle=8,
    k_over_mu=1000.0,
    formulation="p2p1",
    fiber_sheets=(),
    law=None,
    top_stretch=None,
):
    """The 1/4 tube slice of height 1 mm. Plane strain (top on a symmetry plane) unless
    `top_stretch` is given: then the top face moves axially by (top_stretch - 1) mm times the
    load factor (a prescribed uniform axial stretch). `law` replaces the Neo-Hookean MU body."""
    mesh = tube_sector(
        inner, outer, height=1.0, n_radial=n_radial, n_angle=n_angle, n_height=1, geometric=True
    )
    top = (
        Dirichlet.symmetry("top", 2)
        if top_stretch is None
        else Dirichlet.prescribed("top", 2, float(top_stretch) - 1.0)
    )
    bcs = [
        Dirichlet.symmetry("sym_x", 0),
        Dirichlet.symmetry("sym_y", 1),
        Dirichlet.symmetry("bottom", 2),
        top,
    ]
    return SolidModel(
        mesh,
        law if law is not None else NeoHookean.nearly_incompressible(MU, k_over_mu),
        dirichlet=bcs,
        chambers=ChamberSpec(("inner",), (1, 1, 0)),
        formulation=formulation,
        fiber_sheets=fiber_sheets,
    )


def mean_radius(model: SolidModel, x, tag) -> float:
    nodes = model.boundary_nodes(tag)
    pos = model.nodes[:, nodes] + model.displacement(x)[:, nodes]
    return float(np.hypot(pos[0], pos[1]).mean())


def sphere_model(inner=5.0, outer=7.5, n_radial=3, n_surface=4, k_over_mu=1000.0, formulation="p2p1"):
    mesh = sphere_octant(inner, outer, n_radial=n_radial, n_surface=n_surface)
    bcs = [Dirichlet.symmetry("sym_x", 0), Dirichlet.symmetry("sym_y", 1), Dirichlet.symmetry("sym_z", 2)]
    return SolidModel(
        mesh,
        NeoHookean.nearly_incompressible(MU, k_over_mu),
        dirichlet=bcs,
        chambers=("inner",),
        formulation=formulation,
    )


def sphere_inner_stretch(model, x, inner):
    nodes = model.boundary_nodes("inner")
    pos = model.nodes[:, nodes] + model.displacement(x)[:, nodes]
    return float(np.linalg.norm(pos, axis=0).mean() / inner)


def tube_convergence(
    levels=((6, 4), (12, 8), (24, 16)), pressure_over_mu=0.5, k_over_mu=1000.0, inner=1.0, outer=20.0
):
    """Inner-radius error of the plane-strain tube under uniform refinement.

    Returns a list of (dofs, relative error) and the observed orders log2(e_k / e_{k+1}) (the
    levels halve the cell size). The analytic solution is incompressible, so at K/mu = 1000 the
    error levels off near the compressibility error O(p/K) once the discretisation error is below it.
    """
    rows = []
    for n_radial, n_angle in levels:
        model = tube_model(inner, outer, n_radial, n_angle, k_over_mu=k_over_mu)
        res = load_path(model, [(pressure_over_mu * MU, 0.0)])
        la = analytic.tube_inner_stretch(MU, pressure_over_mu * MU, inner, outer)
        err = abs(mean_radius(model, res.steps[-1].x, "inner") - la * inner) / (la * inner)
        rows.append((model.n_dofs, err))
    orders = [float(np.log2(a[1] / b[1])) for a, b in zip(rows, rows[1:])]
    return rows, orders
