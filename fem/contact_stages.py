r"""Staged loading of a model with contact terms, with an augmented-Lagrangian loop and cut-back.

A stage moves, over a pseudo-time s in [0, 1], the chamber pressures P and the load factor f
(prescribed displacements, dead loads) linearly from where the last stage ended to its own end
values, and may move the rigid surfaces (`surfaces`: contact index -> callable s -> surface,
e.g. a pipe wall shrinking from clear of an oversized foot to its radius) and set the friction
coefficients at its start (`friction`: contact index -> mu; stick points restart there), and
may drive other terms along s (`drive(s)`, called before each sub-step's solve, e.g. the preload
and stiffness of an actuator's `fem.axial_link.AxialLink`, set as functions of s). A stage may
span a `duration` of physical time: each sub-step then tells the terms with a time step its own,
(s - t) times the duration, which viscous slip (`fem.contact_law`) and inertia (`fem.inertia`,
whose body starts at rest at x0) read; a cut-back shortens it. The staged insertion of a foot into
a pipe is three stages: shrink the wall frictionless, switch friction on, drag by prescribed
displacement.

Each sub-step is a Newton solve (`fem.newton`) from the last converged state. A diverged
sub-step is halved (up to `max_cutbacks` times in a row), with the contact history restored; an
easy one (<= 6 iterations) lets the next grow back, up to the stage's own step 1 / `steps` (so
that a drag records at least `steps` points of its curve). After a converged sub-step, the
augmented-Lagrangian (Uzawa) loop updates the multipliers lambda <- p_N and solves again at the
same load until the largest penetration is below `penetration_tol` (mm) or `max_augment`
updates were made (the last update, which no solve follows, is undone: the state keeps the
multipliers it is in equilibrium with); then the friction history is committed once
(`SolidModel.commit`). The
history never changes inside a Newton iteration. Within a stage, each sub-step starts from the
secant prediction of the last two converged states (linear in the pseudo-time), which puts a
drag increment near its slip solution.

Resuming. After each converged sub-step `on_cursor` (if given) receives a `Cursor`: where the
run stands (stage index, pseudo-time t, the next sub-step h, the secant predictor's previous
(t, x), the stage's start load and the current load) and the solver's effort so far. A caller
that stores it with the model's history (each contact term's multipliers, stick points, surface
and friction coefficient, and its own terms' loads; `studies.crawl.resume`) continues with
``run_stages(..., start=cursor)``: the stages before ``cursor.stage`` are skipped, the stage
``cursor.stage`` goes on from t with h and the predictor's history, and its friction
coefficients are not set again (`ContactTerm.set_friction` resets the stick points). A cursor
at the end of a stage (t = 1) resumes at the next stage, whose friction is set as usual.

Nothing raises on divergence: the result says `converged = False` and names the last converged
stage and pseudo-time. Two guards end a stage that grinds in ever smaller sub-steps (a limit
point or a jammed contact: cut-backs alternate with tiny converged sub-steps, so `max_cutbacks`
in a row is never reached): a sub-step below `min_step_fraction` of the stage's own step, and the
wall-time budget `max_wall_s`, checked before every solve attempt (each failed attempt costs up
to `NewtonOptions.max_iter` iterations). Both are off by default.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import numpy as np

from softcrawl.fem.errors import SolverInputError
from softcrawl.fem.newton import Diverged, NewtonOptions, NewtonSolver

#: Halvings of a Uzawa update whose re-solve diverged before the loop keeps the last solve.
MAX_RELAXATIONS = 2


@dataclass(frozen=True)
class Stage:
    name: str
    pressure: object = None  # end pressure(s), MPa; None keeps the last
    factor: float | None = None  # end load factor; None keeps the last
    surfaces: Mapping[int, Callable] = field(default_factory=dict)
    friction: Mapping[int, float] = field(default_factory=dict)
    steps: int = 1  # initial number of sub-steps
    drive: Callable[[float], None] | None = None  # called with s before each sub-step's solve
    duration: float | None = None  # s of physical time the stage spans (viscous slip); None: pseudo-time

    def __post_init__(self):
        if int(self.steps) < 1:
            raise SolverInputError("stage.steps", f"{self.name}: needs at least one sub-step")
        if self.duration is not None and not (np.isfinite(self.duration) and self.duration > 0):
            raise SolverInputError(
                "stage.duration", f"{self.name}: a time > 0 in s or None, not {self.duration!r}"
            )


@dataclass(frozen=True)
class StagedStep:
    stage: str
    s: float  # pseudo-time in the stage
    pressure: np.ndarray
    factor: float
    x: np.ndarray = field(repr=False)
    iterations: tuple[int, ...]  # Newton iterations of each solve (first, then AL re-solves)
    residuals: tuple[float, ...]  # relative residuals of the first solve (convergence order)
    penetration: float  # largest penetration after the last solve (mm)


@dataclass(frozen=True)
class Cursor:
    """Where `run_stages` stands after a converged sub-step (module docstring, "Resuming")."""

    stage: int  # index in the stages
    t: float  # pseudo-time reached in that stage
    h: float  # the next sub-step
    x: np.ndarray = field(repr=False)
    prev_t: float | None  # the secant predictor's previous converged state in this stage
    prev_x: np.ndarray | None = field(repr=False)
    P0: np.ndarray  # the stage's start pressure and factor
    f0: float
    P: np.ndarray  # the current pressure and factor
    f: float
    newton_iterations: int  # this call's so far
    assembly_s: float
    solve_s: float
    factorizations: int = 0  # this call's so far (of the tangent or its symmetric part)


@dataclass(frozen=True)
class StagedResult:
    steps: tuple[StagedStep, ...]
    converged: bool
    message: str
    wall_s: float
    newton_iterations: int
    assembly_s: float
    solve_s: float
    end_x: np.ndarray | None = field(default=None, repr=False)  # the last state (a resumed call
    # at the end of its stages has no step)
    factorizations: int = 0  # of the tangent (or its symmetric part), this call's

    @property
    def x(self) -> np.ndarray:
        return self.steps[-1].x if self.steps else self.end_x


def _snapshot(model):
    return [(c.multiplier.copy(), c.stick.copy(), c.surface) for c in model.contacts]


def _restore(model, snap) -> None:
    for c, (lam, stick, surface) in zip(model.contacts, snap):
        c.multiplier, c.stick, c.surface = lam, stick, surface


def _multipliers(model):
    return [c.multiplier.copy() for c in model.contacts]


def _set_multipliers(model, values) -> None:
    for c, lam in zip(model.contacts, values):
        c.multiplier = lam


def _solve_augmented(solver, model, x, P, f, tol, max_augment):
    """Newton at (P, f), then Uzawa updates until the penetration is below tol; returns
    (x, iterations per solve, residuals of the first solve, last penetration). Raises Diverged
    when the first solve diverges.

    The state returned is in equilibrium with the multipliers of its own solve: an update that
    is not followed by a solve (the loop stops) is undone, so that the contact forces reported
    at x (and the history committed from them) are the ones the residual balanced.

    Relaxed updates. A re-solve after an update lambda <- lambda + w (p_N - lambda) that
    diverges is undone and retried with w halved (at most MAX_RELAXATIONS times in a
    row); after that the loop stops at the last converged solve, an equilibrium of the penalty
    problem with its own multipliers whose penetration (above tol) is returned and reported.
    Before, such a failure threw away the converged first solve and cut the load step back: in
    the foot's backward drag most cut-backs came from here (the update moves p_N, hence the
    Coulomb limit mu p_N, at every point at once; docs/decisions/037-coulomb-cone.md)."""
    x, record = solver.load_step(x, P, f)
    iterations, residuals = [record.iterations], record.residuals
    relax, failures, updates = 1.0, 0, 0
    while True:
        solved = _multipliers(model)
        penetration = max((c.augment(x, relax) for c in model.contacts), default=0.0)
        if penetration <= tol or updates == max_augment or failures > MAX_RELAXATIONS:
            _set_multipliers(model, solved)
            model.commit(x)
            return x, tuple(iterations), residuals, penetration
        try:
            x, record = solver.load_step(x, P, f)
        except Diverged:
            _set_multipliers(model, solved)
            relax, failures = 0.5 * relax, failures + 1
            continue
        iterations.append(record.iterations)
        updates, failures = updates + 1, 0


def run_stages(
    model,
    stages,
    *,
    x0: np.ndarray | None = None,
    factor0: float = 0.0,
    options: NewtonOptions | None = None,
    penetration_tol: float = 1e-3,
    max_augment: int = 4,
    max_cutbacks: int = 6,
    on_step: Callable[[StagedStep], None] | None = None,
    max_wall_s: float | None = None,
    min_step_fraction: float | None = None,
    start: Cursor | None = None,
    on_cursor: Callable[[Cursor], None] | None = None,
) -> StagedResult:
    """Follow `stages` from x0 (default: undeformed) at zero pressure and load factor `factor0`
    (the factor x0 is in equilibrium with: 1 for a body already under its weight), or from
    `start` (module docstring, "Resuming"; x0 is then ignored); give up (not converged) once
    `max_wall_s` seconds have passed or a sub-step would be smaller than `min_step_fraction` /
    `stage.steps` (None: no limit)."""
    if penetration_tol <= 0:
        raise SolverInputError("penetration_tol", "must be positive (mm)")
    if max_wall_s is not None and not max_wall_s > 0:
        raise SolverInputError("max_wall_s", f"must be a positive time in s or None, got {max_wall_s!r}")
    if min_step_fraction is not None and not 0 < min_step_fraction < 1:
        raise SolverInputError("min_step_fraction", f"must be in (0, 1) or None, got {min_step_fraction!r}")
    opt = options or NewtonOptions()
    solver = NewtonSolver(model, opt)
    t0 = time.perf_counter()
    x = model.initial_state() if x0 is None else x0.copy()
    P = np.zeros(max(len(model.chambers), 1))
    f = float(factor0)
    if start is not None:
        if not 0 <= start.stage < len(stages):
            raise SolverInputError("start", f"stage {start.stage} of a run of {len(stages)} stages")
        x, P, f = start.x.copy(), np.array(start.P, dtype=float), float(start.f)
    timed = [t for t in getattr(model, "terms", model.contacts) if hasattr(t, "set_time_step")]
    if start is None:  # a run starts at rest (inertia; a resumed one has its history restored)
        for term in timed:
            if hasattr(term, "rest"):
                term.rest(x)
    out: list[StagedStep] = []

    def result(ok, message):
        return StagedResult(
            tuple(out),
            ok,
            message,
            time.perf_counter() - t0,
            solver.iterations,
            solver.assembly_s,
            solver.linear.seconds,
            x,
            solver.linear.factorizations,
        )

    last = "the start" if start is None else f"stage {stages[start.stage].name!r} at s = {start.t:.4g}"
    for index, stage in enumerate(stages):
        if start is not None and index < start.stage:
            continue
        resumed = start is not None and index == start.stage
        P0, f0 = (np.array(start.P0, dtype=float), float(start.f0)) if resumed else (P.copy(), f)
        P1 = (
            P0
            if stage.pressure is None
            else np.broadcast_to(np.asarray(stage.pressure, float), P0.shape).copy()
        )
        f1 = f0 if stage.factor is None else float(stage.factor)
        if resumed:  # friction was set when the stage began: set_friction would reset the stick points
            t, h, cuts = float(start.t), float(start.h), 0
            prev = None if start.prev_x is None else (float(start.prev_t), start.prev_x.copy())
        else:
            for i, mu in stage.friction.items():
                model.contacts[i].set_friction(mu, x)
            t, h, cuts = 0.0, 1.0 / stage.steps, 0
            prev = None  # (t, x) of the converged state before the last one in this stage
        while t < 1.0 - 1e-12:
            h = min(h, 1.0 - t)
            s = t + h
            if s <= t:  # h below the resolution of t: the stage can no longer advance
                return result(
                    False,
                    f"stage {stage.name!r} stopped: its sub-steps ({h:.3g}) fell below the floating-point "
                    f"resolution of the stage parameter at s = {t:.6g}; last converged: {last}",
                )
            if max_wall_s is not None and time.perf_counter() - t0 > max_wall_s:
                return result(
                    False,
                    f"stage {stage.name!r} stopped at the wall-time budget max_wall_s = {max_wall_s:g} s "
                    f"(trying s = {s:.4g} in sub-steps of {h:.3g}); last converged: {last}",
                )
            snap = _snapshot(model)
            for i, surface_at in stage.surfaces.items():
                model.contacts[i].set_surface(surface_at(s))
            if stage.drive is not None:
                stage.drive(s)
            for term in timed:  # viscous slip, inertia: the sub-step's time (None: pseudo-time)
                term.set_time_step(None if stage.duration is None else (s - t) * stage.duration)
            Ps, fs = P0 + s * (P1 - P0), f0 + s * (f1 - f0)
            guess = x if prev is None else x + (x - prev[1]) * (h / (t - prev[0]))
            try:
                x_new, its, rs, pen = _solve_augmented(
                    solver, model, guess, Ps, fs, penetration_tol, max_augment
                )
            except Diverged as exc:
                _restore(model, snap)
                h *= 0.5
                cuts += 1
                if cuts > max_cutbacks:
                    return result(False, f"stage {stage.name!r} diverged ({exc}); last converged: {last}")
                if min_step_fraction is not None and h < min_step_fraction / stage.steps:
                    return result(
                        False,
                        f"stage {stage.name!r} diverged ({exc}) with sub-steps below min_step_fraction = "
                        f"{min_step_fraction:g} of its step; last converged: {last}",
                    )
                continue
            prev = (t, x)
            x, t, P, f, cuts = x_new, s, Ps, fs, 0
            step = StagedStep(stage.name, s, P.copy(), f, x.copy(), its, tuple(rs), pen)
            out.append(step)
            last = f"stage {stage.name!r} at s = {s:.4g}"
            if on_step is not None:
                on_step(step)
            if its[0] <= 6:
                h = min(2.0 * h, 1.0 / stage.steps)  # never past the stage's own step (curves)
            if on_cursor is not None:
                lin = solver.linear
                work = (solver.iterations, solver.assembly_s, lin.seconds, lin.factorizations)
                on_cursor(Cursor(index, t, h, x, prev[0], prev[1], P0, f0, P.copy(), f, *work))
    return result(True, "all stages reached")
