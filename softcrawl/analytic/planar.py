"""Exhaustive breadth-first gait search in the bend plane of an elbow (fewest cycles).

The cycle model of `analytic.cycle` (rear foot fixed while inflating, front foot fixed and curvature
kept while deflating, deflated centreline = the model's rest length as eq. 17, the body a 23 mm
tube that must stay in the pipe at every inflation stage), in its bend-plane form: the robot is
rolled so that ePSA 1 faces the inside of the bend and the pressure triples are (P1, P23, P23).
Then a state is the rear-foot pose (x, z, heading) plus the curvature kept from the last cycle, and
every cycle is a planar arc with signed curvature k (> 0 towards ePSA 1 / the bend):

    l1 = l_c (1 - k d),  l2 = l3 = l_c (1 + k d / 2),  l_c = (l1 + 2 l23)/3,  k = (1 - l1/l_c)/d.

Breadth first over cycles, with states merged on a grid of cells (`cell_mm`, `cell_deg`, and the kept
curvature to 5e-4 1/mm), so the first layer that reaches the goal gives the fewest cycles on that
discretisation. A layer larger than `max_states` keeps its furthest states (then the search is no
longer exhaustive; the result says so). Vectorised over states and candidate triples.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from softcrawl.analytic import cycle as cm
from softcrawl.analytic import kinematics as kin
from softcrawl.analytic.errors import ModelInputError
from softcrawl.analytic.gait import Cycle, Plan, floats, rotation_tuple
from softcrawl.analytic.pipe import Pipe
from softcrawl.analytic.prototype import BODY_RADIUS_MM, actuator_set
from softcrawl.analytic.statics import EPSAParams
from softcrawl.paper import D_MM

#: Curvature resolution of the state cells, 1/mm.
_CELL_KAPPA = 5e-4


@dataclass(frozen=True)
class _PlanarModel:
    """The bend-plane cycle model on a pressure grid (P1, P23, P23); arrays over the grid."""

    pipe: Pipe
    acts: tuple[EPSAParams, ...]
    fit: cm.PipeFit
    d: float
    grid: np.ndarray  # triples, kPa
    l1: np.ndarray  # inflated lengths
    l23: np.ndarray
    rest: float  # deflated centreline length
    k: np.ndarray  # signed curvature of the inflated arc
    lc: np.ndarray  # its centreline length
    stride: np.ndarray  # lc - rest: the rear foot's slide
    lam: np.ndarray  # inflation stage fractions
    f: np.ndarray  # sample fractions along the arc

    @classmethod
    def build(
        cls,
        pipe: Pipe,
        acts: tuple[EPSAParams, ...],
        fit: cm.PipeFit,
        d: float,
        step_kpa: float,
        stages: int,
        samples: int,
    ) -> _PlanarModel:
        grid = cm.pressure_grid(step_kpa, planar=True)
        l1 = acts[0].length(grid[:, 0], 0.0)
        l23 = acts[1].length(grid[:, 1], 0.0)
        rest1, rest23 = float(acts[0].length(0.0, 0.0)), float(acts[1].length(0.0, 0.0))
        rest = (rest1 + 2.0 * rest23) / 3.0
        k, lc = cm.planar_configuration(l1, l23, d)
        f = np.linspace(0.0, 1.0, samples)
        return cls(pipe, acts, fit, d, grid, l1, l23, rest, k, lc, lc - rest, cm.stage_fractions(stages), f)

    def successors(self, states: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Successors (m, 4) of `states` (S, 4) = (x, z, heading, kept curvature) that fit and advance.

        Returns them with the index of their parent state and of their grid triple.
        """
        x, z, al, kd = (states[:, i][:, None, None] for i in range(4))
        # deflated lengths of the kept curvature -> target lengths, linear in the stages
        l1d, l23d = cm.planar_deflated_lengths(self.rest, kd, self.d)
        L1 = cm.inflation_lengths(l1d, self.l1[None, :, None], self.lam[None, None, :])
        L23 = cm.inflation_lengths(l23d, self.l23[None, :, None], self.lam[None, None, :])
        dist = self.fit.planar_distances(x, z, al, L1, L23, self.d, self.f)  # (S, C, stages, n)
        ok = self.fit.fits(dist.max(axis=(2, 3)))  # (S, C)
        si, ci = np.nonzero(ok & (self.stride[None, :] > 1e-6))
        nx, nz, na = cm.planar_slide(states[si, 0], states[si, 1], states[si, 2], self.k[ci], self.stride[ci])
        return np.stack([nx, nz, na, self.k[ci]], -1), si, ci

    def cycle(
        self, n: int, prev: np.ndarray, state: np.ndarray, c: int, rot: np.ndarray
    ) -> tuple[Cycle, np.ndarray]:
        """Cycle `n` from the state `prev` to `state` by grid triple `c`; the rear frame after it."""
        pipe, d, f = self.pipe, self.d, self.f
        kk, lc, st = float(self.k[c]), float(self.lc[c]), float(self.stride[c])
        phi = np.pi / 2 if kk >= 0 else -np.pi / 2
        rear = np.array([prev[0], 0.0, prev[1]])
        lat, ax = kin.planar_arc(kk, lc)
        front = rear + np.array(
            [np.cos(prev[2]) * lat + np.sin(prev[2]) * ax, 0.0, -np.sin(prev[2]) * lat + np.cos(prev[2]) * ax]
        )
        ldef = cm.deflated_lengths(self.rest, abs(kk), phi, d)
        p_def = floats(cm.deflated_pressures(self.acts, ldef, 0.0))
        _, s_after = pipe.locate(np.array([state[0], 0.0, state[1]]))
        pts = rear + kin.arc_point(abs(kk) * lc * f, phi, lc * f) @ rot.T
        dist, _ = pipe.locate(pts)
        cyc = Cycle(
            n,
            floats(self.grid[c]),
            p_def,
            (float(self.l1[c]), float(self.l23[c]), float(self.l23[c])),
            floats(ldef),
            abs(kk),
            abs(kk) * lc,
            phi,
            lc,
            self.rest,
            floats(rear),
            floats(front),
            (float(state[0]), 0.0, float(state[1])),
            float(s_after),
            float(self.fit.clearance(dist.max())),
        )
        return cyc, cm.frame_slide(rot, abs(kk), phi, st)


def bfs_plan(
    pipe: Pipe,
    actuators: str = "nominal",
    step_kpa: float = 10.0,
    body_radius: float = BODY_RADIUS_MM,
    d: float = D_MM,
    max_cycles: int = 40,
    stages: int = 4,
    samples: int = 21,
    cell_mm: float = 1.0,
    cell_deg: float = 1.0,
    max_states: int = 20000,
    chunk: int = 40,
    progress: Callable[[str], None] | None = None,
) -> Plan:
    """Fewest-cycle gait through the elbow `pipe` on the bend-plane grid; see the module docstring.
    `progress`, if given, is called with one line per cycle of the search (it can take minutes)."""
    if pipe.kind != "elbow":
        raise ModelInputError("pipe", "the planar search is for elbows")
    acts = actuator_set(actuators)
    if acts[1] != acts[2]:
        raise ModelInputError("actuators", "the planar search needs identical ePSAs 2 and 3")
    fit = cm.PipeFit.of(pipe, body_radius)
    model = _PlanarModel.build(pipe, acts, fit, d, step_kpa, stages, samples)
    goal = pipe.goal()
    # state columns: x, z, heading alpha, kept curvature k
    layers = [np.zeros((1, 4))]
    parents: list[np.ndarray] = [np.array([-1])]
    cands: list[np.ndarray] = [np.array([-1])]
    seen: set = set()
    exhaustive, success = True, False
    for _ in range(max_cycles):
        cur = layers[-1]
        parts = [model.successors(cur[i : i + chunk]) for i in range(0, len(cur), chunk)]
        new = np.concatenate([p[0] for p in parts]) if parts else np.zeros((0, 4))
        if len(new) == 0:
            break
        par = np.concatenate([i + p[1] for i, p in zip(range(0, len(cur), chunk), parts)])
        cnd = np.concatenate([p[2] for p in parts])
        _, s_new = pipe.locate(np.stack([new[:, 0], np.zeros(len(new)), new[:, 1]], -1))
        idx = _new_cells(new, s_new, seen, cell_mm, cell_deg)
        if idx.size == 0:
            break
        if idx.size > max_states:
            idx, exhaustive = idx[:max_states], False
        layers.append(new[idx])
        parents.append(par[idx])
        cands.append(cnd[idx])
        if progress is not None:
            progress(
                f"cycle {len(layers) - 1}: {idx.size} new states, "
                f"furthest {s_new[idx[0]]:.0f} of {goal:.0f} mm"
            )
        if s_new[idx[0]] >= goal:
            success = True
            break
    cycles = _furthest_path(model, layers, parents, cands)
    msg = f"rear foot passed s = {goal:.1f} mm" if success else "no triple advances the robot"
    if not exhaustive:
        msg += f" (layers capped at {max_states} states: not exhaustive)"
    return Plan(
        pipe,
        success,
        tuple(cycles),
        body_radius,
        d,
        actuators,
        step_kpa,
        "tube",
        (0.0, 0.0, 0.0),
        (0.0, 0.0, 0.0),
        msg,
        rotation_tuple(cm.elbow_roll(pipe)),
    )


def _new_cells(new: np.ndarray, s_new: np.ndarray, seen: set, cell_mm: float, cell_deg: float) -> np.ndarray:
    """Indices of the furthest state of every cell not `seen` before (added to it), furthest first."""
    cells = (
        np.stack(
            [
                new[:, 0] / cell_mm,
                new[:, 1] / cell_mm,
                np.rad2deg(new[:, 2]) / cell_deg,
                new[:, 3] / _CELL_KAPPA,
            ],
            -1,
        )
        .round()
        .astype(int)
    )
    order = np.argsort(-s_new, kind="stable")  # furthest first within a cell
    _, first = np.unique(cells[order], axis=0, return_index=True)
    idx = order[first]
    idx = np.array([i for i in idx if tuple(cells[i]) not in seen], dtype=int)
    for i in idx:
        seen.add(tuple(cells[i]))
    return idx[np.argsort(-s_new[idx], kind="stable")]


def _furthest_path(
    model: _PlanarModel, layers: list[np.ndarray], parents: list[np.ndarray], cands: list[np.ndarray]
) -> list[Cycle]:
    """The cycles that lead to the furthest state of the last layer (its first)."""
    chain = []
    j = 0
    for li in range(len(layers) - 1, 0, -1):
        chain.append((li, j))
        j = parents[li][j]
    chain.reverse()
    cycles = []
    rot = cm.elbow_roll(model.pipe)
    for n, (li, j) in enumerate(chain, start=1):
        cyc, rot = model.cycle(n, layers[li - 1][parents[li][j]], layers[li][j], cands[li][j], rot)
        cycles.append(cyc)
    return cycles
