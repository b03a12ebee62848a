"""A planned gait (`Plan`, its `Cycle`s) and `replay`, which runs a given gait through the cycle model.

Every planner (`analytic.planner`, `analytic.planar`, `analytic.refine`) returns a `Plan`. `replay` applies
the cycle model of `analytic.cycle` (statics, roll, inflation stages, pipe-fit check, deflation) to
inflated triples chosen elsewhere: it searches nothing, it checks. A plan found by another model
(the bend-plane simulator of `analytic.refine`) is re-run by it, so that what is returned does not
depend on that other model being right.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from softcrawl.analytic import cycle as cm
from softcrawl.analytic import kinematics as kin
from softcrawl.analytic.errors import ModelInputError
from softcrawl.analytic.pipe import Pipe
from softcrawl.analytic.prototype import BODY_RADIUS_MM, actuator_set
from softcrawl.analytic.statics import EPSAParams
from softcrawl.paper import D_MM, P_MAX_KPA

Triple = tuple[float, float, float]


@dataclass(frozen=True)
class Cycle:
    index: int
    pressures_inflated: Triple  # kPa
    pressures_deflated: Triple  # kPa, held after deflation
    lengths_inflated: Triple  # mm
    lengths_deflated: Triple  # mm
    kappa: float
    theta: float
    phi: float
    length_inflated: float  # centreline, mm
    length_deflated: float
    rear_before: Triple
    front: Triple  # front foot, fixed during deflation
    rear_after: Triple
    progress: float  # rear-foot arc length after the cycle, mm
    clearance: float  # smallest wall clearance in the cycle, mm


@dataclass(frozen=True)
class Plan:
    pipe: Pipe
    success: bool
    cycles: tuple[Cycle, ...]
    body_radius: float
    d: float
    actuators: str
    step_kpa: float
    body: str
    start_rear: Triple
    start_pressures: Triple
    message: str = ""
    start_rotation: tuple[Triple, Triple, Triple] = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))

    def gait(self) -> list[tuple[str, float, float, float]]:
        """[(phase, P1, P2, P3)] kPa: 'inflate', 'deflate' per cycle."""
        out = []
        for c in self.cycles:
            out.append(("inflate",) + c.pressures_inflated)
            out.append(("deflate",) + c.pressures_deflated)
        return out


def floats(values: ArrayLike) -> tuple[float, ...]:
    """A vector as a tuple of Python floats (the fields of `Cycle` and `Plan`)."""
    return tuple(map(float, values))


def rotation_tuple(rot: np.ndarray) -> tuple[Triple, Triple, Triple]:
    """A 3 x 3 rotation as nested tuples of floats (`Plan.start_rotation`)."""
    return tuple(tuple(map(float, r)) for r in rot)


def replay(
    pipe: Pipe,
    triples: ArrayLike,
    actuators: str = "nominal",
    body_radius: float = BODY_RADIUS_MM,
    d: float = D_MM,
    stages: int = 4,
    samples: int = 21,
    tol: float = 1e-9,
    deflation: str = "paper",
    body: str = "tube",
    step_kpa: float = 0.0,
) -> Plan:
    """Run a given gait (inflated triples, kPa) through the cycle model of `analytic.planner.plan`.

    Same statics, roll, inflation stages, containment check and deflation as `plan`; the gait is
    not searched but checked: the plan stops, unsuccessful, at the first cycle whose body leaves
    the pipe (its message says by how much) and succeeds when the rear foot passes the goal.
    `step_kpa` is only recorded (0 = continuous pressures).
    """
    acts: tuple[EPSAParams, ...] = actuator_set(actuators)
    cm.check_deflation(deflation)
    fit = cm.PipeFit.of(pipe, body_radius, body, tol)
    triples = np.asarray(triples, dtype=float).reshape(-1, 3)
    if np.any(~np.isfinite(triples)) or np.any(triples < 0) or np.any(triples > P_MAX_KPA + 1e-9):
        raise ModelInputError("pressure", f"pressures must be in [0, {P_MAX_KPA:g}] kPa")
    g = cm.gravity(pipe)
    goal = pipe.goal()
    rot0 = cm.elbow_roll(pipe)
    lam = cm.stage_fractions(stages)
    pos, rot = np.zeros(3), rot0.copy()
    l_cur = cm.epsa_lengths(acts, np.zeros(3), g)
    cycles, success = [], False
    message = f"gait of {len(triples)} cycles ends before s = {goal:.1f} mm"
    for n, P in enumerate(triples, start=1):
        Lg = cm.epsa_lengths(acts, P, g)
        _, dist = fit.inflation_distances(pos, rot, l_cur, Lg, lam, d, samples)
        worst = float(dist.max())
        if not fit.fits(worst):
            message = f"cycle {n} leaves the pipe by {worst - fit.allow:.4f} mm"
            break
        c, rot = _replayed_cycle(pipe, acts, n, P, Lg, pos, rot, d, g, deflation, float(fit.clearance(worst)))
        cycles.append(c)
        pos, l_cur = np.array(c.rear_after), np.array(c.lengths_deflated)
        if c.progress >= goal:
            success, message = True, f"rear foot passed s = {goal:.1f} mm"
            break
    return Plan(
        pipe,
        success,
        tuple(cycles),
        fit.body_radius,
        d,
        actuators,
        step_kpa,
        body,
        (0.0, 0.0, 0.0),
        (0.0, 0.0, 0.0),
        message,
        rotation_tuple(rot0),
    )


def _replayed_cycle(
    pipe: Pipe,
    acts: tuple[EPSAParams, ...],
    n: int,
    P: np.ndarray,
    Lg: np.ndarray,
    pos: np.ndarray,
    rot: np.ndarray,
    d: float,
    g: float,
    deflation: str,
    clearance: float,
) -> tuple[Cycle, np.ndarray]:
    """Cycle `n` (inflated lengths `Lg`, which fit the pipe) and the rear-foot frame after it."""
    k, t, ph, lc = (float(v) for v in kin.forward(Lg, d))
    ldef = float(cm.deflated_length(acts, k, ph, d, g, deflation))
    step = max(lc - ldef, 0.0)
    new_pos = cm.rear_slide(pos, rot, k, ph, step)
    _, s_new = pipe.locate(new_pos)
    ldef_i = cm.deflated_lengths(ldef, k, ph, d)
    p_def = floats(cm.deflated_pressures(acts, ldef_i, g))
    front = cm.front_foot(pos, rot, t, ph, lc)
    cycle = Cycle(
        n,
        floats(P),
        p_def,
        floats(Lg),
        floats(ldef_i),
        k,
        t,
        ph,
        lc,
        ldef,
        floats(pos),
        floats(front),
        floats(new_pos),
        float(s_new),
        clearance,
    )
    return cycle, cm.frame_slide(rot, k, ph, step)
