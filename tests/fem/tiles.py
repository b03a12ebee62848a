"""Shared by the rigid-pipe tests (test_pipe_surfaces.py: the elbow; test_corrugated_pipe.py: the
bellows): a small P2 tile pressed onto a wall, and the contact law's tangent on a curved wall
against central differences."""

from __future__ import annotations

import numpy as np

from softcrawl.fem.contact import ContactSpec
from softcrawl.fem.contact_law import evaluate
from softcrawl.fem.contact_stages import Stage, run_stages
from softcrawl.fem.contact_verification import MATERIAL
from softcrawl.fem.model import SolidModel
from softcrawl.fem.newton import NewtonOptions


def press_tile(mesh, surface, load, dirichlet=()):
    """The tile `mesh` (base "z0" a few um into `surface`, top "z1") pressed by the dead load `load`
    (N) on its top in one frictionless step (penalty 100, `verify`'s contact material), Newton to
    1e-11 -> (result, contact state, contact resultant sum p_N n dA, contact term)."""
    spec = ContactSpec(("z0",), surface, penalty=100.0, max_initial_penetration=0.003)
    model = SolidModel(mesh, MATERIAL, dirichlet=dirichlet, dead_loads={"z1": tuple(load)}, contacts=[spec])
    res = run_stages(
        model, [Stage("press", factor=1.0, steps=1)], penetration_tol=1e-8, options=NewtonOptions(tol=1e-11)
    )
    term = model.contacts[0]
    st = term.state(res.x)
    resultant = (st.normal * (st.pressure * term.dA.reshape(-1))[:, None]).sum(axis=0)
    return res, st, resultant, term


def assert_tangent_matches_differences(x, args, h=1e-6, rtol=1e-7):
    """-df/dx of `evaluate(x, *args)` against central differences of its force, with at least two
    slipping, two sticking and two open points among `x` (so every branch is checked)."""
    st = evaluate(x, *args, True)
    assert st.slip.sum() >= 2 and (st.active & ~st.slip).sum() >= 2 and (~st.active).sum() >= 2
    for j in range(3):
        step = np.zeros(3)
        step[j] = h
        num = -(evaluate(x + step, *args, False).force - evaluate(x - step, *args, False).force) / (2 * h)
        assert np.abs(num - st.stiffness[:, :, j]).max() < rtol * np.abs(st.stiffness).max()
