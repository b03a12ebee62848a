"""Gait planning through a pipe by a beam search on the pressure grid (paper Section IV, Fig. 25).

The cycle model (rear foot fixed while inflating, front foot fixed and curvature kept while
deflating, eqs. 16-18), the deflation modes, the roll in an elbow and the pipe-fit check are those
of `analytic.cycle`; the result is a `analytic.gait.Plan`, and `replay` (re-exported here) runs a given
gait through the same model. By default (`planar=None`) the elbow search uses only the bend-plane
family P2 = P3 (2D pressure grid); straight pipes search all triples.

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
needs the beam (9 cycles, 5 kPa), and the exhaustive planar breadth-first search of `analytic.planar`
passes R = 60, 55, 50 mm in 10, 11, 14 cycles (10 kPa) but not 45 or 40 mm: at R = 40 it runs dry
with the rear foot at s = 118 mm (10 kPa) / 123 mm (5 kPa, 4.7 min), ~30 mm before the bend; with a
22 mm body instead of 23 mm it still does, with 21.5 mm it passes R = 40 in 13 cycles.
With continuous pressures, `analytic.refine.continuous_plan` (SLSQP on the ePSA lengths of a fixed
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
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from softcrawl.analytic import cycle as cm
from softcrawl.analytic import kinematics as kin
from softcrawl.analytic.errors import ModelInputError
from softcrawl.analytic.gait import Cycle, Plan, floats, replay, rotation_tuple
from softcrawl.analytic.limits import MAX_BEAM, MAX_CANDIDATES_PER_CYCLE, check
from softcrawl.analytic.pipe import Pipe
from softcrawl.analytic.prototype import BODY_RADIUS_MM, actuator_set
from softcrawl.analytic.statics import EPSAParams
from softcrawl.paper import D_MM

__all__ = ["Cycle", "Plan", "plan", "replay", "scan_bend_radius"]


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


@dataclass(frozen=True)
class _Successors:
    """The feasible, advancing successors of one state (arrays over the kept grid triples)."""

    idx: np.ndarray  # index in the pressure grid
    k: np.ndarray
    t: np.ndarray
    ph: np.ndarray
    lc: np.ndarray
    ldef: np.ndarray
    pos: np.ndarray  # rear foot after deflation
    rot: np.ndarray
    s: np.ndarray  # its arc length
    dn: np.ndarray  # its distance to the pipe centreline
    align: np.ndarray  # body axis . pipe tangent at the rear foot
    clr: np.ndarray  # wall clearance of the inflation
    L: np.ndarray  # inflated ePSA lengths


def _pose_cells(
    pipe: Pipe,
    pos: np.ndarray,
    rot: np.ndarray,
    progress: ArrayLike,
    cell_mm: float,
    cell_deg: float,
    cell_s_mm: float = np.inf,
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


@dataclass(frozen=True)
class _BeamSearch:
    """The cycle model and the search settings of one `plan` call."""

    pipe: Pipe
    acts: tuple[EPSAParams, ...]
    fit: cm.PipeFit
    d: float
    g: float
    samples: int
    deflation: str
    lam: np.ndarray  # inflation stage fractions
    grid: np.ndarray  # pressure triples, kPa
    L_grid: np.ndarray  # their lengths
    L_coarse: np.ndarray | None  # lengths of the lookahead grid
    beam: int
    cells: tuple[float, float, float]  # cell_mm, cell_deg, cell_s_mm
    lookahead: int
    lookahead_width: int

    def expand(self, st: _State, Lg: np.ndarray) -> _Successors:
        """Feasible, advancing successors of `st` over the length grid `Lg`."""
        pipe, d = self.pipe, self.d
        L, dist = self.fit.inflation_distances(st.pos, st.rot, st.l_cur, Lg, self.lam, d, self.samples)
        worst = dist.max(axis=(0, 2))
        idx = np.flatnonzero(self.fit.fits(worst))
        Lc = L[-1, idx]
        k, t, ph, lc = kin.forward(Lc, d)
        ldef = cm.deflated_length(self.acts, k, ph, d, self.g, self.deflation)
        step = np.maximum(lc - ldef, 0.0)
        new_pos = cm.rear_slide(st.pos, st.rot, k, ph, step)
        dn, sn = pipe.locate(new_pos)
        keep = sn > st.progress + 1e-6
        rot = cm.frame_slide(st.rot, k[keep], ph[keep], step[keep])
        align = np.einsum("mi,mi->m", rot[:, :, 2], pipe.tangent(sn[keep]))
        return _Successors(
            idx[keep],
            k[keep],
            t[keep],
            ph[keep],
            lc[keep],
            ldef[keep],
            new_pos[keep],
            rot,
            sn[keep],
            dn[keep],
            align,
            self.fit.clearance(worst[idx[keep]]),
            Lc[keep],
        )

    def successor(self, st: _State, e: _Successors, j: int) -> _State:
        """The deflated state after successor `j` of `st` (its cycles not yet recorded)."""
        k, ph, ldef = e.k[j], e.ph[j], e.ldef[j]
        ldef_i = cm.deflated_lengths(ldef, k, ph, self.d)
        p_def = cm.deflated_pressures(self.acts, ldef_i, self.g)
        return _State(
            e.pos[j], e.rot[j], p_def, ldef_i, float(k), float(ph), float(ldef), float(e.s[j]), st.cycles
        )

    def value(self, st: _State, depth: int, goal: float) -> float:
        """Best rear progress reachable from `st` in `depth` more cycles (coarse grid)."""
        if depth == 0 or st.progress >= goal:
            return st.progress
        e = self.expand(st, self.L_coarse)
        if e.s.size == 0:
            return st.progress
        order = np.argsort(-e.s)[: self.lookahead_width]
        return max(self.value(self.successor(st, e, j), depth - 1, goal) for j in order)

    def candidates(self, st: _State, goal: float) -> list[tuple]:
        """[((lookahead value, score), st, successors, j, new state)] of the picked successors of `st`.

        Picks: the best by score, plus (beam > 1) the furthest of every pose cell, plus
        (lookahead) the best three per bending direction.
        """
        e = self.expand(st, self.L_grid)
        if e.s.size == 0:
            return []
        score = e.s - 0.05 * e.dn - 2.0 * (1.0 - e.align)
        order = np.argsort(-score)
        picks = list(order[: max(self.beam, self.lookahead_width)])
        if self.beam > 1:
            cells = _pose_cells(self.pipe, e.pos, e.rot, e.s, *self.cells)
            _, first = np.unique(cells[np.argsort(-e.s, kind="stable")], axis=0, return_index=True)
            picks.extend(np.argsort(-e.s, kind="stable")[first])
        if self.lookahead > 0:
            bins = np.round(np.where(e.t > 1e-9, e.ph, 0.0) / (np.pi / 12)).astype(int)
            for b in np.unique(bins):
                members = order[np.isin(order, np.flatnonzero(bins == b))]
                picks.extend(members[:3])
        seen, out = set(), []
        for j in picks:
            if j in seen:
                continue
            seen.add(j)
            cand = self.successor(st, e, j)
            v = self.value(cand, self.lookahead, goal) if self.lookahead > 0 else 0.0
            out.append(((v, score[j]), st, e, j, cand))
        return out

    def select(self, pool: list[tuple]) -> list[_State]:
        """The next beam from the sorted pool: the best state per cell of offset and heading."""
        new_states, keys = [], set()
        for _key, st, e, j, cand in pool:
            if len(new_states) >= self.beam:
                break
            key = tuple(_pose_cells(self.pipe, cand.pos, cand.rot, cand.progress, *self.cells))
            if key in keys:
                continue  # keep the beam diverse
            keys.add(key)
            cand.cycles = st.cycles + [self.record(st, e, j, cand)]
            new_states.append(cand)
        return new_states

    def record(self, st: _State, e: _Successors, j: int, cand: _State) -> Cycle:
        """The cycle from `st` to `cand` (successor `j`)."""
        front = cm.front_foot(st.pos, st.rot, e.t[j], e.ph[j], e.lc[j])
        return Cycle(
            len(st.cycles) + 1,
            floats(self.grid[e.idx[j]]),
            floats(cand.p_def),
            floats(e.L[j]),
            floats(cand.l_cur),
            float(e.k[j]),
            float(e.t[j]),
            float(e.ph[j]),
            float(e.lc[j]),
            float(e.ldef[j]),
            floats(st.pos),
            floats(front),
            floats(cand.pos),
            float(cand.progress),
            float(e.clr[j]),
        )

    def run(self, start: _State, goal: float, max_cycles: int) -> tuple[_State, bool, str]:
        """(final state, success, message): cycles until the rear foot passes `goal`."""
        states = [start]
        best = start
        for _ in range(max_cycles):
            pool = [c for st in states for c in self.candidates(st, goal)]
            if not pool:
                return best, False, "no triple advances the robot"
            pool.sort(key=lambda x: (-x[0][0], -x[0][1]))
            states = self.select(pool)
            best = max(states, key=lambda s_: s_.progress)
            done = [s_ for s_ in states if s_.progress >= goal]
            if done:
                best = min(done, key=lambda s_: len(s_.cycles))
                return best, True, f"rear foot passed s = {goal:.1f} mm"
        return best, False, f"not through after {max_cycles} cycles"


def _start(
    acts: tuple[EPSAParams, ...], fit: cm.PipeFit, rot0: np.ndarray, d: float, g: float, samples: int
) -> _State:
    """The deflated robot (P = 0) at the pipe entrance, after checking that it fits there."""
    p0 = np.zeros(3)
    l0 = cm.epsa_lengths(acts, p0, g)
    k0, t0, f0, lc0 = kin.forward(l0, d)
    start = _State(np.zeros(3), rot0, p0, l0, float(k0), float(f0), float(lc0), 0.0)
    if not fit.fits(fit.distances(start.pos, start.rot, l0, d, samples).max()):
        raise ModelInputError("diameter", "the deflated robot does not fit the pipe at the start")
    return start


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
    fit = cm.PipeFit.of(pipe, body_radius, body, tol)
    beam = check(beam, "beam", minimum=1, maximum=MAX_BEAM, integer=True)
    cm.check_deflation(deflation)
    g = cm.gravity(pipe)
    if planar is None:
        planar = pipe.kind == "elbow"
    grid = cm.pressure_grid(step_kpa, planar)
    if beam * len(grid) > MAX_CANDIDATES_PER_CYCLE:
        raise ModelInputError(
            "beam",
            f"beam {beam} x {len(grid)} pressure triples (step {step_kpa:g} kPa) exceeds "
            f"{MAX_CANDIDATES_PER_CYCLE} candidates per cycle: use a coarser --step or a narrower --beam",
        )
    goal = pipe.goal()
    # Roll the robot so that ePSA 1 (psi = 90 deg, local +y) faces the inside of the bend (world +x):
    # bends in the bend plane are then the P2 = P3 family, as in the paper's gait 2.
    rot0 = cm.elbow_roll(pipe)

    start = _start(acts, fit, rot0, d, g, samples)
    coarse = cm.pressure_grid(lookahead_step_kpa, planar) if lookahead > 0 else None
    search = _BeamSearch(
        pipe,
        acts,
        fit,
        d,
        g,
        samples,
        deflation,
        cm.stage_fractions(stages),
        grid,
        cm.epsa_lengths(acts, grid, g),
        cm.epsa_lengths(acts, coarse, g) if lookahead > 0 else None,
        beam,
        (cell_mm, cell_deg, cell_s_mm),
        lookahead,
        lookahead_width,
    )
    final, success, message = search.run(start, goal, max_cycles)
    return Plan(
        pipe,
        success,
        tuple(final.cycles),
        fit.body_radius,
        d,
        actuators,
        step_kpa,
        body,
        floats(start.pos),
        floats(start.p_def),
        message,
        rotation_tuple(rot0),
    )


def scan_bend_radius(radii: ArrayLike, diameter: float = 70.0, **kwargs: object) -> list[tuple[float, Plan]]:
    """Plan an elbow for every bend radius in `radii` (mm); returns [(radius, plan)].

    Passability is not monotone in the radius for a rigid constant-curvature body: a sharp elbow
    leaves room to cut the corner with one long arc, a wider one does not (its inner wall is
    further out), so we scan rather than bisect.
    """
    return [(float(r), plan(Pipe("elbow", diameter, float(r)), **kwargs)) for r in radii]
