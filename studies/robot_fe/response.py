r"""The robot's response to three chamber pressures: the path and the outputs of each state.

Path. Targets are pressure triples (MPa) reached in order, each segment proportional (a
sequential path, e.g. P2 = 40 and P3 = 60 kPa first and then P1 ramped, is two targets);
`fem.path.load_path` does the sub-steps, the cut-back and, past a limit point, volume control.
With gravity the weight is applied first (load factor 0 -> 1 at zero pressure).

Outputs of a state (`RobotState`), all from the deformed vertices:

* centrelines: at every mesh level z_k in [0, L] the centre of actuator i is the mean of its
  vertices with rho_i <= r0 (the axis in the end caps, the chamber circle along the chamber); the
  robot's centreline is the mean of the three. FE arc length l_i = the length of actuator i's
  centreline polyline (chord error ~ (kappa h)^2 / 24, 2e-4 at 120 deg on the default mesh).
* end: the robot centreline at the actuators' top level z = L0, where the arc of eqs. 4-9 ends.
* front hub: the rigid motion (R, t) that best fits the front hub's vertices (Kabsch); the tip
  is the hub's top-face centre moved by it; theta = angle between R e_z and e_z, phi = the
  azimuth of R e_z (the CC end frame of eq. 9 has R e_z = (c phi s theta, s phi s theta, c theta)).
* arc-fit residual: RMS distance of the robot centreline from its best-fit circle arc (a plane
  by SVD, a circle in it by least squares), or from its best line when that fits better.
* d_eff (eq. 7): the d that makes eq. 5 give the FE theta from the FE lengths,
  d_eff = 2 sqrt(l1^2 + l2^2 + l3^2 - l1 l2 - l1 l3 - l2 l3) / (3 theta); NaN below 0.5 deg.
* phi_cc: eq. 6 fed with the FE lengths; theta_cc: eq. 5 with the FE lengths and d0.
* splay: max over levels and actuators of | |c_i(z) - c(z)| - d0 |, the distance of an actuator
  centre from the robot centre against the design's d0 (zero for a constant-curvature bundle whose
  cross-sections stay rigid; it grows where the actuators bow apart or together between rings).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from softcrawl.analytic import kinematics as kin
from softcrawl.fem import path_cursor
from softcrawl.fem.checkpoint import CheckpointError
from softcrawl.fem.path import NewtonOptions, load_path
from softcrawl.studies.robot_fe.model import RobotModel
from softcrawl.units import mpa_to_kpa

THETA_MIN_FOR_D = math.radians(0.5)
#: Newton options of the robot paths. The ABS rings and seal heads (mu 1.2e4 x the silicone's)
#: turn with the bending robot; the predictor's extrapolation stretched them and Newton spent
#: its first iterations undoing the spurious stress, so the prediction of every part 100 x
#: stiffer than the softest is a rigid motion (`fem.stiff_parts`; the rubber feet, ~30 x, keep
#: theirs): quick mesh, Fig. 11 path in 10 kPa targets, 94 -> 54 Newton iterations, the same
#: states (docs/decisions/050-rigid-abs.md). Cut-backs: up to 8 halvings of a segment.
ROBOT_NEWTON = NewtonOptions(max_cutbacks=8, rigid_ratio=100.0)


@dataclass(frozen=True)
class RobotState:
    pressures_kpa: tuple[float, float, float]
    tip_mm: tuple[float, float, float]
    end_mm: tuple[float, float, float]  # robot centreline at the actuators' top level z = L0
    theta_deg: float
    phi_deg: float
    lengths_mm: tuple[float, float, float]
    extension_mm: float  # mean FE length - L0
    arc_rms_mm: float
    d_eff_mm: float
    splay_mm: float
    theta_cc_deg: float  # eq. 5 with the FE lengths and the design's d0
    phi_cc_deg: float  # eq. 6 with the FE lengths

    def row(self) -> dict:
        d = asdict(self)
        out = {f"P{i + 1}_kpa": p for i, p in enumerate(d.pop("pressures_kpa"))}
        out |= {f"tip_{c}_mm": v for c, v in zip("xyz", d.pop("tip_mm"))}
        out |= {f"end_{c}_mm": v for c, v in zip("xyz", d.pop("end_mm"))}
        out |= {f"l{i + 1}_mm": v for i, v in enumerate(d.pop("lengths_mm"))}
        return out | d


@dataclass(frozen=True)
class RobotRun:
    states: tuple[RobotState, ...]
    converged: bool
    message: str
    material: str
    n_dofs: int
    newton_iterations: int
    seconds: float
    stats: object  # fem.newton.SolveStats
    path: object  # fem.path.PathResult (the states' x)


class Probes:
    """Vertex index sets of the outputs, computed once per model."""

    def __init__(self, robot: RobotModel) -> None:
        d, e = robot.design, robot.design.epsa
        p = robot.mesh.points
        tol = 1e-6 * e.length
        levels = np.unique(p[(p[:, 2] > -tol) & (p[:, 2] < e.length + tol), 2])
        self.levels = levels
        self.axis: list[list[np.ndarray]] = []
        for cx, cy in d.actuator_centres:
            near = np.hypot(p[:, 0] - cx, p[:, 1] - cy) < e.chamber_radius + tol
            self.axis.append([np.nonzero(near & (np.abs(p[:, 2] - z) < tol))[0] for z in levels])
        self.hub = np.unique(robot.mesh.tets[robot.mesh.region == robot.mesh.region_id("foot_front")])
        self.hub_centre = np.array([0.0, 0.0, e.length + e.seal_head_thickness + d.foot.hub_thickness])


def _kabsch(X: np.ndarray, x: np.ndarray):
    """Rotation R and translation t with x ~ R X + t (least squares), X and x (n, 3)."""
    Xc, xc = X.mean(axis=0), x.mean(axis=0)
    U, _, Vt = np.linalg.svd((x - xc).T @ (X - Xc))
    D = np.diag([1.0, 1.0, np.sign(np.linalg.det(U @ Vt))])
    R = U @ D @ Vt
    return R, xc - R @ Xc


def arc_fit_rms(points: np.ndarray) -> float:
    """RMS distance of points (n, 3) from their best circle arc or best line (the smaller)."""
    c = points - points.mean(axis=0)
    _, s, Vt = np.linalg.svd(c, full_matrices=False)
    line_rms = float(np.sqrt(np.mean(np.sum((c - np.outer(c @ Vt[0], Vt[0])) ** 2, axis=1))))
    if s[1] < 1e-9 * s[0]:
        return line_rms
    uv = c @ Vt[:2].T
    out_of_plane = c @ Vt[2]
    # algebraic circle (Kasa), then the geometric fit from it
    A = np.column_stack([2 * uv, np.ones(len(uv))])
    sol = np.linalg.lstsq(A, np.sum(uv**2, axis=1), rcond=None)[0]
    from scipy.optimize import least_squares

    def resid(q):
        return np.hypot(uv[:, 0] - q[0], uv[:, 1] - q[1]) - q[2]

    r0 = math.sqrt(max(sol[2] + sol[0] ** 2 + sol[1] ** 2, 1e-12))
    q = least_squares(resid, [sol[0], sol[1], r0]).x
    circle_rms = float(np.sqrt(np.mean(resid(q) ** 2 + out_of_plane**2)))
    return min(circle_rms, line_rms)


def robot_state(robot: RobotModel, probes: Probes, x: np.ndarray, pressures_mpa) -> RobotState:
    """The outputs of the module docstring at state x."""
    design = robot.design
    n_v = robot.mesh.n_nodes
    pos = robot.mesh.points + robot.model.displacement(x)[:, :n_v].T
    centres = np.array([[pos[idx].mean(axis=0) for idx in act] for act in probes.axis])  # (3, levels, 3)
    lengths = np.linalg.norm(np.diff(centres, axis=1), axis=2).sum(axis=1)
    axis = centres.mean(axis=0)
    R, t = _kabsch(robot.mesh.points[probes.hub], pos[probes.hub])
    tip = R @ probes.hub_centre + t
    n = R[:, 2]
    theta = math.acos(max(-1.0, min(1.0, float(n[2]))))
    phi = math.atan2(float(n[1]), float(n[0]))
    l1, l2, l3 = lengths
    q = math.sqrt(max(l1 * l1 + l2 * l2 + l3 * l3 - l1 * l2 - l1 * l3 - l2 * l3, 0.0))
    d_eff = 2.0 * q / (3.0 * theta) if theta > THETA_MIN_FOR_D else float("nan")
    _, theta_cc, phi_cc, _ = kin.forward(lengths, design.d)
    splay = float(np.abs(np.linalg.norm(centres - axis[None], axis=2) - design.d).max())
    return RobotState(
        tuple(mpa_to_kpa(float(p)) for p in pressures_mpa),
        tuple(float(v) for v in tip),
        tuple(float(v) for v in axis[-1]),
        math.degrees(theta),
        math.degrees(phi),
        tuple(float(v) for v in lengths),
        float(lengths.mean() - design.epsa.length),
        arc_fit_rms(axis),
        d_eff,
        splay,
        math.degrees(float(theta_cc)),
        math.degrees(float(phi_cc)),
    )


def simulate_robot(
    robot: RobotModel,
    targets_mpa,
    *,
    options=None,
    gravity: bool = False,
    checkpoints=None,
    resume: bool = False,
) -> RobotRun:
    """Follow the pressure triples `targets_mpa` (MPa) from zero; the outputs of every converged
    state. A path that stops early is a result whose message names the last converged load.
    `checkpoints` (a `fem.checkpoint.Checkpoints`): every converged pressure-controlled sub-step is
    written to it (`fem.path_cursor`); with `resume`, the path continues from its newest state
    (none: from the start)."""
    f = 1.0 if gravity else 0.0
    targets = [((0.0, 0.0, 0.0), 1.0)] if gravity else []
    targets += [(tuple(float(v) for v in P), f) for P in targets_mpa]
    start, on_cursor = None, None
    if checkpoints is not None:
        start, index = _latest(checkpoints) if resume else (None, 0)

        def on_cursor(cursor):
            nonlocal index
            index += 1
            arrays, meta = path_cursor.to_arrays(cursor)
            checkpoints.save(index, arrays, meta | {"index": index})

    res = load_path(robot.model, targets, options=options or ROBOT_NEWTON, start=start, on_cursor=on_cursor)
    probes = Probes(robot)
    states = tuple(robot_state(robot, probes, s.x, _triple(s.pressure)) for s in res.steps)
    return RobotRun(
        states,
        res.converged,
        res.message,
        robot.materials["epsa"],
        robot.n_dofs,
        int(res.stats.iterations),
        float(res.stats.wall_s),
        res.stats,
        res,
    )


def _latest(checkpoints):
    """(cursor, index) of the newest state in `checkpoints`, or (None, 0); `CheckpointError` for a
    folder of other options or another version, or a state that is not a path's."""
    found = checkpoints.load_latest()
    if found is None:
        return None, 0
    meta, arrays = found
    try:
        return path_cursor.from_arrays(meta, arrays), int(meta["index"])
    except (KeyError, TypeError, ValueError) as exc:
        raise CheckpointError(
            "resume", f"the checkpoint in {checkpoints.folder} cannot be read ({type(exc).__name__}: {exc})"
        ) from None


def _triple(p) -> tuple[float, float, float]:
    p = np.atleast_1d(np.asarray(p, dtype=float))
    return tuple(float(v) for v in (p if p.size == 3 else np.full(3, p[0])))
