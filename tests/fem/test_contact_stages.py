"""The augmented-Lagrangian loop of `fem.contact_stages` when a Uzawa re-solve diverges."""

from types import SimpleNamespace

import numpy as np

from fem import contact_stages as cs
from fem.newton import Diverged, NewtonRecord


class _Term:
    """A contact term whose penetration is 1 / (1 + number of solves) and whose Uzawa update
    moves the multiplier towards 1."""

    def __init__(self):
        self.multiplier = np.zeros(1)
        self.committed = None

    def augment(self, x, relax=1.0):
        self.multiplier = self.multiplier + relax * (1.0 - self.multiplier)
        return float(x[1])


class _Solver:
    """Converges while the multiplier's relaxed step is small enough, diverges otherwise."""

    def __init__(self, term, limit):
        self.term, self.limit, self.calls = term, limit, []

    def load_step(self, x, P, f):
        self.calls.append(float(self.term.multiplier[0]))
        if self.term.multiplier[0] > self.limit:
            raise Diverged("residual stalls")
        n = len(self.calls)
        return np.array([float(self.term.multiplier[0]), 1.0 / (1 + n)]), NewtonRecord((1.0, 1e-9), True)


def _model(term):
    model = SimpleNamespace(contacts=[term])
    model.commit = lambda x: setattr(term, "committed", x.copy())
    return model


def test_a_diverged_uzawa_resolve_keeps_the_last_converged_solve_and_its_multipliers():
    term = _Term()
    solver = _Solver(term, limit=0.25)  # lambda above 0.25 diverges
    x, its, res, pen = cs._solve_augmented(solver, _model(term), np.zeros(2), 0.0, 1.0, 1e-6, 4)
    # first solve at lambda = 0; the updates w = 1, 1/2 diverge, 1/4 converges (lambda = 1/4);
    # from there w = 1/4, 1/8, 1/16 diverge (MAX_RELAXATIONS + 1 failures): the loop stops
    assert cs.MAX_RELAXATIONS == 2
    assert solver.calls == [0.0, 1.0, 0.5, 0.25, 0.4375, 0.34375, 0.296875]
    assert len(its) == 2  # two converged solves
    assert x[0] == 0.25 and term.multiplier[0] == 0.25  # in equilibrium with its own multipliers
    assert np.array_equal(term.committed, x)  # the history is committed once, from that state
    assert pen == x[1] > 1e-6  # the penetration above tol is returned, not hidden


def test_converging_resolves_take_full_updates():
    term = _Term()
    solver = _Solver(term, limit=2.0)
    x, its, _, pen = cs._solve_augmented(solver, _model(term), np.zeros(2), 0.0, 1.0, 0.4, 4)
    assert solver.calls == [0.0, 1.0]  # one full update, then the penetration 1/3 < 0.4
    assert term.multiplier[0] == 1.0 and pen < 0.4 and len(its) == 2
