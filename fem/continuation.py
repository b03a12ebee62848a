r"""Volume control past a limit point, from a state where pressure control stalled.

The pressures keep the direction of the segment on which pressure control stalled,
P = P0 + lambda d, with d normalised so that d_k = 1 for the driving chamber k (the one whose
pressure changes most); the volume V_k of that chamber is prescribed and lambda is solved for
(`fem.newton.NewtonSolver.volume_step`). With one chamber, d = 1 and lambda is the pressure.

Volume steps adapt to the Newton effort. When the driving pressure crosses the next target, a
secant iteration in V lands on it, and that state is recorded as the target's step (control
"volume", `past_limit` False: it is the equilibrium at that target). If the driving pressure
peaks and falls, the peak (refined by a parabola through the three samples around it) is the
limit point: "limit point at P ~ x kPa"; the path goes on for `post_limit_steps` volume steps and
ends (targets above the peak are unreachable). Volume control follows one load direction: a
remaining target off that line is not reached, and the path says so.

Guards. The path ends (converged = False, a message naming the last converged load and the
guard) after `max_volume_steps` volume steps, after `max_cutbacks` halvings of the volume step in
a row, or when the step falls below 1e-3 of the first one: a wrong tangent or load (a flipped
chamber normal, say) makes volume control creep forward in ever smaller steps without ever
reaching a target or a peak, and without these limits that never ends.
"""

from __future__ import annotations

import numpy as np

from softcrawl.fem.newton import Diverged
from softcrawl.fem.steps import History, PathResult, describe_load, failed, make_step
from softcrawl.units import mpa_to_kpa  # the path works in MPa; its limit-point messages are read in kPa


def volume_continuation(solver, shape, history: History, remaining, steps, events, opt, t0) -> PathResult:
    """Volume control from the stalled state of `history` through the `remaining` load vectors."""
    m = solver.model
    L0 = np.asarray(history.load, dtype=float)
    dP = remaining[0][:-1] - L0[:-1]
    k = int(np.argmax(np.abs(dP))) if dP.size > 1 else 0
    d = dP / dP[k]
    f = float(L0[-1])
    pending, off_line = _on_the_line(remaining, L0, d, k)
    P_vec = m.pressures(L0[:-1])
    V = m.chamber_volume(history.x, k)
    V_prev = m.chamber_volume(history.x_prev, k) if history.x_prev is not None else V * 0.99
    vh = History(history.x, np.r_[L0[:-1], f], V)
    vh.x_prev, vh.load_prev, vh.volume_prev = history.x_prev, history.load_prev, V_prev
    dV = max(0.5 * abs(V - V_prev), 1e-3 * abs(V))  # floor: round-off in P must not look like a peak
    samples = [(V, float(P_vec[k]))]
    peak, after_peak, cuts = None, 0, 0

    def solve_at(volume):
        x, P, record = solver.volume_step(vh.predict(volume=volume), vh.load[:-1], volume, f, d, k)
        return x, np.r_[_user_length(P, shape), f], record

    dV_min = 1e-3 * dV  # volume steps below this are a stalled path, not progress
    n_steps = 0
    while pending:
        n_steps += 1
        if n_steps > opt.max_volume_steps:
            reason = (
                f"{opt.max_volume_steps} volume steps (max_volume_steps) did not reach "
                f"{describe_load(pending[0])}; the driving pressure is {mpa_to_kpa(vh.load[k]):.4g} kPa"
            )
            return _end_of_volume_path(solver, vh, steps, events, t0, peak, reason)
        try:
            x_new, L_new, record = solve_at(vh.volume + dV)
        except Diverged as exc:
            dV *= 0.5
            cuts += 1
            if cuts > opt.max_cutbacks or dV < dV_min:
                reason = f"{exc}; the volume step was cut back {cuts} times in a row to {dV:.3g} mm^3"
                return _end_of_volume_path(solver, vh, steps, events, t0, peak, reason)
            continue
        cuts = 0
        V_new = vh.volume + dV
        target = pending[0][k]
        if L_new[k] >= target > vh.load[k] and peak is None:
            x_hit, L_hit, rec_hit, V_hit = _land_on(
                solve_at, (vh.volume, vh.load[k]), (V_new, L_new[k]), (x_new, L_new, record, V_new), target, k
            )
            vh.accept(x_hit, L_hit, V_hit)
            m.commit(x_hit)
            steps.append(make_step(m, shape, L_hit, x_hit, "volume", rec_hit, chamber=k))
            samples.append((V_hit, float(L_hit[k])))
            pending.pop(0)
            continue
        vh.accept(x_new, L_new, V_new)
        m.commit(x_new)
        samples.append((V_new, float(L_new[k])))
        if (
            peak is None
            and len(samples) >= 3
            and samples[-1][1] < samples[-2][1] - 1e-6 * abs(samples[-2][1])
        ):
            peak = parabola_peak(samples[-3:])
            events.append(f"limit point at P ~ {mpa_to_kpa(peak):.4g} kPa (volume control continues)")
        if peak is not None:
            steps.append(make_step(m, shape, L_new, x_new, "volume", record, past_limit=True, chamber=k))
            after_peak += 1
            if after_peak >= opt.post_limit_steps:
                break
        if record.iterations <= 5:
            dV *= 1.5
    if peak is not None:
        msg = f"limit point at P ~ {mpa_to_kpa(peak):.4g} kPa"
        return PathResult(tuple(steps), True, msg, peak, tuple(events), solver.stats(t0))
    if off_line:
        return failed(
            steps,
            events,
            solver,
            t0,
            vh.load,
            f"volume control follows one load direction; the target {describe_load(off_line[0])} lies off it",
            volume=vh.volume,
        )
    msg = "all load targets reached (the last ones on volume control)"
    return PathResult(tuple(steps), True, msg, None, tuple(events), solver.stats(t0))


def _user_length(P: np.ndarray, shape) -> np.ndarray:
    """The model's per-chamber pressures cut back to the load vector's pressure entries."""
    return P[: shape.n] if shape.n < P.size else P


def _on_the_line(remaining, L0, d, k):
    """The remaining targets on the ray P0 + t d (t >= 0) up to the first one off it."""
    pending, off = [], []
    scale = max(float(np.abs(np.vstack(remaining)[:, :-1]).max()), 1e-300)
    for L in remaining:
        t = L[k] - L0[k]
        if off or t < 0 or np.abs(L[:-1] - (L0[:-1] + t * d)).max() > 1e-9 * scale:
            off.append(L)
        else:
            pending.append(L)
    return pending, off


def _land_on(solve_at, lo, hi, best, target, k):
    """Secant iteration in V onto the driving pressure `target`, between the bracketing states
    lo and hi (V, P_k); returns (x, L, record, V) of the landed (or best bracketing) state."""
    x_hit, L_hit, rec_hit, V_hit = best
    for _ in range(4):
        Vs = lo[0] + (target - lo[1]) * (hi[0] - lo[0]) / (hi[1] - lo[1])
        try:
            x_hit, L_hit, rec_hit = solve_at(Vs)
        except Diverged:
            break
        V_hit = Vs
        if abs(L_hit[k] - target) <= 1e-5 * abs(target):
            break
        lo, hi = ((Vs, L_hit[k]), hi) if L_hit[k] < target else (lo, (Vs, L_hit[k]))
    return x_hit, L_hit, rec_hit, V_hit


def _end_of_volume_path(solver, vh, steps, events, t0, peak, reason) -> PathResult:
    if peak is not None:
        events.append(f"volume control stopped after the limit point ({reason})")
        msg = f"limit point at P ~ {mpa_to_kpa(peak):.4g} kPa"
        return PathResult(tuple(steps), True, msg, peak, tuple(events), solver.stats(t0))
    return failed(
        steps, events, solver, t0, vh.load, f"volume control could not advance ({reason})", volume=vh.volume
    )


def parabola_peak(samples) -> float:
    """The maximum of the parabola through three (V, P) samples (bounded by the samples' range)."""
    (v0, p0), (v1, p1), (v2, p2) = samples
    A = np.array([[v0 * v0, v0, 1.0], [v1 * v1, v1, 1.0], [v2 * v2, v2, 1.0]])
    a, b, c = np.linalg.solve(A, [p0, p1, p2])
    if a >= 0:
        return max(p0, p1, p2)
    v = -b / (2 * a)
    return float(min(max(a * v * v + b * v + c, max(p0, p1, p2)), 1.5 * max(p0, p1, p2)))
