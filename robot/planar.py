"""Exhaustive breadth-first gait search in the bend plane of an elbow (fewest cycles).

Same cycle model as `robot.planner` (rear foot fixed while inflating, front foot fixed and
curvature kept while deflating, deflated centreline = the model's rest length as eq. 17, the body a
23 mm tube that must stay in the pipe at every inflation stage), restricted to the plane of the
bend: the robot is rolled so that ePSA 1 faces the inside of the bend and the pressure triples are
(P1, P23, P23). Then a state is the rear-foot pose (x, z, heading) plus the curvature kept from the
last cycle, and every cycle is a planar arc with signed curvature k (> 0 towards ePSA 1 / the bend):

    l1 = l_c (1 - k d),  l2 = l3 = l_c (1 + k d / 2),  l_c = (l1 + 2 l23)/3,  k = (1 - l1/l_c)/d.

Breadth first over cycles, with states merged on a grid of cells (`cell_mm`, `cell_deg`, and the kept
curvature to 5e-4 1/mm), so the first layer that reaches the goal gives the fewest cycles on that
discretisation. A layer larger than `max_states` keeps its furthest states (then the search is no
longer exhaustive; the result says so). Vectorised over states and candidate triples.
"""

from __future__ import annotations

import numpy as np

from robot import kinematics as kin
from robot.errors import ModelInputError
from robot.pipe import Pipe
from robot.planner import Cycle, Plan, _deflated_pressure, _pressure_grid
from robot.prototype import BODY_RADIUS_MM, D_MM, actuator_set

_ROT0 = np.array([[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])


def _arc(k, u):
    """Lateral and axial offsets of a planar arc of signed curvature k at arc length u."""
    th = k * u
    return u * kin._versinc(np.abs(th)) * np.sign(k), u * kin._sinc(th)


def _planar(l1, l23, d):
    lc = (l1 + 2.0 * l23) / 3.0
    return (1.0 - l1 / lc) / d, lc


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
    progress=None,
) -> Plan:
    """Breadth-first search over the planar gait (module docstring). `progress`, if given, is
    called with one line per cycle of the search (it can take minutes)."""
    if pipe.kind != "elbow":
        raise ModelInputError("pipe", "the planar search is for elbows")
    acts = actuator_set(actuators)
    if acts[1] != acts[2]:
        raise ModelInputError("actuators", "the planar search needs identical ePSAs 2 and 3")
    allow = pipe.diameter / 2.0 - body_radius
    if allow < 0:
        raise ModelInputError(
            "diameter", f"a {2 * body_radius:g} mm body does not fit a {pipe.diameter:g} mm pipe"
        )
    grid = _pressure_grid(step_kpa, planar=True)
    l1 = acts[0].length(grid[:, 0], 0.0)
    l23 = acts[1].length(grid[:, 1], 0.0)
    rest1, rest23 = float(acts[0].length(0.0, 0.0)), float(acts[1].length(0.0, 0.0))
    rest = (rest1 + 2.0 * rest23) / 3.0
    k_t, lc_t = _planar(l1, l23, d)
    stride = lc_t - rest
    s_lat, s_ax = _arc(k_t, stride)
    lam = np.linspace(0.0, 1.0, stages + 1)[1:]
    f = np.linspace(0.0, 1.0, samples)
    goal = pipe.goal()

    # state columns: x, z, heading alpha, kept curvature k
    layers = [np.zeros((1, 4))]
    parents: list[np.ndarray] = [np.array([-1])]
    cands: list[np.ndarray] = [np.array([-1])]
    seen: set = set()
    exhaustive = True
    found = None
    for _ in range(max_cycles):
        cur = layers[-1]
        nxt, par, cnd = [], [], []
        for start in range(0, len(cur), chunk):
            ch = cur[start : start + chunk]
            x, z, al, kd = (ch[:, i][:, None, None, None] for i in range(4))
            # deflated lengths of the kept curvature -> target lengths, linear in the stages
            l1d = rest * (1.0 - kd * d)
            l23d = rest * (1.0 + kd * d / 2.0)
            L1 = l1d + lam[None, None, :, None] * (l1[None, :, None, None] - l1d)
            L23 = l23d + lam[None, None, :, None] * (l23[None, :, None, None] - l23d)
            k, lc = _planar(L1, L23, d)
            lat, ax = _arc(k, lc * f)  # (S, C, stages, n)
            px = x + np.cos(al) * lat + np.sin(al) * ax
            pz = z - np.sin(al) * lat + np.cos(al) * ax
            dist, _ = pipe.locate(np.stack([px, np.zeros_like(px), pz], -1))
            ok = dist.max(axis=(2, 3)) <= allow + 1e-9  # (S, C)
            si, ci = np.nonzero(ok & (stride[None, :] > 1e-6))
            a0 = ch[si, 2]
            nx = ch[si, 0] + np.cos(a0) * s_lat[ci] + np.sin(a0) * s_ax[ci]
            nz = ch[si, 1] - np.sin(a0) * s_lat[ci] + np.cos(a0) * s_ax[ci]
            na = a0 + k_t[ci] * stride[ci]
            nxt.append(np.stack([nx, nz, na, k_t[ci]], -1))
            par.append(start + si)
            cnd.append(ci)
        new = np.concatenate(nxt) if nxt else np.zeros((0, 4))
        if len(new) == 0:
            break
        par, cnd = np.concatenate(par), np.concatenate(cnd)
        _, s_new = pipe.locate(np.stack([new[:, 0], np.zeros(len(new)), new[:, 1]], -1))
        cells = (
            np.stack(
                [
                    new[:, 0] / cell_mm,
                    new[:, 1] / cell_mm,
                    np.rad2deg(new[:, 2]) / cell_deg,
                    new[:, 3] / 5e-4,
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
        if idx.size == 0:
            break
        for i in idx:
            seen.add(tuple(cells[i]))
        idx = idx[np.argsort(-s_new[idx], kind="stable")]
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
            found = 0
            break
    # reconstruct the furthest path of the last layer
    chain = []
    j = 0
    for li in range(len(layers) - 1, 0, -1):
        chain.append((li, j))
        j = parents[li][j]
    chain.reverse()
    cycles = []
    rot = _ROT0.copy()
    for n, (li, j) in enumerate(chain, start=1):
        prev = layers[li - 1][parents[li][j]]
        c = cands[li][j]
        kk, lc, st = float(k_t[c]), float(lc_t[c]), float(stride[c])
        phi = np.pi / 2 if kk >= 0 else -np.pi / 2
        rear = np.array([prev[0], 0.0, prev[1]])
        lat, ax = _arc(kk, lc)
        front = rear + np.array(
            [np.cos(prev[2]) * lat + np.sin(prev[2]) * ax, 0.0, -np.sin(prev[2]) * lat + np.cos(prev[2]) * ax]
        )
        state = layers[li][j]
        ldef = rest * (1.0 - abs(kk) * d * np.cos(kin.PSI - phi))
        p_def = tuple(float(_deflated_pressure(acts[i], ldef[i], 0.0)) for i in range(3))
        _, s_after = pipe.locate(np.array([state[0], 0.0, state[1]]))
        pts = rear + kin.arc_point(abs(kk) * lc * f, phi, lc * f) @ rot.T
        dist, _ = pipe.locate(pts)
        cycles.append(
            Cycle(
                n,
                tuple(map(float, grid[c])),
                p_def,
                (float(l1[c]), float(l23[c]), float(l23[c])),
                tuple(map(float, ldef)),
                abs(kk),
                abs(kk) * lc,
                phi,
                lc,
                rest,
                tuple(map(float, rear)),
                tuple(map(float, front)),
                (float(state[0]), 0.0, float(state[1])),
                float(s_after),
                float(allow - dist.max()),
            )
        )
        rot = rot @ kin.arc_rotation(abs(kk) * st, phi)
    success = found is not None
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
        tuple(tuple(map(float, r)) for r in _ROT0),
    )
