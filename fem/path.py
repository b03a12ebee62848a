r"""Path following: Newton's method under pressure, volume or displacement control.

Load control. The load is the pair (P, f): chamber pressure P (MPa) and the factor f that scales
the prescribed Dirichlet values. Between two targets the load moves on a straight line in (P, f)
in sub-steps; a sub-step whose Newton iteration diverges (residual growth, an inverted element,
no convergence in `max_iter`) is halved, and a successful easy one lets the next grow again.

Line search. A Newton correction that does not reduce the residual norm is halved (backtracking)
up to `max_backtracks` times. Near the solution the full step is always taken, so the quadratic
convergence of the consistent tangent is kept (`Step.newton.residuals` shows it).

Volume control (passes limit points). The cavity volume V is prescribed and P is an unknown:

    R(x, P) = f_int(x) - P q(x) = 0,        V(x) - V* = 0,        q = dV/dx.

Each Newton step solves the bordered system with one factorisation and two right-hand sides:
K a = -R, K b = q, dP = (V* - V - q.a) / (q.b), dx = a + dP b. It stays regular at the pressure
maximum where K alone is singular.

Limit points. When pressure control cannot advance (the step is cut below `min_step_fraction`),
the path switches to volume control from the last converged state. If the pressure then rises past
the next target, pressure control resumes (a snap-through was passed); if it peaks and falls, a
limit point is reported as "limit point at P ~ x kPa" (the peak is refined by a parabola through
the three samples around it), and the path continues for `post_limit_steps` volume steps. If volume
control cannot advance either, the path ends with `converged=False` and a message that names the
last converged load. Nothing here raises on divergence.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from fem.errors import SolverInputError
from fem.linsolve import LinearSolver
from fem.mechanics import InvertedElement, SolidModel


@dataclass(frozen=True, kw_only=True)
class NewtonOptions:
    tol: float = 1e-8                 # relative residual ||R_free|| / ||f_int||
    max_iter: int = 20
    stall_iter: int = 8               # after this many iterations the residual must keep halving
    max_backtracks: int = 6
    max_cutbacks: int = 6             # halvings of a load sub-step before giving up
    min_step_fraction: float = 1e-3   # smallest sub-step, as a fraction of a load segment
    post_limit_steps: int = 6
    max_control_switches: int = 4     # pressure -> volume control hand-overs in one path
    solver: str | None = None


@dataclass(frozen=True)
class NewtonRecord:
    residuals: tuple[float, ...]      # relative residual norm at each iteration
    converged: bool

    @property
    def iterations(self) -> int:
        return max(len(self.residuals) - 1, 0)


@dataclass(frozen=True)
class Step:
    """One converged equilibrium state on the path."""

    pressure: float                   # MPa
    factor: float                     # Dirichlet factor
    volume: float                     # cavity volume, mm^3
    x: np.ndarray = field(repr=False) # state vector (u, and p for the mixed formulation)
    control: str                      # "pressure", "volume" or "displacement"
    newton: NewtonRecord = field(repr=False)
    substeps: int = 1


@dataclass(frozen=True)
class SolveStats:
    iterations: int
    assembly_s: float
    solve_s: float
    wall_s: float


@dataclass(frozen=True)
class PathResult:
    steps: tuple[Step, ...]
    converged: bool                   # every requested target was reached (or passed on volume control)
    message: str
    limit_pressure: float | None      # MPa, None when no limit point was met
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
        self._q0_norm = np.linalg.norm(model.pressure_load(model.initial_state()))

    def _assemble(self, x, P):
        t = time.perf_counter()
        try:
            R, K = self.model.residual_and_tangent(x, P)
        finally:
            self.assembly_s += time.perf_counter() - t
        return R, K

    def _residual(self, x, P):
        t = time.perf_counter()
        try:
            return self.model.residual(x, P)
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
        rf_prev = np.inf
        for it in range(self.opt.max_iter + 1):
            try:
                R, K = self._assemble(x, P)
            except InvertedElement as exc:
                raise _Diverged(str(exc))
            rf = np.linalg.norm(R[free])
            scale = self._scale(R, x, P)
            history.append(rf / scale)
            if not np.isfinite(rf):
                raise _Diverged("non-finite residual")
            if rf <= self.opt.tol * scale:
                return x, NewtonRecord(tuple(history), True)
            if it >= self.opt.stall_iter and rf > 0.5 * rf_prev:
                raise _Diverged(f"residual stalls at {rf / scale:.2e} after {it} iterations")
            rf_prev = min(rf_prev, rf) if it else rf
            dx = -self._solve(K, R[free])
            x = self._line_search(x, dx, P, rf, scale)
        raise _Diverged(f"no convergence in {self.opt.max_iter} iterations")

    def _scale(self, R, x, P):
        """Force scale of the relative residual: ||f_int|| over all dofs (load plus reactions)."""
        fint = R + P * self.model.pressure_load(x) if self.model.chamber else R
        return max(np.linalg.norm(fint), abs(P) * self._q0_norm, _force_floor(self.model))

    def _line_search(self, x, dx, P, rf, scale):
        """Backtracking on ||R_free|| with residual-only evaluations; the full step is tried first."""
        free = self.free
        alpha = 1.0
        for k in range(self.opt.max_backtracks + 1):
            trial = x.copy()
            trial[free] += alpha * dx
            if k == 0 and rf <= 1e-3 * scale:
                return trial          # near the solution: plain Newton (quadratic convergence)
            try:
                new = np.linalg.norm(self._residual(trial, P)[free])
            except InvertedElement:
                alpha *= 0.5
                continue
            if np.isfinite(new) and new < rf:
                return trial
            alpha *= 0.5
        raise _Diverged("line search found no decrease")

    def volume_step(self, x, P, volume_target, factor):
        """Equilibrium at prescribed cavity volume; returns (x, P, record); raises _Diverged."""
        m, free = self.model, self.free
        x = m.apply_dirichlet(x, factor)
        history = []
        for it in range(self.opt.max_iter + 1):
            try:
                R, K = self._assemble(x, P)
            except InvertedElement as exc:
                raise _Diverged(str(exc))
            q = m.pressure_load(x)
            g = m.chamber_volume(x) - volume_target
            rf = np.linalg.norm(R[free])
            scale = self._scale(R, x, P)
            history.append(rf / scale)
            if not (np.isfinite(rf) and np.isfinite(g)):
                raise _Diverged("non-finite residual")
            if rf <= self.opt.tol * scale and abs(g) <= 1e-10 * abs(volume_target):
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


def load_path(model: SolidModel, targets, *, options: NewtonOptions | None = None,
              control: str = "pressure", on_step=None) -> PathResult:
    """Follow the load through `targets`, a sequence of (pressure MPa, Dirichlet factor) pairs.

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
    x = model.initial_state()
    load = (0.0, 0.0)
    steps: list[Step] = _ReportingList(on_step)
    events: list[str] = []
    h_min = opt.min_step_fraction
    switches = 0
    i = 0
    while i < len(targets):
        target = targets[i]
        try:
            x, record, n_sub = _advance(solver, x, load, target, opt, h_min)
        except _Diverged as exc:
            # Pressure control cannot advance: try volume control from the last converged state.
            if not model.chamber or switches >= opt.max_control_switches:
                return _failed(steps, events, solver, t0, load, str(exc))
            switches += 1
            events.append(f"pressure control stalled above P = {load[0] * 1e3:.4g} kPa ({exc}); "
                          "switching to volume control")
            outcome = _volume_continuation(solver, x, load, targets[i:], steps, events, opt)
            if outcome is None:
                return _failed(steps, events, solver, t0, load, "volume control could not advance")
            x, load, i, limit = outcome
            if limit is not None:
                msg = f"limit point at P ~ {limit * 1e3:.4g} kPa"
                return PathResult(tuple(steps), True, msg, limit, tuple(events), solver.stats(t0))
            continue
        load = target
        steps.append(Step(load[0], load[1], model.chamber_volume(x), x, control, record, n_sub))
        i += 1
    return PathResult(tuple(steps), True, "all load targets reached", None, tuple(events), solver.stats(t0))


def _advance(solver, x, start, end, opt, h_min):
    """From load `start` to `end` in adaptive sub-steps; returns (x, last record, n_substeps)."""
    t, h, n_sub = 0.0, 1.0, 0
    cuts = 0
    record = None
    while t < 1.0 - 1e-14:
        h = min(h, 1.0 - t)
        s = t + h
        P = start[0] + s * (end[0] - start[0])
        f = start[1] + s * (end[1] - start[1])
        try:
            x_new, record = solver.load_step(x, P, f)
        except _Diverged:
            h *= 0.5
            cuts += 1
            if cuts > opt.max_cutbacks or h < h_min:
                raise
            continue
        x, t = x_new, s
        n_sub += 1
        if record.iterations <= 6:
            h *= 2.0
    if record is None:  # zero-length step
        x, record = solver.load_step(x, end[0], end[1])
    return x, record, n_sub


def _volume_continuation(solver, x, load, remaining, steps, events, opt):
    """Volume control from a stalled pressure-controlled state (see module docstring).

    Returns (x, load, index into `remaining` offset, limit pressure or None), or None on failure.
    """
    m = solver.model
    P, f = load
    V = m.chamber_volume(x)
    prev_V = steps[-1].volume if steps else m.chamber_volume(m.initial_state())
    if len(steps) >= 2:
        prev_V = steps[-2].volume if steps[-1].volume == V else steps[-1].volume
    dV = max(abs(V - prev_V) * 0.25, 1e-3 * abs(V))
    samples = [(V, P)]
    next_target = remaining[0][0]
    n_after_peak = 0
    peak = None
    cuts = 0
    while True:
        try:
            x_new, P_new, record = solver.volume_step(x, P, V + dV, f)
        except _Diverged:
            dV *= 0.5
            cuts += 1
            if cuts > opt.max_cutbacks:
                if peak is not None:
                    events.append(f"volume control stopped after the limit point: {peak * 1e3:.4g} kPa")
                    return x, (P, f), 0, peak
                return None
            continue
        x, P, V = x_new, P_new, V + dV
        samples.append((V, P))
        steps.append(Step(P, f, V, x, "volume", record))
        if P >= next_target and peak is None:
            events.append(f"pressure passed {next_target * 1e3:.4g} kPa on volume control; "
                          "back to pressure control")
            # Step back onto pressure control at the next target from here.
            steps.pop()
            return x, (P, f), 0, None
        if peak is None and len(samples) >= 3 and samples[-1][1] < samples[-2][1]:
            peak = _parabola_peak(samples[-3:])
            events.append(f"limit point at P ~ {peak * 1e3:.4g} kPa (volume control continues)")
        if peak is not None:
            n_after_peak += 1
            if n_after_peak >= opt.post_limit_steps:
                return x, (P, f), 0, peak
        if record.iterations <= 5:
            dV *= 1.5


def _parabola_peak(samples):
    (v0, p0), (v1, p1), (v2, p2) = samples
    A = np.array([[v0 * v0, v0, 1.0], [v1 * v1, v1, 1.0], [v2 * v2, v2, 1.0]])
    a, b, c = np.linalg.solve(A, [p0, p1, p2])
    if a >= 0:
        return max(p0, p1, p2)
    v = -b / (2 * a)
    return float(min(max(a * v * v + b * v + c, max(p0, p1, p2)), 1.5 * max(p0, p1, p2)))


def volume_path(model: SolidModel, volumes, *, factor: float = 0.0,
                options: NewtonOptions | None = None) -> PathResult:
    """Prescribe the cavity volume through `volumes` (mm^3); the pressure is an unknown."""
    opt = options or NewtonOptions()
    if not model.chamber:
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
    return PathResult(tuple(steps), True, "all volume targets reached", limit, tuple(events),
                      solver.stats(t0))


def _failed(steps, events, solver, t0, load, reason, volume=None):
    P, f = load
    where = f"P = {P * 1e3:.4g} kPa, Dirichlet factor {f:.4g}"
    if volume is not None:
        where += f", chamber volume {volume:.6g} mm^3"
    msg = f"diverged after the last converged load ({where}): {reason}"
    events.append(msg)
    return PathResult(tuple(steps), False, msg, None, tuple(events), solver.stats(t0))
