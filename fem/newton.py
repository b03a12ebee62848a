r"""Newton's method on a `fem.model.SolidModel` at a fixed load or at a prescribed chamber volume.

Load. P is one pressure per chamber (MPa; a scalar applies to every chamber) and f the factor of
the prescribed displacements and dead loads.

Convergence. The force residual on the free displacement dofs relative to the force scale
(the internal force, the pressure and dead loads at the reference state, a floor far below any
load of interest) is below `tol`, and, for the mixed formulation, the pressure-constraint residual
is below `tol` x the solid volume; the two are kept apart because they have different units.

Line search. Backtracking is non-monotone: a step is accepted when its force residual is below
the largest of the last three (nearly incompressible solids overshoot before they converge). Near
the solution the full step is always taken, so the quadratic convergence of the consistent
tangent is kept (`NewtonRecord.residuals` shows it).

Volume control (passes limit points). The pressures move along a direction d, P = P0 + lambda d
(d_k = 1 for the driving chamber k, so lambda is the change of its pressure), and the volume of
chamber k is prescribed; lambda is an unknown:

    R(x, lambda) = f_int(x) - sum_i (P0_i + lambda d_i) q_i(x) - f f_dead = 0,   V_k(x) - V* = 0.

Each Newton step solves the bordered system with one factorisation and two right-hand sides,
K a = -R, K b = q_d (q_d = sum_i d_i q_i = -dR/dlambda), dlambda = (V* - V_k - q_k.a) / (q_k.b),
dx = a + dlambda b. It stays regular at the pressure maximum where K alone is singular. With one
chamber, d = 1 and lambda is the pressure itself.

A diverged iteration raises `Diverged` (stalling residual, a non-finite residual, an inverted
element, no convergence in `max_iter`); the path (`fem.path`) cuts the step back.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

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
class SolveStats:
    iterations: int
    assembly_s: float
    solve_s: float
    wall_s: float


class Diverged(Exception):
    """A Newton iteration that cannot converge from its start; the caller cuts back."""


def force_floor(model: SolidModel) -> float:
    """A force far below any load of interest: mu * (size)^2 * 1e-14."""
    size = np.ptp(model.nodes, axis=1).max()
    return float(model.mu.max() * size * size * 1e-14)


class NewtonSolver:
    """Newton iterations on one model, accumulating timing statistics."""

    def __init__(self, model: SolidModel, options: NewtonOptions) -> None:
        self.model = model
        self.opt = options
        self.free = model.free_dofs
        self.assembly_s = 0.0
        self.solve_s = 0.0
        self.iterations = 0
        self.linear = LinearSolver(options.solver)
        self.free_u = self.free[self.free < model.n_u]
        self._volume = float(model.dx.sum())
        x0 = model.initial_state()
        self._q0 = [model.pressure_load(x0, i)[: model.n_u] for i in range(len(model.chambers))]
        self._dead_norm = np.linalg.norm(model.dead_load)
        self._floor = force_floor(model)

    def _assemble(self, x, P, f):
        """Residual and tangent; an inverted element makes the Newton iteration diverge."""
        t = time.perf_counter()
        try:
            return self.model.residual_and_tangent(x, P, f)
        except InvertedElement as exc:
            raise Diverged(str(exc)) from None
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
        """Equilibrium at fixed (P, factor); returns (x, NewtonRecord); raises Diverged."""
        m, free = self.model, self.free
        x = m.apply_dirichlet(x, factor)
        history = []
        for _ in range(self.opt.max_iter + 1):
            R, K = self._assemble(x, P, factor)
            merit, p_ok = self._merit(R, x, P, factor)
            history.append(merit)
            if not np.isfinite(merit):
                raise Diverged("non-finite residual")
            if merit <= self.opt.tol and p_ok:
                return x, NewtonRecord(tuple(history), True)
            self._check_progress(history)
            dx = -self._solve(K, R[free])
            x = self._line_search(x, dx, P, factor, history)
        raise Diverged(f"no convergence in {self.opt.max_iter} iterations")

    def _reference_pressure_force(self, P) -> float:
        """||sum_i P_i q_i|| at the reference state: the pressure load's scale."""
        if not self._q0:
            return 0.0
        Ps = self.model.pressures(P)
        return float(np.linalg.norm(sum(p * q for p, q in zip(Ps, self._q0))))

    def _merit(self, R, x, P, f):
        """Relative force residual ||R_u(free)|| / force scale, and whether the mixed-pressure
        constraint residual is below tol x the solid volume (it has units of volume)."""
        m = self.model
        fint = R[: m.n_u] + f * m.dead_load[: m.n_u]
        if m.chambers:
            fint = fint + m.pressure_force(x, P)[: m.n_u]
        scale = max(
            np.linalg.norm(fint), self._reference_pressure_force(P), abs(f) * self._dead_norm, self._floor
        )
        merit = float(np.linalg.norm(R[self.free_u]) / scale)
        p_ok = (not m.mixed) or np.linalg.norm(R[m.n_u :]) <= self.opt.tol * self._volume
        return merit, p_ok

    def _check_progress(self, history):
        """Diverged when, after `stall_iter` iterations, the best of the last three merits is not
        below half the best before them (the residual must keep shrinking)."""
        k = self.opt.stall_iter
        if len(history) > k and min(history[-3:]) > 0.5 * min(history[:-3]):
            raise Diverged(f"residual stalls at {history[-1]:.2e} after {len(history) - 1} iterations")

    def _line_search(self, x, dx, P, f, history):
        """Non-monotone backtracking (module docstring); the full step is tried first."""
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
        raise Diverged("line search found no decrease")

    def volume_step(self, x, P, volume_target, factor, direction=None, chamber: int = 0):
        """Equilibrium with the volume of `chamber` prescribed and the pressures moving along
        `direction` from P (module docstring); returns (x, P, NewtonRecord); raises Diverged.
        P and the returned pressures are arrays of one pressure per chamber."""
        m, free = self.model, self.free
        P = np.array(m.pressures(P), dtype=float)
        d = np.ones_like(P) if direction is None else np.asarray(direction, dtype=float)
        x = m.apply_dirichlet(x, factor)
        history = []
        for it in range(self.opt.max_iter + 1):
            R, K = self._assemble(x, P, factor)
            q = m.pressure_load(x, chamber)
            q_d = q if len(m.chambers) == 1 else m.pressure_force(x, d)
            g = m.chamber_volume(x, chamber) - volume_target
            merit, p_ok = self._merit(R, x, P, factor)
            history.append(merit)
            if not (np.isfinite(merit) and np.isfinite(g)):
                raise Diverged("non-finite residual")
            if merit <= self.opt.tol and p_ok and abs(g) <= 1e-10 * abs(volume_target):
                return x, P, NewtonRecord(tuple(history), True)
            if it == self.opt.max_iter:
                break
            ab = self._solve(K, np.column_stack([-R[free], q_d[free]]))
            a, b = ab[:, 0], ab[:, 1]
            qf = q[free]
            dlam = (-g - qf @ a) / (qf @ b)
            x = x.copy()
            x[free] += a + dlam * b
            P = P + dlam * d
        raise Diverged(f"no convergence in {self.opt.max_iter} iterations (volume control)")

    def stats(self, t0: float) -> SolveStats:
        return SolveStats(self.iterations, self.assembly_s, self.solve_s, time.perf_counter() - t0)
