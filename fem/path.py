r"""Path following: the load through a sequence of targets, with cut-back and limit points.

Load. A target is (P, f): the chamber pressure P (MPa) - a scalar applies to every chamber, a
sequence gives one pressure per chamber (the robot's three ePSAs) - and the factor f that scales
the prescribed Dirichlet values and the dead loads. Internally a load is the vector L = (P..., f).
Between two targets the load moves on a straight line in L (proportional loading; a sequential
path, e.g. P2 and P3 first and then P1, is two targets), in sub-steps; each sub-step starts from
the secant predictor (linear extrapolation of the last two converged states along L), a sub-step
whose Newton iteration diverges (`fem.newton`) is halved, and an easy one lets the next grow.

Limit points. When pressure control cannot advance (`max_cutbacks` halvings fail) on a segment
that raises a chamber pressure, the path goes on under volume control from the last converged
state (`fem.continuation`), along the same load direction. If volume control cannot advance
either, the path ends with `converged = False` and a message that names the last converged load.
Nothing here raises on divergence.

Terms with a history (contact) are told every accepted state (`SolidModel.commit`), never a trial.
"""

from __future__ import annotations

import time

import numpy as np

from fem.continuation import parabola_peak, volume_continuation
from fem.errors import SolverInputError
from fem.model import SolidModel
from fem.newton import Diverged, NewtonOptions, NewtonRecord, NewtonSolver, SolveStats
from fem.steps import History, LoadShape, PathResult, ReportingList, Step, describe_load, failed, make_step

__all__ = [
    "NewtonOptions",
    "NewtonRecord",
    "PathResult",
    "SolveStats",
    "Step",
    "describe_load",
    "load_path",
    "volume_path",
]


def load_path(
    model: SolidModel,
    targets,
    *,
    options: NewtonOptions | None = None,
    control: str = "pressure",
    on_step=None,
) -> PathResult:
    """Follow the load through `targets`, a sequence of (pressure MPa, load factor) pairs (the
    pressure a float, or one per chamber). Starts from the undeformed state at zero load. See
    the module docstring for cut-back and limit points. `control` only labels the steps
    ("pressure" or "displacement"). `on_step`, if given, is called with every converged `Step`
    as it is found (progress reports)."""
    opt = options or NewtonOptions()
    targets = [(P, float(f)) for P, f in targets]
    if not targets:
        raise SolverInputError("targets", "give at least one load target")
    shape = LoadShape(targets)
    loads = [shape.vector(P, f) for P, f in targets]
    solver = NewtonSolver(model, opt)
    t0 = time.perf_counter()
    history = History(model.initial_state(), np.zeros(shape.n + 1))
    steps = ReportingList(on_step)
    events: list[str] = []
    step = [np.inf]  # the last accepted sub-step, as a load distance (see `_advance`)
    for i, target in enumerate(loads):
        try:
            record, n_sub = _advance(solver, history, target, opt, step)
        except Diverged as exc:
            rising = bool(np.any(target[:-1] > history.load[:-1]))
            if not model.chambers or not rising:
                return failed(steps, events, solver, t0, history.load, str(exc))
            # Pressure control cannot advance: volume control from the last converged state,
            # through the remaining targets (fem.continuation).
            events.append(
                f"pressure control stalled above {describe_load(history.load)} ({exc}); "
                "switching to volume control"
            )
            return volume_continuation(solver, shape, history, loads[i:], steps, events, opt, t0)
        steps.append(make_step(model, shape, target, history.x, control, record, n_sub))
    return PathResult(tuple(steps), True, "all load targets reached", None, tuple(events), solver.stats(t0))


def _advance(solver: NewtonSolver, history: History, end, opt, step=None):
    """From the last converged load to `end` in adaptive sub-steps, each started from the
    secant prediction; returns (last Newton record, number of sub-steps). `step` ([distance])
    carries the last accepted sub-step (a load distance) from segment to segment: a path of many
    targets starts each segment with twice the step that last worked instead of the whole
    segment, which on a hard path (the bending robot) fails first and costs a diverged Newton
    iteration per target."""
    start = history.load
    length = float(np.linalg.norm(end - start))
    h0 = 1.0 if step is None or length == 0.0 else min(1.0, 2.0 * step[0] / length)
    t, h, n_sub, cuts = 0.0, h0, 0, 0
    record = None
    while t < 1.0 - 1e-14:
        intended = h
        h = min(h, 1.0 - t)
        s = t + h
        load = start + s * (end - start)
        try:
            x_new, record = solver.load_step(history.predict(load), load[:-1], load[-1])
        except Diverged:
            h *= 0.5
            cuts += 1
            if cuts > opt.max_cutbacks or h < opt.min_step_fraction:
                raise
            continue
        history.accept(x_new, load)
        solver.model.commit(x_new)
        if step is not None:
            step[0] = intended * length  # the step size that worked, before the segment end clipped it
        t = s
        n_sub += 1
        if record.iterations <= 6:
            h *= 2.0
    if record is None:  # zero-length segment
        x_new, record = solver.load_step(history.x, end[:-1], end[-1])
        history.accept(x_new, end)
        solver.model.commit(x_new)
    return record, n_sub


def volume_path(
    model: SolidModel, volumes, *, factor: float = 0.0, options: NewtonOptions | None = None
) -> PathResult:
    """Prescribe the cavity volume through `volumes` (mm^3); the pressure is an unknown (one
    chamber, or the same pressure in every chamber)."""
    opt = options or NewtonOptions()
    if not model.chambers:
        raise SolverInputError("chamber", "volume control needs a chamber surface")
    shape = LoadShape([(0.0, factor)])
    solver = NewtonSolver(model, opt)
    t0 = time.perf_counter()
    x = model.apply_dirichlet(model.initial_state(), factor)
    P = 0.0
    V = model.chamber_volume(x)
    steps: list[Step] = []
    events: list[str] = []
    for Vt in volumes:
        start_V, h, cuts, t, record = V, 1.0, 0, 0.0, None
        while t < 1.0 - 1e-14:
            h = min(h, 1.0 - t)
            try:
                x_new, P_new, record = solver.volume_step(x, P, start_V + (t + h) * (Vt - start_V), factor)
            except Diverged as exc:
                h *= 0.5
                cuts += 1
                if cuts > opt.max_cutbacks:
                    return failed(steps, events, solver, t0, shape.vector(P, factor), str(exc), volume=V)
                continue
            x, P, t = x_new, float(P_new[0]), t + h
            model.commit(x)
            V = start_V + t * (Vt - start_V)
        steps.append(Step(P, factor, V, x, "volume", record, volumes=(V,)))
    limit = None
    ps = [s.pressure for s in steps]
    k = int(np.argmax(ps))
    if 0 < k < len(ps) - 1:
        limit = parabola_peak([(steps[j].volume, steps[j].pressure) for j in (k - 1, k, k + 1)])
        events.append(f"limit point at P ~ {limit * 1e3:.4g} kPa")
    return PathResult(
        tuple(steps), True, "all volume targets reached", limit, tuple(events), solver.stats(t0)
    )
