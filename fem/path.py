r"""Path following: Newton's method under pressure, volume or displacement control.

Load control. The load is the pair (P, f): chamber pressure P (MPa) and the factor f that scales
the prescribed Dirichlet values and the dead loads.
Between two targets the load moves on a straight line in (P, f)
in sub-steps; each sub-step starts from the secant predictor (linear extrapolation of the last two
converged states), a sub-step whose Newton iteration diverges (stalling residual, an inverted
element, no convergence in `max_iter`) is halved, and an easy one lets the next grow again.

Newton and line search. Convergence: the force residual on the free dofs relative to the internal
force norm is below `tol`, and (mixed formulation) the pressure-constraint residual is below
`tol` x the solid volume; the two are kept apart because they have different units. Backtracking
is non-monotone: a step is accepted when its force residual is below the largest of the last
three (nearly incompressible solids overshoot before they converge). Near the solution the full
step is always taken, so the quadratic convergence of the consistent tangent is kept
(`Step.newton.residuals` shows it).

Volume control (passes limit points). The cavity volume V is prescribed and P is an unknown:

    R(x, P) = f_int(x) - P q(x) = 0,        V(x) - V* = 0,        q = dV/dx.

Each Newton step solves the bordered system with one factorisation and two right-hand sides:
K a = -R, K b = q, dP = (V* - V - q.a) / (q.b), dx = a + dP b. It stays regular at the pressure
maximum where K alone is singular.

Limit points. When pressure control cannot advance (`max_cutbacks` halvings fail), the path goes
on under volume control from the last converged state, through the remaining targets: a secant
iteration in V lands on each target pressure as the path crosses it. If the pressure peaks and
falls instead, the limit point is reported as "limit point at P ~ x kPa" (the peak refined by a
parabola through the three samples around it), and the path continues for `post_limit_steps`
volume steps. If volume control cannot advance either, the path ends with `converged=False` and
a message that names the last converged load. Nothing here raises on divergence.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from fem.errors import SolverInputError
from fem.linsolve import LinearSolver
from fem.model import InvertedElement, SolidModel


@dataclass(frozen=True, kw_only=True)
class NewtonOptions:
    tol: float = 1e-8  # relative residual ||R_free|| / ||f_int||
    max_iter: int = 20
    stall_iter: int = 8  # after this many iterations the residual must keep halving
    max_backtracks: int = 6
    max_cutbacks: int = 4  # halvings of a load sub-step before giving up
    min_step_fraction: float = 1e-3  # smallest sub-step, as a fraction of a load segment
    post_limit_steps: int = 6
    solver: str | None = None


@dataclass(frozen=True)
class NewtonRecord:
    residuals: tuple[float, ...]  # relative residual norm at each iteration
    converged: bool

    @property
    def iterations(self) -> int:
        return max(len(self.residuals) - 1, 0)


@dataclass(frozen=True)
class Step:
    """One converged equilibrium state on the path."""

    pressure: float  # MPa
    factor: float  # load factor (Dirichlet values, dead loads)
    volume: float  # cavity volume, mm^3
    x: np.ndarray = field(repr=False)  # state vector (u, and p for the mixed formulation)
    control: str  # "pressure", "volume" or "displacement"
    newton: NewtonRecord = field(repr=False)
    substeps: int = 1
    past_limit: bool = False  # a volume-controlled state after the limit point


@dataclass(frozen=True)
class SolveStats:
    iterations: int
    assembly_s: float
    solve_s: float
    wall_s: float


@dataclass(frozen=True)
class PathResult:
    steps: tuple[Step, ...]
    converged: bool  # every requested target was reached (or passed on volume control)
    message: str
    limit_pressure: float | None  # MPa, None when no limit point was met
    events: tuple[str, ...]
    stats: SolveStats

    @property
    def pressures(self) -> np.ndarray:
        return np.array([s.pressure for s in self.steps])

    @property
    def volumes(self) -> np.ndarray:
        return np.array([s.volume for s in self.steps])


class _Diverged(Exception):
    pass


class _ReportingList(list):
    """A list of steps that calls `on_step` for every appended step."""

    def __init__(self, on_step=None):
        super().__init__()
        self._on_step = on_step

    def append(self, step):
        super().append(step)
        if self._on_step is not None:
            self._on_step(step)


class _Solver:
    """Newton iterations on one model, accumulating timing statistics."""

    def __init__(self, model: SolidModel, options: NewtonOptions):
        self.model = model
        self.opt = options
        self.free = model.free_dofs
        self.assembly_s = 0.0
        self.solve_s = 0.0
        self.iterations = 0
        self.linear = LinearSolver(options.solver)
        self.free_u = self.free[self.free < model.n_u]
        self._volume = float(model.dx.sum())
        self._q0_norm = np.linalg.norm(model.pressure_load(model.initial_state()))
        self._dead_norm = np.linalg.norm(model.dead_load)

    def _assemble(self, x, P, f):
        """Residual and tangent; an inverted element makes the Newton iteration diverge."""
        t = time.perf_counter()
        try:
            return self.model.residual_and_tangent(x, P, f)
        except InvertedElement as exc:
            raise _Diverged(str(exc)) from None
        finally:
            self.assembly_s += time.perf_counter() - t

    def _residual(self, x, P, f):
        t = time.perf_counter()
        try:
            return self.model.residual(x, P, f)
        finally:
            self.assembly_s += time.perf_counter() - t

    def _solve(self, K, b):
        t = time.perf_counter()
        self.linear.factor(K)
        out = self.linear.solve(b)
        self.solve_s += time.perf_counter() - t
        self.iterations += 1
        return out

    def load_step(self, x, P, factor):
        """Equilibrium at fixed (P, factor); raises _Diverged."""
        m, free = self.model, self.free
        x = m.apply_dirichlet(x, factor)
        history = []
        for _it in range(self.opt.max_iter + 1):
            R, K = self._assemble(x, P, factor)
            merit, p_ok = self._merit(R, x, P, factor)
            history.append(merit)
            if not np.isfinite(merit):
                raise _Diverged("non-finite residual")
            if merit <= self.opt.tol and p_ok:
                return x, NewtonRecord(tuple(history), True)
            self._check_progress(history)
            dx = -self._solve(K, R[free])
            x = self._line_search(x, dx, P, factor, history)
        raise _Diverged(f"no convergence in {self.opt.max_iter} iterations")

    def _merit(self, R, x, P, f):
        """Relative force residual ||R_u(free)|| / ||f_int||, and whether the mixed-pressure
        constraint residual is below tol x the solid volume (it has units of volume)."""
        m = self.model
        fint = R[: m.n_u] + f * m.dead_load[: m.n_u]
        if m.chambers:
            fint = fint + m.pressure_force(x, P)[: m.n_u]
        scale = max(np.linalg.norm(fint), abs(P) * self._q0_norm, abs(f) * self._dead_norm, _force_floor(m))
        merit = float(np.linalg.norm(R[self.free_u]) / scale)
        p_ok = (not m.mixed) or np.linalg.norm(R[m.n_u :]) <= self.opt.tol * self._volume
        return merit, p_ok

    def _check_progress(self, history):
        """Diverged when, after `stall_iter` iterations, the best of the last three merits is not
        below half the best before them (the residual must keep shrinking)."""
        k = self.opt.stall_iter
        if len(history) > k and min(history[-3:]) > 0.5 * min(history[:-3]):
            raise _Diverged(f"residual stalls at {history[-1]:.2e} after {len(history) - 1} iterations")

    def _line_search(self, x, dx, P, f, history):
        """Non-monotone backtracking: accept a step whose merit is below the largest of the last
        three (early Newton steps of nearly incompressible solids overshoot before they converge);
        the full step is tried first, and always taken near the solution."""
        free = self.free
        reference = max(history[-3:])
        alpha = 1.0
        for k in range(self.opt.max_backtracks + 1):
            trial = x.copy()
            trial[free] += alpha * dx
            if k == 0 and history[-1] <= 1e-3:
                return trial
            try:
                merit, _ = self._merit(self._residual(trial, P, f), trial, P, f)
            except InvertedElement:
                alpha *= 0.5
                continue
            if np.isfinite(merit) and merit < reference:
                return trial
            alpha *= 0.5
        raise _Diverged("line search found no decrease")

    def volume_step(self, x, P, volume_target, factor):
        """Equilibrium at prescribed cavity volume; returns (x, P, record); raises _Diverged."""
        m, free = self.model, self.free
        x = m.apply_dirichlet(x, factor)
        history = []
        for it in range(self.opt.max_iter + 1):
            R, K = self._assemble(x, P, factor)
            q = m.pressure_load(x)
            g = m.chamber_volume(x) - volume_target
            merit, p_ok = self._merit(R, x, P, factor)
            history.append(merit)
            if not (np.isfinite(merit) and np.isfinite(g)):
                raise _Diverged("non-finite residual")
            if merit <= self.opt.tol and p_ok and abs(g) <= 1e-10 * abs(volume_target):
                return x, P, NewtonRecord(tuple(history), True)
            if it == self.opt.max_iter:
                break
            ab = self._solve(K, np.column_stack([-R[free], q[free]]))
            a, b = ab[:, 0], ab[:, 1]
            qf = q[free]
            dP = (-g - qf @ a) / (qf @ b)
            x = x.copy()
            x[free] += a + dP * b
            P = P + dP
        raise _Diverged(f"no convergence in {self.opt.max_iter} iterations (volume control)")

    def stats(self, t0):
        return SolveStats(self.iterations, self.assembly_s, self.solve_s, time.perf_counter() - t0)


def _force_floor(model):
    """A force far below any load of interest: mu * (size)^2 * 1e-14."""
    size = np.ptp(model.nodes, axis=1).max()
    return float(model.mu.max() * size * size * 1e-14)


def load_path(
    model: SolidModel,
    targets,
    *,
    options: NewtonOptions | None = None,
    control: str = "pressure",
    on_step=None,
) -> PathResult:
    """Follow the load through `targets`, a sequence of (pressure MPa, load factor) pairs.

    Starts from the undeformed state at (0, 0). See the module docstring for cut-back and limit
    point handling. `control` only labels the steps ("pressure" or "displacement"). `on_step`,
    if given, is called with every converged `Step` as it is found (progress reports).
    """
    opt = options or NewtonOptions()
    targets = [(float(P), float(f)) for P, f in targets]
    if not targets:
        raise SolverInputError("targets", "give at least one load target")
    solver = _Solver(model, opt)
    t0 = time.perf_counter()
    history = _History(model.initial_state(), (0.0, 0.0))
    steps: list[Step] = _ReportingList(on_step)
    events: list[str] = []
    for i, target in enumerate(targets):
        try:
            record, n_sub = _advance(solver, history, target, opt)
        except _Diverged as exc:
            load = history.load
            if not model.chambers or target[0] <= load[0]:
                return _failed(steps, events, solver, t0, load, str(exc))
            # Pressure control cannot advance: volume control from the last converged state,
            # through the remaining targets (module docstring).
            events.append(
                f"pressure control stalled above P = {load[0] * 1e3:.4g} kPa ({exc}); "
                "switching to volume control"
            )
            return _volume_continuation(solver, history, targets[i:], steps, events, opt, t0)
        steps.append(
            Step(target[0], target[1], model.chamber_volume(history.x), history.x, control, record, n_sub)
        )
    return PathResult(tuple(steps), True, "all load targets reached", None, tuple(events), solver.stats(t0))


class _History:
    """The last two converged states on the path: the secant predictor extrapolates from them."""

    def __init__(self, x, load, volume=None):
        self.x, self.load, self.volume = x, load, volume
        self.x_prev, self.load_prev, self.volume_prev = None, None, None

    def accept(self, x, load, volume=None):
        self.x_prev, self.load_prev, self.volume_prev = self.x, self.load, self.volume
        self.x, self.load, self.volume = x, load, volume

    def predict(self, load=None, volume=None):
        """Linear extrapolation of the state to a new load (or volume) from the last two states."""
        if self.x_prev is None:
            return self.x
        if volume is not None:
            span, ahead = self.volume - self.volume_prev, volume - self.volume
        else:
            d = np.subtract(self.load, self.load_prev)
            span = float(np.hypot(*d))
            ahead = float(np.dot(np.subtract(load, self.load), d) / span) if span > 0 else 0.0
        if span == 0 or not np.isfinite(ahead / span) or ahead / span > 2.0:
            return self.x
        return self.x + (self.x - self.x_prev) * (ahead / span)


def _advance(solver, history, end, opt):
    """From the last converged load to `end` in adaptive sub-steps, each started from the
    secant prediction; returns (last Newton record, number of sub-steps)."""
    start = history.load
    t, h, n_sub, cuts = 0.0, 1.0, 0, 0
    record = None
    while t < 1.0 - 1e-14:
        h = min(h, 1.0 - t)
        s = t + h
        load = (start[0] + s * (end[0] - start[0]), start[1] + s * (end[1] - start[1]))
        try:
            x_new, record = solver.load_step(history.predict(load), *load)
        except _Diverged:
            h *= 0.5
            cuts += 1
            if cuts > opt.max_cutbacks or h < opt.min_step_fraction:
                raise
            continue
        history.accept(x_new, load)
        solver.model.commit(x_new)
        t = s
        n_sub += 1
        if record.iterations <= 6:
            h *= 2.0
    if record is None:  # zero-length segment
        x_new, record = solver.load_step(history.x, *end)
        history.accept(x_new, end)
        solver.model.commit(x_new)
    return record, n_sub


def _volume_continuation(solver, history, remaining, steps, events, opt, t0):
    """Volume control from a stalled pressure-controlled state through the remaining targets.

    Volume steps adapt to the Newton effort. When the pressure crosses the next target, a secant
    iteration in V lands on it, and that state is recorded as the target's step (control
    "volume", `past_limit` False: it is the equilibrium at that target). If the pressure peaks and
    falls, the peak is the limit point; the path goes on for
    `post_limit_steps` volume steps and ends (targets above the peak are unreachable).
    """
    m = solver.model
    f = history.load[1]
    P = history.load[0]
    V = m.chamber_volume(history.x)
    V_prev = m.chamber_volume(history.x_prev) if history.x_prev is not None else V * 0.99
    vh = _History(history.x, (P, f), V)
    vh.x_prev, vh.load_prev, vh.volume_prev = history.x_prev, history.load_prev, V_prev
    dV = max(0.5 * abs(V - V_prev), 1e-3 * abs(V))  # floor: round-off in P must not look like a peak
    pending = [t[0] for t in remaining]
    samples = [(V, P)]
    peak, after_peak, cuts = None, 0, 0

    def solve_at(volume):
        return solver.volume_step(vh.predict(volume=volume), vh.load[0], volume, f)

    while pending:
        try:
            x_new, P_new, record = solve_at(vh.volume + dV)
        except _Diverged as exc:
            dV *= 0.5
            cuts += 1
            if cuts > opt.max_cutbacks:
                return _end_of_volume_path(solver, vh, steps, events, t0, peak, str(exc))
            continue
        cuts = 0
        V_new = vh.volume + dV
        target = pending[0]
        if P_new >= target > vh.load[0] and peak is None:
            # secant in V onto P = target, between the bracketing states
            lo, hi = (vh.volume, vh.load[0]), (V_new, P_new)
            x_hit, P_hit, rec_hit, V_hit = x_new, P_new, record, V_new
            for _ in range(4):
                Vs = lo[0] + (target - lo[1]) * (hi[0] - lo[0]) / (hi[1] - lo[1])
                try:
                    x_hit, P_hit, rec_hit = solve_at(Vs)
                except _Diverged:
                    break
                V_hit = Vs
                if abs(P_hit - target) <= 1e-5 * abs(target):
                    break
                lo, hi = ((Vs, P_hit), hi) if P_hit < target else (lo, (Vs, P_hit))
            vh.accept(x_hit, (P_hit, f), V_hit)
            m.commit(x_hit)
            steps.append(Step(P_hit, f, V_hit, x_hit, "volume", rec_hit))
            samples.append((V_hit, P_hit))
            pending.pop(0)
            continue
        vh.accept(x_new, (P_new, f), V_new)
        m.commit(x_new)
        samples.append((V_new, P_new))
        if (
            peak is None
            and len(samples) >= 3
            and samples[-1][1] < samples[-2][1] - 1e-6 * abs(samples[-2][1])
        ):
            peak = _parabola_peak(samples[-3:])
            events.append(f"limit point at P ~ {peak * 1e3:.4g} kPa (volume control continues)")
        if peak is not None:
            steps.append(Step(P_new, f, V_new, x_new, "volume", record, past_limit=True))
            after_peak += 1
            if after_peak >= opt.post_limit_steps:
                break
        if record.iterations <= 5:
            dV *= 1.5
    if peak is not None:
        msg = f"limit point at P ~ {peak * 1e3:.4g} kPa"
        return PathResult(tuple(steps), True, msg, peak, tuple(events), solver.stats(t0))
    return PathResult(
        tuple(steps),
        True,
        "all load targets reached (the last ones on volume control)",
        None,
        tuple(events),
        solver.stats(t0),
    )


def _end_of_volume_path(solver, vh, steps, events, t0, peak, reason):
    if peak is not None:
        events.append(f"volume control stopped after the limit point ({reason})")
        return PathResult(
            tuple(steps),
            True,
            f"limit point at P ~ {peak * 1e3:.4g} kPa",
            peak,
            tuple(events),
            solver.stats(t0),
        )
    return _failed(
        steps, events, solver, t0, vh.load, f"volume control could not advance ({reason})", volume=vh.volume
    )


def _parabola_peak(samples):
    (v0, p0), (v1, p1), (v2, p2) = samples
    A = np.array([[v0 * v0, v0, 1.0], [v1 * v1, v1, 1.0], [v2 * v2, v2, 1.0]])
    a, b, c = np.linalg.solve(A, [p0, p1, p2])
    if a >= 0:
        return max(p0, p1, p2)
    v = -b / (2 * a)
    return float(min(max(a * v * v + b * v + c, max(p0, p1, p2)), 1.5 * max(p0, p1, p2)))


def volume_path(
    model: SolidModel, volumes, *, factor: float = 0.0, options: NewtonOptions | None = None
) -> PathResult:
    """Prescribe the cavity volume through `volumes` (mm^3); the pressure is an unknown."""
    opt = options or NewtonOptions()
    if not model.chambers:
        raise SolverInputError("chamber", "volume control needs a chamber surface")
    solver = _Solver(model, opt)
    t0 = time.perf_counter()
    x = model.apply_dirichlet(model.initial_state(), factor)
    P = 0.0
    V = model.chamber_volume(x)
    steps: list[Step] = []
    events: list[str] = []
    best = None
    for Vt in volumes:
        start_V, h, cuts = V, 1.0, 0
        t = 0.0
        record = None
        while t < 1.0 - 1e-14:
            h = min(h, 1.0 - t)
            try:
                x_new, P_new, record = solver.volume_step(x, P, start_V + (t + h) * (Vt - start_V), factor)
            except _Diverged as exc:
                h *= 0.5
                cuts += 1
                if cuts > opt.max_cutbacks:
                    return _failed(steps, events, solver, t0, (P, factor), str(exc), volume=V)
                continue
            x, P, t = x_new, P_new, t + h
            model.commit(x)
            V = start_V + t * (Vt - start_V)
        steps.append(Step(P, factor, V, x, "volume", record))
        if best is None or P > best:
            best = P
    limit = None
    ps = [s.pressure for s in steps]
    k = int(np.argmax(ps))
    if 0 < k < len(ps) - 1:
        limit = _parabola_peak([(steps[j].volume, steps[j].pressure) for j in (k - 1, k, k + 1)])
        events.append(f"limit point at P ~ {limit * 1e3:.4g} kPa")
    return PathResult(
        tuple(steps), True, "all volume targets reached", limit, tuple(events), solver.stats(t0)
    )


def _failed(steps, events, solver, t0, load, reason, volume=None):
    P, f = load
    where = f"P = {P * 1e3:.4g} kPa, load factor {f:.4g}"
    if volume is not None:
        where += f", chamber volume {volume:.6g} mm^3"
    msg = f"diverged after the last converged load ({where}): {reason}"
    events.append(msg)
    return PathResult(tuple(steps), False, msg, None, tuple(events), solver.stats(t0))
