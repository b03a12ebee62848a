r"""Newton's method on a `fem.model.SolidModel` at a fixed load or at a prescribed chamber volume.

Load. P is one pressure per chamber (MPa; a scalar applies to every chamber) and f the factor of
the prescribed displacements and dead loads.

Convergence. The force residual on the free displacement dofs relative to the force scale
(the internal force, the pressure and dead loads at the reference state, a floor far below any
load of interest) is below `tol`, and, for the mixed formulation, the pressure-constraint residual
is below `tol` x the solid volume; the two are kept apart because they have different units.
The internal force includes the reactions of the prescribed dofs, which is what makes it a scale:
on a body with no displacement prescribed (held only by springs and contact terms, like the one FE
body of docs/decisions/076-one-body.md) it equals the residual, and the relative residual would be
1 at every state. There the solid's own force div(sigma) (`SolidModel.body_force`), which the terms
balance at equilibrium, joins the scale; a model with any prescribed dof is unchanged.
Tied dofs (`fem.dirichlet`) are no unknowns: T^T K T dq = -T^T R, x moves by T dq, and the norms
fold the tied rows onto their masters (`SolidModel.fold`): a wedge's merit is the whole body's
(docs/decisions/083-exact-wedge.md).
Each iteration evaluates the residual first and assembles the tangent only when the state has
not converged (the tangent of a converged state is never needed by Newton itself).

Line search, only when the full step fails. The full Newton step is accepted when its residual
is below the largest of the last three (non-monotone: nearly incompressible solids overshoot
before they converge) and, near the solution (relative residual below 1e-3), without a check, so
the quadratic convergence of the consistent tangent is kept (`NewtonRecord.residuals` shows it).
A rejected full step (an inverted element, a non-finite or a too large residual) is shortened by
the secant root of the directional derivative s(a) = dx . R(x + a dx) (Crisfield's line search,
clipped to [0.1, 0.5] of the last trial, so that it shortens at least as fast as bisection: a
penalty contact whose first full step penetrates the wall decreases only at small steps), or
halved when the trial has no residual.

Linear solves (`fem.linsolve.StepSolver`): a factorisation of the current tangent (of its
symmetric part, with GMRES on the tangent, when it is not symmetric), or GMRES on it
preconditioned by the last factorisation when that is cheaper (the forcing term
eta = min(1e-2, max(r / 10, tol / (10 r))) keeps the convergence quadratic:
r_{k+1} <= eta r_k + C r_k^2).

Volume control (passes limit points). The pressures move along a direction d, P = P0 + lambda d
(d_k = 1 for the driving chamber k, so lambda is the change of its pressure), and the volume of
chamber k is prescribed; lambda is an unknown:

    R(x, lambda) = f_int(x) - sum_i (P0_i + lambda d_i) q_i(x) - f f_dead = 0,   V_k(x) - V* = 0.

Each Newton step solves the bordered system with one factorisation and two right-hand sides,
K a = -R, K b = q_d (q_d = sum_i d_i q_i = -dR/dlambda), dlambda = (V* - V_k - q_k.a) / (q_k.b),
dx = a + dlambda b. It stays regular at the pressure maximum where K alone is singular. With one
chamber, d = 1 and lambda is the pressure itself.

Stalled residuals and iterations that make no progress: `fem.newton_progress` (`stall_iter`,
`stall_tol`, `progress_iter`).

A diverged iteration raises `Diverged` (stalling residual, a non-finite residual, an inverted
element, no convergence in `max_iter`, a line search without decrease), each with a message that
says which; the path (`fem.path`) cuts the step back, within its own limits (`NewtonOptions`).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from softcrawl.fem.krylov import dot, norm
from softcrawl.fem.linsolve import StepSolver
from softcrawl.fem.model import InvertedElement, SolidModel
from softcrawl.fem.newton_progress import accepts_stall, divergence


@dataclass(frozen=True, kw_only=True)
class NewtonOptions:
    """Tolerances and the guards that bound every loop of a solve (none can spin forever)."""

    tol: float = 1e-8  # relative residual ||R_free|| / force scale
    max_iter: int = 20  # Newton iterations of one load or volume step
    stall_iter: int = 8  # after this many iterations the residual must keep halving
    #: A residual that stalls (the `stall_iter` test) below this relative level is accepted as
    #: converged (None: never; `fem.newton_progress`).
    stall_tol: float | None = None
    #: after this many iterations, three in a row without a new lowest residual are a divergence
    #: (None: never; `fem.newton_progress`)
    progress_iter: int | None = None
    max_backtracks: int = 6  # line-search trials after a rejected full step
    max_cutbacks: int = 4  # consecutive halvings of a load (or volume) step before giving up
    min_step_fraction: float = 1e-3  # smallest sub-step, as a fraction of a load segment
    max_substeps: int = 100  # sub-steps of one load segment
    max_volume_steps: int = 50  # volume steps of one continuation or volume target (tests: <= 12)
    post_limit_steps: int = 6
    predictor: str = "tangent"  # "tangent" (Euler, Hermite with the last state), "secant", "none"
    rigid_ratio: float | None = None  # predict parts this much stiffer rigidly (fem.stiff_parts)
    reuse_factor: bool = True  # GMRES on the tangent with the last factorisation when cheaper
    #: A non-symmetric tangent: factorise its symmetric part and solve by GMRES on the tangent
    #: (`fem.linsolve.StepSolver`, docs/decisions/080-symmetric-part.md).
    symmetric_part: bool = True
    solver: str | None = None


PREDICTORS = ("tangent", "secant", "none")
#: Newton iterations try the last factorisation only when GMRES may take this many iterations
#: within half a factorisation (the predictor's tangent solve, on nearly the same matrix, 2).
#: Measured (docs/decisions/017-solver-pass2.md): with 9 allowed, a win at 22k DOFs (-18 % wall time) since
#: GMRES runs without BLAS threads and abandons hopeless attempts; a win at 165k.
REUSE_MIN_KRYLOV = 6


@dataclass(frozen=True)
class NewtonRecord:
    residuals: tuple[float, ...]  # relative residual norm at each iteration
    converged: bool

    @property
    def iterations(self) -> int:
        return max(len(self.residuals) - 1, 0)


@dataclass(frozen=True)
class SolveStats:
    iterations: int  # Newton iterations (linear systems solved)
    assembly_s: float  # residual and tangent assembly
    solve_s: float  # linear algebra: factorisations, substitutions, GMRES
    wall_s: float
    factorizations: int = 0
    substitutions: int = 0  # forward and back substitutions with a factorisation
    krylov_iterations: int = 0


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
        self.iterations = 0
        symmetric = model.symmetric_tangent
        self.linear = StepSolver(options.solver, symmetric, options.reuse_factor, options.symmetric_part)
        self._u_rows = self.free < model.n_u  # the free displacement dofs among the free dofs
        self._unheld = not np.any(model.fixed_dofs < model.n_u)  # no displacement prescribed (docstring)
        self._volume = float(model.dx.sum())
        x0 = model.initial_state()
        self._q0 = [model.fold(model.pressure_load(x0, i))[: model.n_u] for i in range(len(model.chambers))]
        self._dead = model.fold(model.dead_load)
        self._dead_norm = np.linalg.norm(self._dead)
        self._floor = force_floor(model)
        self._converged_factor = None  # the state whose last Newton iteration factorised (load_tangent)

    # ------------------------------------------------------------------ assembly
    def _tangent(self, x, P, f):
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

    def _weights(self, R, scale):
        """Row weights of the free dofs that put the forces (/ force scale) and the volume
        constraints (/ solid volume) on the scales of the convergence test."""
        w = np.full(self.free.size, 1.0 / scale)
        if self.model.mixed:
            w[self.free >= self.model.n_u] = 1.0 / self._volume
        return w

    def _solve(self, K, B, rtol, weights, first: bool):
        # Reusing the last factorisation in a Newton iteration pays only when GMRES may run long
        # enough (REUSE_MIN_KRYLOV iterations within half a factorisation), and never at the
        # first iteration, which starts from a predicted state far from where the last
        # factorisation was made (measured: docs/decisions/016-solver-pass1.md).
        out = self.linear.solve(K, B, rtol, weights, 0 if first else REUSE_MIN_KRYLOV)
        self.iterations += 1
        return out

    def _forcing(self, merit: float) -> float:
        """Relative accuracy of the linear solve at relative residual `merit` (module docstring)."""
        return float(min(1e-2, max(0.1 * merit, 0.1 * self.opt.tol / max(merit, 1e-300))))

    # ---------------------------------------------------------------- load step
    def load_step(self, x, P, factor, start=None):
        """Equilibrium at fixed (P, factor) from the predicted state x; returns (x, NewtonRecord);
        raises Diverged. With `start` (the last converged state), a prediction that inverts an
        element is drawn back towards `start` (halved up to three times) before Newton begins."""
        x = self._admissible(self.model.apply_dirichlet(x, factor), start, P, factor)
        history = []
        self._converged_factor = None
        for it in range(self.opt.max_iter + 1):
            R = self._checked_residual(x, P, factor)
            merit, p_ok, scale = self._merit(R, x, P, factor)
            history.append(merit)
            if not np.isfinite(merit):
                raise Diverged("non-finite residual")
            if merit <= self.opt.tol and p_ok:
                if it > 0 and self.linear.last_factored:
                    self._converged_factor = x
                return x, NewtonRecord(tuple(history), True)
            if it == self.opt.max_iter:
                break
            if accepts_stall(history, self.opt.stall_tol, p_ok):
                return x, NewtonRecord(tuple(history), True)
            self._check_progress(history)
            R, K = self._tangent(x, P, factor)
            dx = -self._solve(K, self.model.reduce(R), self._forcing(merit), self._weights(R, scale), it == 0)
            x = self._line_search(x, dx, R, P, factor, history)
        raise Diverged(f"no convergence in {self.opt.max_iter} Newton iterations")

    def _checked_residual(self, x, P, f):
        try:
            return self._residual(x, P, f)
        except InvertedElement as exc:
            raise Diverged(str(exc)) from None

    def _admissible(self, x, start, P, f):
        """x, or x drawn back towards `start` until no element is inverted."""
        if start is None:
            return x
        start = self.model.apply_dirichlet(start, f)
        for _ in range(3):
            try:
                self._residual(x, P, f)
                return x
            except InvertedElement:
                x = start + 0.5 * (x - start)
        return x

    def _reference_pressure_force(self, P) -> float:
        """||sum_i P_i q_i|| at the reference state: the pressure load's scale."""
        if not self._q0:
            return 0.0
        Ps = self.model.pressures(P)
        return norm(sum(p * q for p, q in zip(Ps, self._q0)))

    def _merit(self, R, x, P, f):
        """Relative force residual ||R_u(free)|| / force scale, whether the mixed-pressure
        constraint residual is below tol x the solid volume (it has units of volume), and the
        force scale."""
        m = self.model
        R = m.fold(R)  # tied rows on their masters': a wedge's forces as the whole body's, once each
        fint = R[: m.n_u] + f * self._dead[: m.n_u]
        if m.chambers:
            fint = fint + m.fold(m.pressure_force(x, P))[: m.n_u]
        scale = max(norm(fint), self._reference_pressure_force(P), abs(f) * self._dead_norm, self._floor)
        if self._unheld:  # no reactions: fint is the residual itself, the solid's own force is not
            scale = max(scale, norm(m.fold(m.body_force(x))[: m.n_u]))
        Rf = R[self.free]  # the free dofs' equations, T^T R
        merit = norm(Rf[self._u_rows]) / scale  # fem.krylov.norm: no BLAS threads on long vectors
        p_ok = (not m.mixed) or norm(Rf[~self._u_rows]) <= self.opt.tol * self._volume
        return merit, p_ok, scale

    def _check_progress(self, history):
        """Diverged when the residual has stalled or makes no progress (`fem.newton_progress`)."""
        why = divergence(history, self.opt.stall_iter, self.opt.progress_iter)
        if why is not None:
            raise Diverged(why)

    def _trial(self, x, dx, alpha, P, f):
        """(state, merit, residual) at x + alpha dx; merit inf and residual None if inverted."""
        trial = self.model.step(x, dx, alpha)
        try:
            R = self._residual(trial, P, f)
        except InvertedElement:
            return trial, np.inf, None
        return trial, self._merit(R, trial, P, f)[0], R

    def _line_search(self, x, dx, R0, P, f, history):
        """The full step if it is acceptable, else Crisfield's secant line search (module
        docstring); the residual of the accepted state is remembered by the model for the next
        iteration, so a full step costs nothing extra."""
        reduce = self.model.reduce
        reference = max(history[-3:])
        if history[-1] <= 1e-3:
            return self.model.step(x, dx)
        trial, merit, R = self._trial(x, dx, 1.0, P, f)
        if np.isfinite(merit) and merit < reference:
            return trial
        s0 = dot(dx, reduce(R0))
        alpha = 1.0
        for _ in range(self.opt.max_backtracks):
            if R is None or s0 >= 0:
                alpha *= 0.5
            else:
                s1 = dot(dx, reduce(R))
                root = alpha * s0 / (s0 - s1) if s1 != s0 else 0.5 * alpha
                # at least halve: after k trials the step is no longer than plain bisection's
                # (a penalty contact that first penetrates decreases only at small steps)
                alpha = float(np.clip(root, 0.1 * alpha, 0.5 * alpha))
            trial, merit, R = self._trial(x, dx, alpha, P, f)
            if np.isfinite(merit) and merit < reference:
                return trial
        raise Diverged(f"line search found no decrease in {self.opt.max_backtracks} trials")

    # ------------------------------------------------------------------ tangent
    def load_tangent(self, x, L, direction):
        """dx/ds along the load direction `direction` (a load vector (P..., f) per unit s) at the
        converged state x at load L: K dx/ds = -dR/ds, with dR/ds by a one-sided difference of
        the residual (exact for pressures and dead loads, which enter linearly; the Dirichlet
        values move with f). The Euler predictor of `fem.path`.

        When x was just found by a Newton iteration whose last step factorised the tangent (one
        quadratically convergent update before x: K changes by O(||R||), below 1e-4 relative),
        that factorisation is used as K(x): one substitution, no assembly and no GMRES. Otherwise
        K(x) is assembled and solved to 1e-4."""
        m = self.model
        d = np.asarray(direction, dtype=float)
        delta = 1e-6
        x1 = m.apply_dirichlet(x, L[-1] + delta * d[-1])
        reuse = self._converged_factor is x and self.linear.holds_factor()
        if reuse:
            R0 = self._checked_residual(x, L[:-1], L[-1])
        else:
            R0, K = self._tangent(x, L[:-1], L[-1])
        R1 = self._checked_residual(x1, L[:-1] + delta * d[:-1], L[-1] + delta * d[-1])
        g = m.reduce(R1 - R0) / delta
        if reuse:
            dq = -self.linear.substitute(g)
        else:
            scale = self._merit(R0, x, L[:-1], L[-1])[2]
            dq = -self.linear.solve(K, g, 1e-4, self._weights(R0, scale))
        v = m.step(np.zeros_like(x), dq)
        v[m.fixed_dofs] = (x1 - x)[m.fixed_dofs] / delta
        return v

    # ----------------------------------------------------------- volume control
    def volume_step(self, x, P, volume_target, factor, direction=None, chamber: int = 0):
        """Equilibrium with the volume of `chamber` prescribed and the pressures moving along
        `direction` from P (module docstring); returns (x, P, NewtonRecord); raises Diverged.
        P and the returned pressures are arrays of one pressure per chamber."""
        m = self.model
        P = np.array(m.pressures(P), dtype=float)
        d = np.ones_like(P) if direction is None else np.asarray(direction, dtype=float)
        x = m.apply_dirichlet(x, factor)
        history = []
        self._converged_factor = None
        for it in range(self.opt.max_iter + 1):
            R, K = self._tangent(x, P, factor)
            q = m.pressure_load(x, chamber)
            q_d = q if len(m.chambers) == 1 else m.pressure_force(x, d)
            g = m.chamber_volume(x, chamber) - volume_target
            merit, p_ok, scale = self._merit(R, x, P, factor)
            history.append(merit)
            if not (np.isfinite(merit) and np.isfinite(g)):
                raise Diverged("non-finite residual")
            if merit <= self.opt.tol and p_ok and abs(g) <= 1e-10 * abs(volume_target):
                return x, P, NewtonRecord(tuple(history), True)
            if it == self.opt.max_iter:
                break
            self._check_progress(history)
            rtol = min(self._forcing(merit), 1e-6)  # dlambda divides by q.b: b needs accuracy
            B = np.column_stack([-m.reduce(R), m.reduce(q_d)])
            ab = self._solve(K, B, rtol, self._weights(R, scale), it == 0)
            a, b = ab[:, 0], ab[:, 1]
            qf = m.reduce(q)
            dlam = (-g - qf @ a) / (qf @ b)
            x = m.step(x, a + dlam * b)
            P = P + dlam * d
        raise Diverged(f"no convergence in {self.opt.max_iter} Newton iterations (volume control)")

    def stats(self, t0: float) -> SolveStats:
        lin = self.linear
        return SolveStats(
            self.iterations,
            self.assembly_s,
            lin.seconds,
            time.perf_counter() - t0,
            lin.factorizations,
            lin.substitutions,
            lin.krylov_iterations,
        )
