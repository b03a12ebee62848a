"""Continuous gait refinement through an elbow: ePSA lengths as free variables, SLSQP minimax.

The grid searches (`analytic.planner`, `analytic.planar`) pick pressures on a 5-10 kPa grid, i.e. ePSA
lengths 1-10 mm apart, for a body whose centreline has a 12 mm corridor (70 mm pipe, 23 mm body
tube). Near a tight bend the feasible gaits are thinner than that grid: R = 40 mm is passed only
by gaits that no grid search contains. Here the gait is a fixed number of cycles whose inflated
lengths (l1, l23) are continuous (any pressure in 0-100 kPa), and

    maximise t   subject to   dist(body point) <= D/2 - r_body - t   for every sampled point of
                              every inflation stage of every cycle,
                              s(rear foot after the last cycle) >= goal,

solved with SLSQP (forward-difference Jacobians, batched; per cycle and stage only the largest
sample distance enters, an order statistic and so continuous in the lengths). t > 0 means a gait
with t mm of wall clearance to spare; by default SLSQP stops once t >= 0.02 mm. Lengths in the
upward 0.17 mm gap of the nominal l(P) at 60 kPa are reached by no pressure and are pinned to its
ends. The bend-plane form of `analytic.cycle` (docs/decisions/007-analytic-models.md, eqs. 16-18): the robot
is rolled so that ePSA 1 faces the inside of the bend, triples (P1, P23, P23) bend in the bend
plane with signed curvature k (> 0 towards the bend)

    l_c = (l1 + 2 l23) / 3,   k = (1 - l1 / l_c) / d,

the rear foot is fixed while the lengths go linearly from the deflated to the inflated lengths
(`stages` checked), then slides by l_c - l_def along the inflated arc (paper deflation: l_def =
l(0), curvature kept, deflated lengths l_def (1 - k d), l_def (1 + k d / 2)). The optimum is local:
the seed is a straight gait of short strides and SLSQP finds the manoeuvre (an S: first a slight
bend away from the elbow that puts the rear foot ~4 mm towards the outer wall, tilted ~4 deg away,
then a curvature that grows cycle by cycle). The result is converted to pressures by the inverse
statics and re-run by `analytic.gait.replay`, which applies the planner's own checks, so the
returned `Plan` does not depend on this module's simulator being right.

Only the nominal actuators (identical ePSAs 2 and 3 make P2 = P3 a planar family) and the paper
deflation are supported. Radii passed and clearances: see `analytic.planner`.
"""

from __future__ import annotations

import dataclasses
import time

import numpy as np
from numpy.typing import ArrayLike
from scipy.optimize import OptimizeResult, minimize

from softcrawl.analytic import cycle as cm
from softcrawl.analytic.errors import ModelInputError
from softcrawl.analytic.gait import Plan, replay
from softcrawl.analytic.limits import MAX_CONTINUOUS_CYCLES, check
from softcrawl.analytic.pipe import Pipe
from softcrawl.analytic.prototype import BODY_RADIUS_MM, actuator_set
from softcrawl.analytic.statics import EPSAParams
from softcrawl.paper import D_MM, P_MAX_KPA


def _cycle(
    pipe: Pipe,
    state: tuple[np.ndarray, ...],
    l1: np.ndarray,
    l23: np.ndarray,
    rest: float,
    d: float,
    lam: np.ndarray,
    f: np.ndarray,
) -> tuple[np.ndarray, tuple[np.ndarray, ...]]:
    """One cycle for a batch: wall distances (B, stages, samples) and the next state.

    A state is (x, z, heading, deflated l1, deflated l23), each (B,); `lam` is (1, stages).
    """
    x, z, A, l1d, l23d = state
    L1 = cm.inflation_lengths(l1d[:, None], l1[:, None], lam)
    L23 = cm.inflation_lengths(l23d[:, None], l23[:, None], lam)
    dist = cm.planar_distances(pipe, x[:, None], z[:, None], A[:, None], L1, L23, d, f)
    kf, lcf = cm.planar_configuration(l1, l23, d)
    step = lcf - rest
    return dist, (*cm.planar_slide(x, z, A, kf, step), *cm.planar_deflated_lengths(rest, kf, d))


def simulate(
    pipe: Pipe, lengths: ArrayLike, rest: float, d: float = D_MM, stages: int = 4, samples: int = 21
) -> tuple[np.ndarray, np.ndarray]:
    """Planar cycle model for gaits `lengths` (B, N, 2) = inflated (l1, l23) per cycle, mm.

    Returns the wall distances of the body centreline, (B, N, stages, samples), and the rear foot
    (x, z, heading) before the first and after every cycle, (B, N + 1, 3).
    """
    ls = np.asarray(lengths, dtype=float)
    B, N, _ = ls.shape
    state = (np.zeros(B), np.zeros(B), np.zeros(B), np.full(B, rest), np.full(B, rest))
    lam = cm.stage_fractions(stages)[None, :]
    f = np.linspace(0.0, 1.0, samples)
    dist = np.empty((B, N, stages, samples))
    rear = np.zeros((B, N + 1, 3))
    for i in range(N):
        dist[:, i], state = _cycle(pipe, state, ls[:, i, 0], ls[:, i, 1], rest, d, lam, f)
        rear[:, i + 1] = np.stack(state[:3], -1)
    return dist, rear


def _perturbed(
    pipe: Pipe, ls: np.ndarray, h: float, rest: float, d: float, stages: int, samples: int
) -> tuple[np.ndarray, np.ndarray]:
    """`simulate` of the gait ls (N, 2) and of its n = 2N forward perturbations by h.

    A cycle's lengths act on that cycle and the later ones only, so perturbation j (cycle j // 2)
    is simulated from its cycle on; before it, it equals the unperturbed gait.
    Returns dist (n + 1, N, stages, samples) and the final rear feet (n + 1, 3); row 0 unperturbed.
    """
    N = len(ls)
    n = 2 * N
    lam = cm.stage_fractions(stages)[None, :]
    f = np.linspace(0.0, 1.0, samples)
    dist = np.empty((n + 1, N, stages, samples))
    base = (np.zeros(1), np.zeros(1), np.zeros(1), np.full(1, rest), np.full(1, rest))
    pert = tuple(np.repeat(v, n) for v in base)
    for i in range(N):
        m = 2 * i + 2  # perturbations 0 .. m-1 act by cycle i
        l1 = np.full(m, ls[i, 0])
        l23 = np.full(m, ls[i, 1])
        l1[2 * i] += h
        l23[2 * i + 1] += h
        # rows that start to differ at this cycle start from the unperturbed state
        st = tuple(np.concatenate([p[: 2 * i], np.repeat(b, 2)]) for p, b in zip(pert, base))
        dp, st = _cycle(pipe, st, l1, l23, rest, d, lam, f)
        db, base = _cycle(pipe, base, ls[i, :1], ls[i, 1:], rest, d, lam, f)
        dist[0, i] = db[0]
        dist[1 : m + 1, i] = dp
        dist[m + 1 :, i] = db[0]
        pert = tuple(np.concatenate([a, np.repeat(b, n - m)]) for a, b in zip(st, base))
    rear = np.stack([np.concatenate([b, p]) for b, p in zip(base[:3], pert[:3])], -1)
    return dist, rear


def _progress(pipe: Pipe, rear: np.ndarray) -> np.ndarray:
    """Arc length along the pipe of bend-plane rear feet (..., >= 2) = (x, z, ...)."""
    r = np.asarray(rear)
    return pipe.locate(np.stack([r[..., 0], np.zeros_like(r[..., 0]), r[..., 1]], -1))[1]


def refine(
    pipe: Pipe,
    lengths0: ArrayLike,
    allow: float,
    rest: float,
    l_max: float,
    d: float = D_MM,
    stages: int = 4,
    samples: int = 21,
    maxiter: int = 400,
    h: float = 1e-6,
    keep: int = 1,
    target: float | None = None,
    bounds: ArrayLike | None = None,
) -> tuple[np.ndarray, float, OptimizeResult]:
    """Maximise the wall clearance t of the gait `lengths0` (N, 2) with the goal as a constraint.

    The constraints are, per cycle and stage, the `keep` largest sample distances (order
    statistics are continuous in the lengths, so this is exact for the max and keeps SLSQP's
    problem small). With `target`, SLSQP stops at the first iterate whose gait reaches the goal
    with at least `target` mm of clearance. Returns (lengths (N, 2), clearance t in mm of the
    returned gait, scipy result); lengths stay in [rest, l_max], or in `bounds` ((2N, 2) per
    length, l1 and l23 of cycle 1 first).
    """
    l0 = np.asarray(lengths0, dtype=float)
    N = len(l0)
    n = 2 * N
    goal = pipe.goal()
    memo: dict = {}

    def evaluate(v: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Wall and goal constraints at v and their Jacobians (forward differences, memoised)."""
        key = v.tobytes()
        if key not in memo:
            dist, rear = _perturbed(pipe, v[:n].reshape(N, 2), h, rest, d, stages, samples)
            g = np.sort(dist, axis=-1)[..., -keep:].reshape(n + 1, -1)
            s = _progress(pipe, rear)
            jw = np.empty((g.shape[1], n + 1))
            jw[:, :n] = -((g[1:] - g[0]) / h).T
            jw[:, n] = -1.0
            jg = np.zeros((1, n + 1))
            jg[0, :n] = (s[1:] - s[0]) / h
            memo.clear()
            memo[key] = (allow - v[n] - g[0], jw, np.array([s[0] - goal]), jg)
        return memo[key]

    def clearance(v: np.ndarray) -> float:
        """Wall clearance of the gait v if it reaches the goal, else -inf."""
        wall, _, goal_ok, _ = evaluate(v)
        return float(wall.min() + v[n]) if goal_ok[0] >= 0 else -np.inf

    def stop(xk: np.ndarray) -> None:
        if target is not None and clearance(xk) >= target:
            raise StopIteration

    dist0, _ = simulate(pipe, l0[None], rest, d, stages, samples)
    v0 = np.concatenate([l0.ravel(), [allow - dist0.max()]])
    grad = np.zeros(n + 1)
    grad[n] = -1.0
    res = minimize(
        lambda v: -v[n],
        v0,
        jac=lambda v: grad,
        method="SLSQP",
        callback=stop,
        bounds=[*(((rest, l_max),) * n if bounds is None else map(tuple, bounds)), (-allow - 100.0, allow)],
        constraints=[
            {"type": "ineq", "fun": lambda v: evaluate(v)[0], "jac": lambda v: evaluate(v)[1]},
            {"type": "ineq", "fun": lambda v: evaluate(v)[2], "jac": lambda v: evaluate(v)[3]},
        ],
        options={"maxiter": maxiter, "ftol": 1e-10},
    )
    return res.x[:n].reshape(N, 2), clearance(res.x), res


def continuous_plan(
    pipe: Pipe,
    cycles: int = 25,
    body_radius: float = BODY_RADIUS_MM,
    d: float = D_MM,
    stages: int = 8,
    samples: int = 41,
    maxiter: int = 400,
    seed: ArrayLike | None = None,
    check_stages: int = 4,
    check_samples: int = 21,
    margin: float | None = 0.02,
    attempts: int = 3,
) -> Plan:
    """Plan an elbow with continuous pressures (see the module docstring).

    `seed`: inflated triples (N, 3) in kPa to start from (P2 = P3); default a straight gait of
    `cycles` equal strides of min(1.25 goal / cycles, 12 mm). SLSQP first on the planner's own
    check (4 stages x 21 samples), then on `stages` x `samples`, stopping once the clearance to
    spare reaches `margin` mm (None: maximise it). The optimum is local; if a straight seed ends
    with the body in the wall, the next of `attempts` seeds has one cycle more. The gait is re-run
    by `replay` with `check_stages` x `check_samples`; the message states the clearance to spare
    on the optimiser's finer check and the run time.
    """
    if pipe.kind != "elbow":
        raise ModelInputError("pipe", "continuous refinement is for elbows")
    cycles = check(cycles, "cycles", minimum=1, maximum=MAX_CONTINUOUS_CYCLES, integer=True)
    a = actuator_set("nominal")[0]
    rest, l_max = float(a.length(0.0, 0.0)), float(a.length(P_MAX_KPA, 0.0))
    allow = cm.PipeFit.of(pipe, body_radius).allow
    t_start = time.perf_counter()
    best = None
    for l0 in _seeds(pipe, a, seed, cycles, attempts, rest, l_max):
        lengths, t = _refine_gait(pipe, a, l0, allow, rest, l_max, d, stages, samples, maxiter, margin)
        if best is None or t > best[1]:
            best = (lengths, t)
        if t >= 0:
            break
    lengths, t = best
    triples = []
    for l1, l23 in lengths:
        p1, p23 = (a.pressure_for_length(min(max(v, rest), l_max), 0.0) for v in (l1, l23))
        triples.append((p1, p23, p23))
    result = replay(pipe, triples, "nominal", body_radius, d, check_stages, check_samples)
    spare = (
        f"clearance to spare {t:.4f} mm on {stages} stages x {samples} samples"
        if np.isfinite(t)
        else "the optimiser did not reach the goal"
    )
    msg = (
        f"{result.message}; continuous pressures, {len(lengths)} cycles planned, {spare} "
        f"({time.perf_counter() - t_start:.1f} s)"
    )
    return dataclasses.replace(result, step_kpa=0.0, message=msg)


def _seeds(
    pipe: Pipe,
    a: EPSAParams,
    seed: ArrayLike | None,
    cycles: int,
    attempts: int,
    rest: float,
    l_max: float,
) -> list[np.ndarray]:
    """Gaits (N, 2) of inflated (l1, l23) to start SLSQP from: the given `seed` triples, or
    straight gaits of `cycles`, `cycles` + 1, ... equal strides (`attempts` of them)."""
    if seed is not None:
        P = np.asarray(seed, dtype=float).reshape(-1, 3)
        if np.any(P[:, 1] != P[:, 2]):
            raise ModelInputError("seed", "triples must have P2 = P3")
        return [np.stack([a.length(P[:, 0], 0.0), a.length(P[:, 1], 0.0)], -1)]
    seeds = []
    for n in range(cycles, cycles + max(attempts, 1)):
        stride = min(1.25 * pipe.goal() / n, 12.0)
        seeds.append(np.full((n, 2), min(rest + stride, l_max)))
    return seeds


def _refine_gait(
    pipe: Pipe,
    a: EPSAParams,
    l0: np.ndarray,
    allow: float,
    rest: float,
    l_max: float,
    d: float,
    stages: int,
    samples: int,
    maxiter: int,
    margin: float | None,
) -> tuple[np.ndarray, float]:
    """SLSQP on the planner's check, then on stages x samples; lengths kept out of the 60 kPa gap."""
    lengths, t, _ = refine(pipe, l0, allow, rest, l_max, d, 4, 21, maxiter, target=margin)
    if (stages, samples) != (4, 21) and t >= 0:
        lengths, t, _ = refine(pipe, lengths, allow, rest, l_max, d, stages, samples, maxiter, target=margin)
    # Lengths inside the upward jump of l(P) at 60 kPa are reached by no pressure: pin them to
    # the nearer end of the gap and refine the others.
    gap_lo, gap_hi, jump = a.length_jump(0.0)
    inside = (lengths > gap_lo) & (lengths < gap_hi) if jump > 0 else np.zeros(lengths.shape, bool)
    if inside.any():
        lengths = np.where(inside, np.where(lengths - gap_lo < gap_hi - lengths, gap_lo, gap_hi), lengths)
        b = np.stack([np.where(inside, lengths, rest), np.where(inside, lengths, l_max)], -1)
        lengths, t, _ = refine(
            pipe,
            lengths,
            allow,
            rest,
            l_max,
            d,
            stages,
            samples,
            maxiter,
            target=margin,
            bounds=b.reshape(-1, 2),
        )
    return lengths, t
