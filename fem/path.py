r"""Path following: the load through a sequence of targets, with cut-back and limit points.

Load. A target is (P, f): the chamber pressure P (MPa) - a scalar applies to every chamber, a
sequence gives one pressure per chamber (the robot's three ePSAs) - and the factor f that scales
the prescribed Dirichlet values and the dead loads. Internally a load is the vector L = (P..., f).
Between two targets the load moves on a straight line in L (proportional loading; a sequential
path, e.g. P2 and P3 first and then P1, is two targets), in sub-steps. The targets are landing
points, not the step size.

Predictor (`NewtonOptions.predictor`). "tangent", the default: the Euler step along the tangent
dx/ds = -K^{-1} dR/ds of the last converged state (`NewtonSolver.load_tangent`; s is the arc
length in L along the segment), bent into the quadratic x(s) = x + s v + s^2 w through the
previous converged state when that lies on the same load line (`History.hermite`); "secant":
linear extrapolation of the last two states; "none": the last state. A prediction that inverts
an element is drawn back towards the last state (`NewtonSolver.load_step`). With
`NewtonOptions.rigid_ratio`, the parts that much stiffer than the softest material move rigidly
in the prediction (`fem.stiff_parts`: a linear or quadratic extrapolation of a turning stiff
part stretches it, and the spurious stress costs Newton iterations).

Step size. A sub-step whose Newton iteration diverges is halved; after a converged one the next
grows or shrinks with the Newton iterations it took (`_growth`: the iteration count measures how
far the predictor was off), and the next target along the same load direction starts with the
last step length (`StepMemory`). docs/decisions/016-solver-pass1.md has the measurements.

Guards. A segment ends in a divergence after `max_cutbacks` halvings in a row, after
`max_substeps` sub-steps, or when the step shrinks below `min_step_fraction` of the segment;
each says which in the path's message.

Limit points. When pressure control cannot advance (`max_cutbacks` halvings fail) on a segment
that raises a chamber pressure, the path goes on under volume control from the last converged
state (`fem.continuation`), along the same load direction. If volume control cannot advance
either, the path ends with `converged = False` and a message that names the last converged load.
Nothing here raises on divergence.

Terms with a history (contact) are told every accepted state (`SolidModel.commit`), never a trial.

Resuming. `on_cursor` (if given) receives a `fem.path_cursor.PathCursor` after every converged
pressure-controlled sub-step; ``load_path(..., start=cursor)`` continues from it (the solver's
effort and wall time carried over), after a kill (`studies.robot_fe.response`).
"""

from __future__ import annotations

import time
from dataclasses import astuple

import numpy as np

from softcrawl.fem.continuation import parabola_peak, volume_continuation
from softcrawl.fem.errors import SolverInputError
from softcrawl.fem.model import SolidModel
from softcrawl.fem.newton import PREDICTORS, Diverged, NewtonOptions, NewtonRecord, NewtonSolver, SolveStats
from softcrawl.fem.path_cursor import PathCursor
from softcrawl.fem.steps import (
    History,
    LoadShape,
    PathResult,
    ReportingList,
    Step,
    describe_load,
    failed,
    make_step,
)
from softcrawl.fem.stiff_parts import StiffParts
from softcrawl.units import mpa_to_kpa  # the path works in MPa; its limit-point messages are read in kPa

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
    start=None,
    on_cursor=None,
) -> PathResult:
    """Follow the load through `targets`, a sequence of (pressure MPa, load factor) pairs (the
    pressure a float, or one per chamber). Starts from the undeformed state at zero load. See
    the module docstring for cut-back and limit points. `control` only labels the steps
    ("pressure" or "displacement"). `on_step`, if given, is called with every converged `Step`
    as it is found (progress reports). `start`, `on_cursor`: module docstring, "Resuming"."""
    opt = options or NewtonOptions()
    if opt.predictor not in PREDICTORS:
        raise SolverInputError("predictor", f"{opt.predictor!r} is not one of {PREDICTORS}")
    if opt.rigid_ratio is not None and not opt.rigid_ratio > 1.0:
        raise SolverInputError("rigid_ratio", f"must be a ratio > 1 or None, got {opt.rigid_ratio!r}")
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
    memory = StepMemory()
    rigid = StiffParts.of(model, opt.rigid_ratio) if opt.rigid_ratio else None
    if start is not None:
        _resume(model, solver, start, len(loads), history, steps, events, memory)
    report = None
    if on_cursor is not None:

        def report(i, seg_start, t, h, n_sub, trials):
            on_cursor(
                PathCursor(
                    i,
                    seg_start,
                    t,
                    h,
                    n_sub,
                    trials,
                    history.x,
                    history.load,
                    history.x_prev,
                    history.load_prev,
                    (memory.length, memory.direction),
                    tuple(steps),
                    tuple(events),
                    _carried(solver, t0, start),
                )  # fmt: skip
            )

    for i, target in enumerate(loads):
        if start is not None and i < start.target:
            continue
        resume = (
            (start.start, start.t, start.h, start.n_sub, start.trials)
            if start is not None and i == start.target
            else None
        )
        on_sub = None if report is None else (lambda *a, i=i: report(i, *a))
        try:
            record, n_sub = _advance(solver, history, target, opt, memory, rigid, resume, on_sub)
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
        if report is not None and i + 1 < len(loads):
            report(i + 1, history.load, 0.0, None, 0, 0)
    stats = _carried(solver, t0, start)
    return PathResult(tuple(steps), True, "all load targets reached", None, tuple(events), stats)


def _resume(model, solver, start, n_targets, history, steps, events, memory) -> None:
    """Put the path's state back to the cursor `start` (module docstring, "Resuming")."""
    if model.contacts:
        raise SolverInputError(
            "start", "a path cursor holds no contact history: resume with fem.contact_stages"
        )
    if not 0 <= start.target < n_targets:
        raise SolverInputError("start", f"target {start.target} of a path of {n_targets} targets")
    history.x, history.load = start.x.copy(), np.array(start.load, dtype=float)
    if start.x_prev is not None:
        history.x_prev, history.load_prev = start.x_prev.copy(), np.array(start.load_prev, dtype=float)
    memory.length, memory.direction = start.memory
    list.extend(steps, start.steps)  # reported already, by the run that found them
    events.extend(start.events)


def _carried(solver, t0, start) -> SolveStats:
    """The solver's statistics of this call, plus those of the run it resumes."""
    now = solver.stats(t0)
    if start is None:
        return now
    return SolveStats(*(a + b for a, b in zip(astuple(now), astuple(start.stats))))


class StepMemory:
    """The size of the last accepted sub-step (a load-space length) and its load direction: the
    next segment along the same direction starts with it instead of its full length."""

    def __init__(self) -> None:
        self.length, self.direction = None, None

    def first_fraction(self, direction, segment_length: float) -> float:
        # a zero-length segment (a repeated target) leaves no direction to compare with
        if self.length is None or self.direction is None or direction is None or segment_length == 0:
            return 1.0
        if float(np.dot(direction, self.direction)) < 1.0 - 1e-9:
            return 1.0
        return min(1.0, self.length / segment_length)


def _growth(iterations: int) -> float:
    """Factor of the next sub-step after one that took `iterations` Newton iterations: grow when
    easy, shrink when hard (the predictors make easy steps 2-4 iterations)."""
    if iterations <= 3:
        return 2.0
    if iterations <= 5:
        return 1.5
    if iterations <= 8:
        return 1.0
    return 0.6


def _predict(solver: NewtonSolver, history: History, load, direction, opt, rigid=None) -> np.ndarray:
    """The starting state of Newton's method at `load` (`NewtonOptions.predictor`), its stiff
    parts moved rigidly when `rigid` (a `fem.stiff_parts.StiffParts`) is given."""
    x = _extrapolate(solver, history, load, direction, opt)
    return x if rigid is None or x is history.x else rigid.project(history.x, x)


def _extrapolate(solver: NewtonSolver, history: History, load, direction, opt) -> np.ndarray:
    if opt.predictor == "none" or direction is None:
        return history.x
    if opt.predictor == "secant":
        return history.predict(load)
    if history.tangent is None or float(np.dot(history.tangent[0], direction)) < 1.0 - 1e-12:
        try:
            slope = solver.load_tangent(history.x, history.load, direction)
        except Diverged:
            return history.predict(load)
        history.tangent = (direction, slope)
    return history.hermite(load, direction, history.tangent[1])


def _advance(
    solver: NewtonSolver, history: History, end, opt, memory: StepMemory, rigid=None, resume=None, on_sub=None
):
    """From the last converged load to `end` in adaptive sub-steps (grown after easy ones, halved
    after a divergence), each started from the predictor; returns (last Newton record, number of
    sub-steps). Raises Diverged after `max_cutbacks` halvings in a row, below
    `min_step_fraction`, or after `max_substeps` sub-steps, with a message that says which.
    `resume`: (segment start load, t, h, sub-steps, attempts) of a cursor in this segment (h None:
    the segment's first); `on_sub(start, t, h, n_sub, trials)` after each converged sub-step but
    the segment's last."""
    start = history.load if resume is None else np.array(resume[0], dtype=float)
    span = end - start
    length = float(np.linalg.norm(span))
    direction = span / length if length > 0 else None
    t, h = 0.0, memory.first_fraction(direction, length)
    n_sub, cuts, trials = 0, 0, 0
    if resume is not None:
        t, n_sub, trials = float(resume[1]), int(resume[3]), int(resume[4])
        h = h if resume[2] is None else float(resume[2])
    record = None
    while t < 1.0 - 1e-14:
        trials += 1
        if trials > opt.max_substeps:
            raise Diverged(f"{opt.max_substeps} sub-steps (max_substeps) did not reach {describe_load(end)}")
        h = min(h, 1.0 - t)
        load = start + (t + h) * span
        try:
            x_new, record = solver.load_step(
                _predict(solver, history, load, direction, opt, rigid), load[:-1], load[-1], start=history.x
            )
        except Diverged as exc:
            h *= 0.5
            cuts += 1
            if cuts > opt.max_cutbacks or h < opt.min_step_fraction:
                raise Diverged(f"{exc} (after {cuts - 1} cut-backs of the load step)") from None
            continue
        history.accept(x_new, load)
        solver.model.commit(x_new)
        t += h
        n_sub, cuts = n_sub + 1, 0
        h *= _growth(record.iterations)
        if h < opt.min_step_fraction and t < 1.0 - 1e-14:  # hard steps shrink it: no Zeno path
            raise Diverged(
                f"the load step shrank below {opt.min_step_fraction:g} of the segment (min_step_fraction)"
                f" after {n_sub} sub-steps of {record.iterations}+ Newton iterations"
            )
        memory.length, memory.direction = h * length, direction
        if on_sub is not None and t < 1.0 - 1e-14:
            on_sub(start, t, h, n_sub, trials)
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
        start_V, h, cuts, t, record, trials = V, 1.0, 0, 0.0, None, 0
        while t < 1.0 - 1e-14:
            h = min(h, 1.0 - t)
            trials += 1
            try:
                if trials > opt.max_volume_steps:
                    raise Diverged(
                        f"{opt.max_volume_steps} volume steps (max_volume_steps) did not reach {Vt:.6g} mm^3"
                    )
                x_new, P_new, record = solver.volume_step(x, P, start_V + (t + h) * (Vt - start_V), factor)
            except Diverged as exc:
                h *= 0.5
                cuts += 1
                if cuts > opt.max_cutbacks or h < opt.min_step_fraction or trials > opt.max_volume_steps:
                    reason = f"{exc} (after {cuts - 1} cut-backs of the volume step)"
                    return failed(steps, events, solver, t0, shape.vector(P, factor), reason, volume=V)
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
        events.append(f"limit point at P ~ {mpa_to_kpa(limit):.4g} kPa")
    return PathResult(
        tuple(steps), True, "all volume targets reached", limit, tuple(events), solver.stats(t0)
    )
