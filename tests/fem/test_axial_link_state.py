"""`fem.axial_link` at prescribed states, no solve: the link's dofs and weights, its extension,
tension, residual and tangent, `set_load`, and every bad input as one named error (issue 32).

A stub discretisation gives the boundary nodes: B = {4, 5} and A = {0, 1, 2}. With
Delta = mean_B u_c - mean_A u_c and T = F0 - k (Delta - Delta0): r = -T g and K = k g g^T.
"""

import math
from types import SimpleNamespace

import numpy as np
import pytest

from softcrawl.fem.axial_link import AxialLink
from softcrawl.fem.errors import SolverInputError

TAGS = {"b": np.array([4, 5]), "a": np.array([0, 1, 2]), "ab": np.array([2, 7])}
SPACE = SimpleNamespace(boundary_nodes=lambda tag: TAGS[tag])


def test_dofs_weights_extension_tension_and_arrays_of_an_internal_link():
    term = AxialLink("b", "a", component=1, stiffness=2.0, preload=0.5, rest=0.25).build(SPACE)
    assert term.dofs[:, 0].tolist() == [13, 16, 1, 4, 7]
    assert term.g.tolist() == [0.5, 0.5, -1 / 3, -1 / 3, -1 / 3]
    x = np.zeros(30)
    x[[13, 16]] = [1.0, 2.0]  # mean 1.5 over B
    x[[1, 4, 7]] = [0.0, 0.3, 0.6]  # mean 0.3 over A
    x[[12, 14, 0, 2]] = 9.0  # other components: not read
    assert term.extension(x) == pytest.approx(1.2)
    T = 0.5 - 2.0 * (1.2 - 0.25)
    assert term.tension(x) == pytest.approx(T)
    r, K = term.arrays(x)
    assert r[:, 0] == pytest.approx(-T * term.g)
    assert K[0] == pytest.approx(2.0 * np.outer(term.g, term.g))
    r2, none = term.arrays(x, with_tangent=False)
    assert none is None and np.array_equal(r, r2)
    assert term.name == "link" and term.symmetric


def test_a_ground_link_on_component_zero_and_set_load():
    term = AxialLink("b", None, component=0, stiffness=1.0, preload=0.0, rest=0.0, name="g").build(SPACE)
    assert term.dofs[:, 0].tolist() == [12, 15] and term.g.tolist() == [0.5, 0.5] and term.name == "g"
    x = np.zeros(30)
    x[[12, 15]] = 0.4
    assert term.tension(x) == pytest.approx(-0.4)
    term.set_load(3.0, 1.0, rest=0.1)
    assert (term.stiffness, term.preload, term.rest) == (3.0, 1.0, 0.1)
    assert term.tension(x) == pytest.approx(1.0 - 3.0 * (0.4 - 0.1))
    term.set_load(0.0, -2.0)  # no rest given: the rest extension stays; a negative preload pulls
    assert (term.stiffness, term.preload, term.rest) == (0.0, -2.0, 0.1)


@pytest.mark.parametrize(
    "kwargs, parameter, detail",
    [
        ({"component": 3}, "axial_link.component", "must be 0, 1 or 2"),
        ({"component": -1}, "axial_link.component", "must be 0, 1 or 2"),
        ({"stiffness": -1.0}, "axial_link.stiffness", "must be a finite number >= 0, got -1.0"),
        ({"stiffness": math.inf}, "axial_link.stiffness", "must be a finite number >= 0, got inf"),
        ({"preload": math.nan}, "axial_link.preload", "must be a finite number, got nan"),
        ({"preload": "abc"}, "axial_link.preload", "must be a finite number, got 'abc'"),
        ({"rest": None}, "axial_link.rest", "must be a finite number, got None"),
        ({"tag_a": "b"}, "axial_link.tag_a", "the two ends must be different boundaries"),
    ],
)
def test_a_bad_link_is_one_error_naming_its_parameter(kwargs, parameter, detail):
    with pytest.raises(SolverInputError) as err:
        AxialLink(**({"tag_b": "b"} | kwargs))
    assert (err.value.parameter, err.value.detail) == (parameter, detail)


def test_valid_links_are_accepted():
    for c in (0, 1, 2):
        AxialLink("b", "a", component=c, stiffness=0.0, preload=-1.0, rest=-2.0)


def test_ends_that_share_nodes_and_a_bad_load_are_named_errors():
    with pytest.raises(SolverInputError) as err:
        AxialLink("b", "ab").build(
            SimpleNamespace(boundary_nodes=lambda t: {"b": np.array([2, 4]), "ab": TAGS["ab"]}[t])
        )
    assert (err.value.parameter, err.value.detail) == ("axial_link.tag_a", "the two ends share nodes")
    term = AxialLink("b", "a").build(SPACE)
    for args, parameter, detail in (
        ((-0.5, 0.0), "axial_link.stiffness", "must be a finite number >= 0, got -0.5"),
        ((1.0, math.inf), "axial_link.preload", "must be a finite number, got inf"),
        ((1.0, 0.0, "x"), "axial_link.rest", "must be a finite number, got 'x'"),
    ):
        with pytest.raises(SolverInputError) as err:
            term.set_load(*args)
        assert (err.value.parameter, err.value.detail) == (parameter, detail)
