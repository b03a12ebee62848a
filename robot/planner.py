"""Gait planning through a pipe (paper Section IV, eqs. 16-18, Fig. 25).

Model of one crawling cycle (assumption (c) of Section III-C and Fig. 4):

1. Inflation, rear foot fixed. The pressures go linearly from the deflated triple to the inflated
   triple P, whose ePSA lengths come from the statics model (eq. 3); each stage is a
   constant-curvature arc (eqs. 4-6) posed from the rear foot frame (eq. 9).
2. Deflation, front foot fixed, curvature kept (eqs. 16, 18: kappa_2 = kappa_1, phi_2 = phi_1). The
   body shrinks along its own arc to the deflated centreline length l_def, so the rear foot slides
   along the inflated arc by (l_c - l_def), i.e. through the angle theta_2 = (l_c - l_def) kappa
   (eq. 17; the paper writes (l_1 - 100) kappa).

Deflated length, two modes (`deflation=`):

* "paper" (default): eq. (17) as printed, the deflated centreline has the rest length whatever the
  curvature. We use the model's P = 0 centreline length, mean_i l_i(0) (99.25 mm for the nominal
  actuator), instead of the printed 100 mm so that a straight robot deflates to exactly P = 0.
  The deflated ePSA lengths l_i = l_def (1 - kappa d cos(psi_i - phi)) then put the inner ePSA below
  its rest length: it is fully vented (0 kPa) and the kept curvature is the paper's assumption
  (the pipe and the anchored front foot hold it), while ePSAs above their rest length keep the
  pressure that the inverted statics model gives (the paper's gait 2, "deflated but not fully").
* "held": no ePSA may go below its rest length, so the curvature is held by pressure alone:
  l_def = max_i l_i(0) / (1 - kappa d cos(psi_i - phi)). Bent bodies then stay long after
  deflation and the stride in a bend is much shorter.

Deflated triples invert the statics model (`EPSAParams.pressure_for_length`: smallest pressure on
the monotone branch; a length inside an upward 60 kPa gap -> 60 kPa; lengths below rest -> 0 kPa).
During inflation the ePSA lengths go linearly from the deflated lengths to the statics lengths of
the inflated triple (the shape path between two static states is not modelled by the paper).

Constraint: with `body="tube"` (default) the body is a tube of radius `body_radius` (d + R0 = 23 mm,
half the prototype's 46 mm minimum diameter; the feet, 78 mm, deform and are not checked) around
the arc, so every sampled arc point of every inflation stage must lie within D/2 - 23 = 12 mm of the
pipe centreline (70 mm pipe). With `body="epsa"` only the three ePSA tubes (R0 = 9 mm around their
own centrelines at d = 14 mm) are checked; this ignores the connecting rings. Deflated bodies are
sub-arcs of the inflated one, hence inside as well.

Roll. In an elbow the robot is inserted with ePSA 1 (psi = 90 deg) facing the inside of the bend, so
bends in the bend plane are the family P2 = P3, P1 lower (the paper's gait 2: "ePSA2 and ePSA3 are
inflated for 1.5 s, ePSA1 for 0.3 s"). By default (`planar=None`) the elbow search uses only this
family (2D pressure grid); straight pipes search all triples.

Search. The inflated triple of each cycle is chosen on a pressure grid (0-100 kPa, `step_kpa`)
by forward statics, so commanded pressures and the predicted shapes are consistent also across the
60 kPa jump. A beam search over cycles (`beam` states kept per cycle; 1 = greedy) keeps, per cell of
lateral offset, heading and coarse progress (`cell_mm`, `cell_deg`, `cell_s_mm`), the state whose
rear foot went furthest, and ranks by rear-foot progress with a small preference for a centred,
pipe-aligned rear foot. Breadth per cycle means the first plan through uses the fewest cycles among
the states kept. The plan ends when the rear foot passes the goal (pipe end, or end of the bend), or
fails (reported, not raised) when no triple advances the robot.

Limits found (see the package report): a straight or vertical pipe is crossed with (100, 100, 100)
/ (0, 0, 0) in ceil(L / 54 mm) cycles. In an elbow the 70 mm pipe leaves the 23 mm-radius body a
12 mm corridor, and near a tight bend the gaits that pass are thinner than a pressure grid (a
10 kPa step moves an ePSA by 2-10 mm). On the grid: R = 80 mm passes greedily in 7 cycles (10 kPa), R = 60 mm
needs the beam (9 cycles, 5 kPa), and the exhaustive planar breadth-first search of `robot.planar`
passes R = 60, 55, 50 mm in 10, 11, 14 cycles (10 kPa) but not 45 or 40 mm: at R = 40 it runs dry
with the rear foot at s = 118 mm (10 kPa) / 123 mm (5 kPa, 4.7 min), ~30 mm before the bend; with a
22 mm body instead of 23 mm it still does, with 21.5 mm it passes R = 40 in 13 cycles.
With continuous pressures, `robot.refine.continuous_plan` (SLSQP on the ePSA lengths of a fixed
number of cycles, maximising the wall clearance, replayed through this cycle model) passes
R = 40 mm: 25 cycles from a straight seed in ~8 s, stopping at 0.045 mm of clearance to spare
(maximised: 0.066 mm with 25 cycles, 0.096 mm with 29; 0.054 / 0.084 mm on a 64-stage x 161-sample
check of the inflation path); straight seeds of 23-28 cycles pass too. R = 45 and 50 mm pass with
0.75 and 1.42 mm to spare (25 cycles, maximised), 60 and 80 mm as well. It does not find
R = 39 mm (best -0.034 mm, i.e. the body 34 um into the wall, 30 cycles), 38.2 mm (-0.19 mm) or
37 mm (-0.35 mm): the smallest radius passed is 40 mm, by a hair. (SLSQP is a local method: 39 mm
is not proven impossible.) The manoeuvre is an S:
the first cycles bend slightly away from the elbow (P1 > P2 = P3), which puts the rear foot ~4.5 mm
towards the outer wall and tilts it ~4 deg away from the bend by s ~ 60-100 mm; then the curvature
grows cycle by cycle (P1 -> 0) and the last strides cut the corner. No single-arc argument rules
the tight bends out: at every rear-foot position along an R = 40 mm elbow some arc of the deflated
length (99.25 mm) with a curvature the actuators reach fits with ~9 mm to spare; what limits the
robot is reaching the rear-foot offsets and headings that such arcs need, cycle after cycle.
The paper's 38.2 mm minimum turning radius belongs to a soft body that the pipe deforms, which this
model does not have; its own smallest body bending radius is 45.1 mm (prototype ePSAs, `softcrawl
model workspace`).

Gravity: only the "vertical" pipe applies g along the body axis (climbing). Straight and elbow plans
are made without gravity, as the paper's kinematics are (assumption (d)).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from robot import kinematics as kin
from robot.errors import ModelInputError
from robot.pipe import Pipe
from robot.prototype import BODY_RADIUS_MM, D_MM, EPSA_RADIUS_MM, actuator_set
from robot.statics import G_STANDARD, P_MAX_KPA, EPSAParams


@dataclass(frozen=True)
class Cycle:
    index: int
    pressures_inflated: tuple[float, float, float]  # kPa
    pressures_deflated: tuple[float, float, float]  # kPa, held after deflation
    lengths_inflated: tuple[float, float, float]  # mm
    lengths_deflated: tuple[float, float, float]  # mm
    kappa: float
    theta: float
    phi: float
    length_inflated: float  # centreline, mm
    length_deflated: float
    rear_before: tuple[float, float, float]
    front: tuple[float, float, float]  # front foot, fixed during deflation
    rear_after: tuple[float, float, float]
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
    start_rear: tuple[float, float, float]
    start_pressures: tuple[float, float, float]
    message: str = ""
    start_rotation: tuple = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))

    def gait(self):
        """[(phase, P1, P2, P3)] kPa: 'inflate', 'deflate' per cycle."""
        out = []
        for c in self.cycles:
            out.append(("inflate",) + c.pressures_inflated)
            out.append(("deflate",) + c.pressures_deflated)
        return out


@dataclass
class _State:
    pos: np.ndarray
    rot: np.ndarray
    p_def: np.ndarray
    l_cur: np.ndarray
    kappa: float
    phi: float
    l_def: float
    progress: float
    cycles: list = field(default_factory=list)


def _pose_cells(
    pipe: Pipe, pos, rot, progress, cell_mm: float, cell_deg: float, cell_s_mm: float = np.inf
) -> np.ndarray:
    """Cells (m, 4) of the rear feet's lateral offsets and headings relative to the pipe.

    The progress along the pipe enters only coarsely (`cell_s_mm`): per cell, the beam keeps the
    state that went furthest, and near a bend a state a little behind can be the better one.
    """
    c = pipe.point(progress)
    t = pipe.tangent(progress)
    n = np.stack([t[..., 2], np.zeros_like(t[..., 0]), -t[..., 0]], -1)
    off = pos - c
    head = rot[..., :, 2]
    h = np.sin(np.deg2rad(cell_deg))
    cells = np.stack(
        [
            np.einsum("...i,...i->...", off, n) / cell_mm,
            off[..., 1] / cell_mm,
            np.einsum("...i,...i->...", head, n) / h,
            head[..., 1] / h,
            np.asarray(progress) / cell_s_mm,
        ],
        -1,
    )
    return np.round(cells).astype(int)


def _pressure_grid(step_kpa: float, planar: bool = False) -> np.ndarray:
    """All triples on a `step_kpa` grid, or only P2 = P3 (bending in the plane of ePSA 1)."""
    n = int(round(P_MAX_KPA / step_kpa))
    if n < 1 or abs(n * step_kpa - P_MAX_KPA) > 1e-9:
        raise ModelInputError("step", f"must divide {P_MAX_KPA:g} kPa, got {step_kpa:g}")
    v = np.linspace(0.0, P_MAX_KPA, n + 1)
    if planar:
        a, b = np.meshgrid(v, v, indexing="ij")
        return np.stack([a.ravel(), b.ravel(), b.ravel()], -1)
    return np.stack(np.meshgrid(v, v, v, indexing="ij"), -1).reshape(-1, 3)


def _lengths(acts, P, g):
    return np.stack([acts[i].length(P[..., i], g) for i in range(3)], -1)


def _body_points(pos, rot, lengths, d, n_s, epsa: bool = False):
    """World points of the body arcs with the given ePSA lengths, posed from the rear foot.

    (..., n_s, 3) on the body centreline, or with `epsa` (..., 3 * n_s, 3) on the three ePSA
    centrelines (offset d at psi_i in the cross-section frame, which follows the arc by eq. 9).
    """
    k, t, p, lc = kin.forward(lengths, d)
    f = np.linspace(0.0, 1.0, n_s)
    local = kin.arc_point(t[..., None] * f, p[..., None], lc[..., None] * f)
    if epsa:
        frames = kin.arc_rotation(t[..., None] * f, p[..., None])  # (..., n_s, 3, 3)
        offs = d * np.stack([np.cos(kin.PSI), np.sin(kin.PSI), np.zeros(3)], -1)  # (3, 3)
        local = local[..., None, :] + np.einsum("...ij,aj->...ai", frames, offs)
        local = local.reshape(local.shape[:-3] + (-1, 3))
    return pos + local @ rot.T


def _deflated_length(acts, kappa, phi, d, g, mode):
    rest = np.array([float(a.length(0.0, g)) for a in acts])
    if mode == "paper":
        return np.full(np.shape(kappa), rest.mean())
    c = 1.0 - np.asarray(kappa)[..., None] * d * np.cos(kin.PSI - np.asarray(phi)[..., None])
    return np.max(rest / c, axis=-1)


def _deflated_pressure(a: EPSAParams, length, g):
    if length <= float(a.length(0.0, g)) + 1e-12:
        return 0.0
    return a.pressure_for_length(length, g)


def _elbow_roll(pipe: Pipe) -> np.ndarray:
    """Roll ePSA 1 (psi = 90 deg, local +y) to the inside of an elbow's bend (world +x)."""
    if pipe.kind == "elbow":
        return np.array([[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    return np.eye(3)


def _body_allowance(pipe: Pipe, body: str, body_radius: float):
    """(ePSA-only body?, body radius, allowed centreline offset D/2 - radius) after checking them."""
    if body not in ("tube", "epsa"):
        raise ModelInputError("body", f"must be 'tube' or 'epsa', got {body!r}")
    epsa_body = body == "epsa"
    if epsa_body:
        body_radius = EPSA_RADIUS_MM
    allow = pipe.diameter / 2.0 - body_radius
    if allow < 0:
        raise ModelInputError(
            "diameter", f"a {2 * body_radius:g} mm body does not fit a {pipe.diameter:g} mm pipe"
        )
    return epsa_body, body_radius, allow


def plan(
    pipe: Pipe,
    actuators: str = "nominal",
    step_kpa: float = 5.0,
    beam: int = 1,
    body_radius: float = BODY_RADIUS_MM,
    d: float = D_MM,
    max_cycles: int = 60,
    stages: int = 4,
    samples: int = 21,
    tol: float = 1e-9,
    deflation: str = "paper",
    body: str = "tube",
    planar: bool | None = None,
    cell_mm: float = 3.0,
    cell_deg: float = 4.0,
    cell_s_mm: float = 10.0,
    lookahead: int = 0,
    lookahead_step_kpa: float = 20.0,
    lookahead_width: int = 12,
) -> Plan:
    """Plan the fewest-cycle gait through `pipe`; see the module docstring.

    `lookahead` > 0 ranks candidates by the best progress reachable `lookahead` cycles later on a
    coarse grid (`lookahead_step_kpa`, `lookahead_width` branches); it did not help in the elbows
    we tried and is off by default.
    """
    acts: tuple[EPSAParams, ...] = actuator_set(actuators)
    if body_radius <= 0:
        raise ModelInputError("body-radius", "must be > 0 mm")
    epsa_body, body_radius, allow = _body_allowance(pipe, body, body_radius)
    if beam < 1:
        raise ModelInputError("beam", "must be >= 1")
    if deflation not in ("paper", "held"):
        raise ModelInputError("deflation", f"must be 'paper' or 'held', got {deflation!r}")
    g = G_STANDARD if pipe.kind == "vertical" else 0.0
    if planar is None:
        planar = pipe.kind == "elbow"
    grid = _pressure_grid(step_kpa, planar)
    goal = pipe.goal()
    # Roll the robot so that ePSA 1 (psi = 90 deg, local +y) faces the inside of the bend (world +x):
    # bends in the bend plane are then the P2 = P3 family, as in the paper's gait 2.
    rot0 = _elbow_roll(pipe)

    p0 = np.zeros(3)
    l0 = _lengths(acts, p0, g)
    k0, t0, f0, lc0 = kin.forward(l0, d)
    start = _State(np.zeros(3), rot0, p0, l0, float(k0), float(f0), float(lc0), 0.0)
    d0, _ = pipe.locate(_body_points(start.pos, start.rot, l0, d, samples, epsa_body))
    if d0.max() > allow + tol:
        raise ModelInputError("diameter", "the deflated robot does not fit the pipe at the start")

    lam = np.linspace(0.0, 1.0, stages + 1)[1:]
    L_grid = _lengths(acts, grid, g)
    coarse = _pressure_grid(lookahead_step_kpa, planar) if lookahead > 0 else None
    L_coarse = _lengths(acts, coarse, g) if lookahead > 0 else None

    def expand(st, Lg):
        """Feasible, advancing successors of `st` over the length grid `Lg`."""
        L = st.l_cur + lam[:, None, None] * (Lg[None] - st.l_cur)  # (stages, n, 3)
        pts = _body_points(st.pos, st.rot, L, d, samples, epsa_body)  # (stages, n, s, 3)
        dist, _ = pipe.locate(pts)
        worst = dist.max(axis=(0, 2))
        idx = np.flatnonzero(worst <= allow + tol)
        Lc = L[-1, idx]
        k, t, ph, lc = kin.forward(Lc, d)
        ldef = _deflated_length(acts, k, ph, d, g, deflation)
        step = np.maximum(lc - ldef, 0.0)
        new_pos = st.pos + kin.arc_point(k * step, ph, step) @ st.rot.T
        dn, sn = pipe.locate(new_pos)
        keep = sn > st.progress + 1e-6
        rot = st.rot @ kin.arc_rotation(k[keep] * step[keep], ph[keep])
        align = np.einsum("mi,mi->m", rot[:, :, 2], pipe.tangent(sn[keep]))
        return dict(
            idx=idx[keep],
            k=k[keep],
            t=t[keep],
            ph=ph[keep],
            lc=lc[keep],
            ldef=ldef[keep],
            pos=new_pos[keep],
            rot=rot,
            s=sn[keep],
            dn=dn[keep],
            align=align,
            clr=allow - worst[idx[keep]],
            L=Lc[keep],
        )

    def make_state(st, e, j):
        k, ph, ldef = e["k"][j], e["ph"][j], e["ldef"][j]
        ldef_i = ldef * (1.0 - k * d * np.cos(kin.PSI - ph))
        p_def = np.array([_deflated_pressure(acts[i], ldef_i[i], g) for i in range(3)])
        return _State(
            e["pos"][j],
            e["rot"][j],
            p_def,
            ldef_i,
            float(k),
            float(ph),
            float(ldef),
            float(e["s"][j]),
            st.cycles,
        )

    def value(st, depth):
        """Best rear progress reachable from `st` in `depth` more cycles (coarse grid)."""
        if depth == 0 or st.progress >= goal:
            return st.progress
        e = expand(st, L_coarse)
        if e["s"].size == 0:
            return st.progress
        order = np.argsort(-e["s"])[:lookahead_width]
        return max(value(make_state(st, e, j), depth - 1) for j in order)

    states = [start]
    message = "no triple advances the robot"
    success = False
    best_final = start
    for _ in range(max_cycles):
        pool = []
        for st in states:
            e = expand(st, L_grid)
            if e["s"].size == 0:
                continue
            score = e["s"] - 0.05 * e["dn"] - 2.0 * (1.0 - e["align"])
            order = np.argsort(-score)
            # keep a spread of candidates: the best by score, and the best per bending direction
            picks = list(order[: max(beam, lookahead_width)])
            if beam > 1:  # plus the furthest candidate of every pose cell
                cells = _pose_cells(pipe, e["pos"], e["rot"], e["s"], cell_mm, cell_deg, cell_s_mm)
                _, first = np.unique(cells[np.argsort(-e["s"], kind="stable")], axis=0, return_index=True)
                picks.extend(np.argsort(-e["s"], kind="stable")[first])
            if lookahead > 0:
                bins = np.round(np.where(e["t"] > 1e-9, e["ph"], 0.0) / (np.pi / 12)).astype(int)
                for b in np.unique(bins):
                    members = order[np.isin(order, np.flatnonzero(bins == b))]
                    picks.extend(members[:3])
            seen = set()
            for j in picks:
                if j in seen:
                    continue
                seen.add(j)
                cand = make_state(st, e, j)
                v = value(cand, lookahead) if lookahead > 0 else 0.0
                pool.append(((v, score[j]), st, e, j, cand))
        if not pool:
            break
        pool.sort(key=lambda x: (-x[0][0], -x[0][1]))
        new_states, keys = [], set()
        for _key, st, e, j, cand in pool:
            if len(new_states) >= beam:
                break
            key = tuple(_pose_cells(pipe, cand.pos, cand.rot, cand.progress, cell_mm, cell_deg, cell_s_mm))
            if key in keys:
                continue  # keep the beam diverse: the best state per cell of offset and heading
            keys.add(key)
            gi = e["idx"][j]
            front = st.pos + st.rot @ kin.arc_point(e["t"][j], e["ph"][j], e["lc"][j])
            cyc = Cycle(
                len(st.cycles) + 1,
                tuple(map(float, grid[gi])),
                tuple(map(float, cand.p_def)),
                tuple(map(float, e["L"][j])),
                tuple(map(float, cand.l_cur)),
                float(e["k"][j]),
                float(e["t"][j]),
                float(e["ph"][j]),
                float(e["lc"][j]),
                float(e["ldef"][j]),
                tuple(map(float, st.pos)),
                tuple(map(float, front)),
                tuple(map(float, cand.pos)),
                float(cand.progress),
                float(e["clr"][j]),
            )
            cand.cycles = st.cycles + [cyc]
            new_states.append(cand)
        states = new_states
        best_final = max(states, key=lambda s_: s_.progress)
        done = [s_ for s_ in states if s_.progress >= goal]
        if done:
            best_final = min(done, key=lambda s_: len(s_.cycles))
            success, message = True, f"rear foot passed s = {goal:.1f} mm"
            break
    else:
        message = f"not through after {max_cycles} cycles"
    return Plan(
        pipe,
        success,
        tuple(best_final.cycles),
        body_radius,
        d,
        actuators,
        step_kpa,
        body,
        tuple(map(float, start.pos)),
        tuple(map(float, p0)),
        message,
        tuple(tuple(map(float, r)) for r in rot0),
    )


def replay(
    pipe: Pipe,
    triples,
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
    """Run a given gait (inflated triples, kPa) through the cycle model of `plan`.

    Same statics, roll, inflation stages, containment check and deflation as `plan`; the gait is
    not searched but checked: the plan stops, unsuccessful, at the first cycle whose body leaves
    the pipe (its message says by how much) and succeeds when the rear foot passes the goal.
    `step_kpa` is only recorded (0 = continuous pressures).
    """
    acts: tuple[EPSAParams, ...] = actuator_set(actuators)
    if deflation not in ("paper", "held"):
        raise ModelInputError("deflation", f"must be 'paper' or 'held', got {deflation!r}")
    epsa_body, body_radius, allow = _body_allowance(pipe, body, body_radius)
    triples = np.asarray(triples, dtype=float).reshape(-1, 3)
    if np.any(~np.isfinite(triples)) or np.any(triples < 0) or np.any(triples > P_MAX_KPA + 1e-9):
        raise ModelInputError("pressure", f"pressures must be in [0, {P_MAX_KPA:g}] kPa")
    g = G_STANDARD if pipe.kind == "vertical" else 0.0
    goal = pipe.goal()
    rot0 = _elbow_roll(pipe)
    lam = np.linspace(0.0, 1.0, stages + 1)[1:]
    pos, rot = np.zeros(3), rot0.copy()
    l_cur = _lengths(acts, np.zeros(3), g)
    progress, cycles, success = 0.0, [], False
    message = f"gait of {len(triples)} cycles ends before s = {goal:.1f} mm"
    for n, P in enumerate(triples, start=1):
        Lg = _lengths(acts, P, g)
        L = l_cur + lam[:, None] * (Lg - l_cur)
        dist, _ = pipe.locate(_body_points(pos, rot, L, d, samples, epsa_body))
        worst = float(dist.max())
        if worst > allow + tol:
            message = f"cycle {n} leaves the pipe by {worst - allow:.4f} mm"
            break
        k, t, ph, lc = (float(v) for v in kin.forward(Lg, d))
        ldef = float(_deflated_length(acts, k, ph, d, g, deflation))
        step = max(lc - ldef, 0.0)
        new_pos = pos + kin.arc_point(k * step, ph, step) @ rot.T
        _, s_new = pipe.locate(new_pos)
        ldef_i = ldef * (1.0 - k * d * np.cos(kin.PSI - ph))
        p_def = tuple(float(_deflated_pressure(acts[i], ldef_i[i], g)) for i in range(3))
        front = pos + rot @ kin.arc_point(t, ph, lc)
        progress = float(s_new)
        cycles.append(
            Cycle(
                n,
                tuple(map(float, P)),
                p_def,
                tuple(map(float, Lg)),
                tuple(map(float, ldef_i)),
                k,
                t,
                ph,
                lc,
                ldef,
                tuple(map(float, pos)),
                tuple(map(float, front)),
                tuple(map(float, new_pos)),
                progress,
                allow - worst,
            )
        )
        pos, rot, l_cur = new_pos, rot @ kin.arc_rotation(k * step, ph), ldef_i
        if progress >= goal:
            success, message = True, f"rear foot passed s = {goal:.1f} mm"
            break
    return Plan(
        pipe,
        success,
        tuple(cycles),
        body_radius,
        d,
        actuators,
        step_kpa,
        body,
        (0.0, 0.0, 0.0),
        (0.0, 0.0, 0.0),
        message,
        tuple(tuple(map(float, r)) for r in rot0),
    )


def scan_bend_radius(radii, diameter: float = 70.0, **kwargs) -> list[tuple[float, Plan]]:
    """Plan an elbow for every bend radius in `radii` (mm); returns [(radius, plan)].

    Passability is not monotone in the radius for a rigid constant-curvature body: a sharp elbow
    leaves room to cut the corner with one long arc, a wider one does not (its inner wall is
    further out), so we scan rather than bisect.
    """
    return [(float(r), plan(Pipe("elbow", diameter, float(r)), **kwargs)) for r in radii]
