"""Several chambers, each with its own follower pressure, against the closed forms.

Two disjoint bodies in one mesh, each with its own chamber: the per-chamber pressures, their
load vectors and tangents are right exactly when each body follows its own single-chamber closed
form (docs/decisions/010-verification.md) at its own pressure. Volume control along a two-chamber load
direction is checked past the limit point of one sphere while the other stays on its stable branch.
"""

import numpy as np
import pytest

from softcrawl.fem import analytic
from softcrawl.fem.errors import SolverInputError
from softcrawl.fem.laws import NeoHookean
from softcrawl.fem.model import ChamberSpec, Dirichlet, SolidModel
from softcrawl.fem.path import load_path
from softcrawl.fem.reference_models import MU
from softcrawl.fem.structured import curved, joined, mirrored, sphere_octant, tag_boundaries, tube_sector

A, B = 1.0, 20.0  # the verification tube (docs/decisions/010-verification.md)


def two_tubes():
    """Plane-strain quarter tubes z in [0, 1] and [2, 3] on one axis, chambers "inner_a", "inner_b"."""
    lower = tube_sector(A, B, height=1.0, n_radial=12, n_angle=8, geometric=True, quadratic=False)
    upper = tube_sector(A, B, height=1.0, n_radial=12, n_angle=8, geometric=True, quadratic=False)
    upper = upper.translated((0.0, 0.0, 2.0))
    mesh = joined(lower, upper)

    def radius(x):
        return np.hypot(x[0], x[1])

    def near(v):
        return lambda x: np.abs(x[2] - v) < 1e-9

    mesh = tag_boundaries(
        mesh,
        {
            "inner_a": lambda x: (np.abs(radius(x) - A) < 1e-6) & (x[2] < 1.5),
            "inner_b": lambda x: (np.abs(radius(x) - A) < 1e-6) & (x[2] > 1.5),
            "sym_x": lambda x: np.abs(x[0]) < 1e-9,
            "sym_y": lambda x: np.abs(x[1]) < 1e-9,
            **{f"cap{v}": near(v) for v in (0, 1, 2, 3)},
        },
    )
    bcs = [Dirichlet.symmetry("sym_x", 0), Dirichlet.symmetry("sym_y", 1)]
    bcs += [Dirichlet.symmetry(f"cap{v}", 2) for v in (0, 1, 2, 3)]
    chambers = [ChamberSpec((t,), (1, 1, 0)) for t in ("inner_a", "inner_b")]
    return SolidModel(
        curved(mesh, "cylinder"),
        NeoHookean.nearly_incompressible(MU, 1000.0),
        dirichlet=bcs,
        chambers=chambers,
    )


def _inner_radius(model, x, lower: bool):
    nodes = model.boundary_nodes("inner_a" if lower else "inner_b")
    pos = model.nodes[:, nodes] + model.displacement(x)[:, nodes]
    return float(np.hypot(pos[0], pos[1]).mean())


def test_each_chamber_carries_its_own_pressure():
    model = two_tubes()
    P = (0.5 * MU, 2.0 * MU)
    res = load_path(model, [((0.25 * MU, 1.0 * MU), 0.0), (P, 0.0)])
    assert res.converged, res.message
    x = res.steps[-1].x
    assert res.steps[-1].pressure == pytest.approx(P)
    assert len(res.steps[-1].volumes) == 2
    for lower, p in ((True, P[0]), (False, P[1])):
        exact = analytic.tube_inner_stretch(MU, p, A, B) * A
        # observed 2.3e-5 at 0.5 mu and 1.4e-3 at 2 mu (the K/mu = 1000 compressibility)
        assert _inner_radius(model, x, lower) == pytest.approx(exact, rel=5e-3)


def test_the_final_state_does_not_depend_on_the_loading_sequence():
    """A hyperelastic body under conservative (closed-chamber) pressures has one equilibrium per
    load: proportional and sequential paths end in the same state."""
    model = two_tubes()
    P = (1.0 * MU, 0.5 * MU)
    together = load_path(model, [(P, 0.0)]).steps[-1].x
    one_after_the_other = load_path(model, [((P[0], 0.0), 0.0), (P, 0.0)]).steps[-1].x
    u = model.displacement(together)
    assert np.abs(model.displacement(one_after_the_other) - u).max() <= 1e-6 * np.abs(u).max()


def test_a_wrong_number_of_pressures_is_a_named_error():
    model = two_tubes()
    with pytest.raises(SolverInputError) as err:
        model.residual(model.initial_state(), (0.01, 0.02, 0.03))
    assert err.value.parameter == "pressure"


def two_spheres():
    """Thick-sphere octants A = 5, B = 7.5 mm on both sides of the plane x = 0 (disjoint bodies
    that touch the plane, each held there by symmetry), chambers "inner_a" (x > 0), "inner_b"."""
    a = sphere_octant(5.0, 7.5, n_radial=3, n_surface=4, quadratic=False)
    mesh = joined(a, mirrored(a, 0))

    def inner(x):
        return np.abs(np.linalg.norm(x, axis=0) - 5.0) < 1e-6

    mesh = tag_boundaries(
        mesh,
        {
            "inner_a": lambda x: inner(x) & (x[0] >= -1e-9),
            "inner_b": lambda x: inner(x) & (x[0] <= 1e-9),
            **{f"sym_{c}": (lambda x, i=i: np.abs(x[i]) < 1e-9) for i, c in enumerate("xyz")},
        },
    )
    bcs = [Dirichlet.symmetry(f"sym_{c}", i) for i, c in enumerate("xyz")]
    chambers = [ChamberSpec(("inner_a",)), ChamberSpec(("inner_b",))]
    return SolidModel(
        curved(mesh, "sphere"), NeoHookean.nearly_incompressible(MU, 1000.0), dirichlet=bcs, chambers=chambers
    )


def _sphere_stretch(model, x, tag):
    nodes = model.boundary_nodes(tag)
    pos = model.nodes[:, nodes] + model.displacement(x)[:, nodes]
    return float(np.linalg.norm(pos, axis=0).mean() / 5.0)


def test_volume_control_along_a_two_chamber_load_direction_passes_one_limit_point():
    """P = (p, p/2) towards 1.2 x the analytic maximum of sphere a: pressure control stalls at a's
    limit point, volume control of a goes on along d = (1, 1/2). The limit pressure is a's
    analytic maximum (observed error 6.8e-4) and, on the way, sphere b follows its own closed form
    at half the pressure (observed 6.2e-4)."""
    model = two_spheres()
    _, p_max = analytic.sphere_limit(MU, 5.0, 7.5)
    targets = [((f * p_max, 0.5 * f * p_max), 0.0) for f in np.linspace(0.2, 1.2, 6)]
    res = load_path(model, targets)
    assert res.limit_pressure is not None, res.message
    assert res.limit_pressure == pytest.approx(p_max, rel=2.5e-3)
    assert any(s.control == "volume" for s in res.steps)
    for step in res.steps:
        pa, pb = step.pressure
        assert pb == pytest.approx(0.5 * pa, rel=1e-9)  # the load stays on its direction
        la = _sphere_stretch(model, step.x, "inner_b")
        assert analytic.sphere_pressure(MU, la, 5.0, 7.5) == pytest.approx(pb, rel=2e-3)
