r"""The robot's workspace in FE against the constant-curvature model (paper Fig. 11(d)).

Grid. Pressure levels v = (0, 25, 50, 75, 100) kPa (--quick: 0, 50, 100) for each chamber. The
robot is 3-fold symmetric: turning it by +120 deg about its axis takes actuator i to i + 1, so
the state at (P3, P1, P2) is the state at (P1, P2, P3) turned by +120 deg. It is also mirror
symmetric about the plane x = 0 through actuator 1 (the double helix has both hands): the state
at (P1, P3, P2) is the state at (P1, P2, P3) with x -> -x. The FE computes only the triples with
P1 = max(P1, P2, P3) and P2 <= P3 and obtains the rest by mirroring and turning (the swept mesh's
sections are translated, not turned, copies: the symmetry holds for the physics and to the
discretisation error for the mesh).

Continuation. For each (P2, P3) on the grid one path: proportional from zero to
(max(P2, P3), P2, P3), then P1 up through the grid levels, each converged state the start of the
next (`fem.path`), with targets at most 10 kPa apart (the bending robot needs small
steps). A path that stops keeps its converged points; the missing points are reported.

Comparison. The FE end point is the robot centreline at the actuators' top level z = L0
(`studies.robot_fe.response`), where the arc of eqs. 4-9 ends; the constant-curvature (CC) end
point is eq. 9's translation for the lengths
  (a) of the single FE ePSA at the same material and mesh (`studies.epsa.response`, the top
      guided on the axis: the axial response, as in the robot), and
  (b) of eq. 3 with the paper's identified prototype parameters (eqs. 19-24, `analytic.workspace`).
Reported: the median and the largest end-point error divided by the FE arc length, the ratio of
the convex-hull volumes (CC / FE) and the largest theta of each cloud.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from softcrawl.analytic import kinematics as kin
from softcrawl.analytic.prototype import actuator_set
from softcrawl.geometry.design import EPSADesign
from softcrawl.provenance import write_summary
from softcrawl.studies.declaration import StudyRequest
from softcrawl.studies.epsa.response import simulate_epsa
from softcrawl.studies.outcome import StudyOutcome
from softcrawl.studies.robot_fe.model import build_robot_model
from softcrawl.studies.robot_fe.plots import plot_workspace
from softcrawl.studies.robot_fe.response import simulate_robot
from softcrawl.studies.sweeps.tables import read_csv, write_csv
from softcrawl.units import kpa_to_mpa

LEVELS_KPA = (0.0, 25.0, 50.0, 75.0, 100.0)
QUICK_LEVELS_KPA = (0.0, 50.0, 100.0)


def _rotate(p: np.ndarray, turns: int) -> np.ndarray:
    a = 2 * math.pi / 3 * turns
    c, s = math.cos(a), math.sin(a)
    return np.array([c * p[0] - s * p[1], s * p[0] + c * p[1], p[2]])


def fe_lines(levels) -> list[list[tuple[float, float, float]]]:
    """The continuation paths of the module docstring: lists of pressure triples (kPa)."""
    lines = []
    for p2 in levels:
        for p3 in levels:
            if p2 > p3:
                continue  # the mirror image of (p3, p2)
            start = max(p2, p3)
            pts = [(p1, p2, p3) for p1 in levels if p1 >= start]
            if pts:
                lines.append(pts)
    return lines


#: Largest pressure change between two path targets (kPa): see LOAD_CASES_KPA in robot_studies.
TARGET_STEP_KPA = 10.0


def path_targets(points):
    """The path through `points` with targets at most TARGET_STEP_KPA apart (in every chamber)."""
    out = []
    for a, b in zip(points, points[1:]):
        n = max(1, math.ceil(max(abs(x - y) for x, y in zip(a, b)) / TARGET_STEP_KPA - 1e-9))
        out += [tuple(x + (y - x) * k / n for x, y in zip(a, b)) for k in range(1, n + 1)]
    return out or [points[0]]


def fe_cloud(robot, levels, progress=None, on_line=None) -> tuple[dict, list[str]]:
    """{(P1, P2, P3) kPa: RobotState} over the whole grid (computed and turned), and messages.
    The paths run cheapest first (least bending: smallest spread of the pressures); `on_line`,
    if given, gets (grid so far, messages) after every path, so partial results are kept."""
    states, messages = {}, []
    for line in sorted(fe_lines(levels), key=lambda ln: max(max(P) - min(P) for P in ln)):
        targets = path_targets([(0.0, 0.0, 0.0), *line])
        run = simulate_robot(robot, [tuple(kpa_to_mpa(v) for v in P) for P in targets])
        for s in run.states:
            for P in line:  # a target reached on volume control reads e.g. 100.0006 kPa
                if max(abs(a - b) for a, b in zip(s.pressures_kpa, P)) < 0.01:
                    states[tuple(float(v) for v in P)] = s
        if not run.converged:
            messages.append(f"path {line[0]}..{line[-1]} kPa: {run.message}")
        if progress:
            progress(f"line {line[0]}..{line[-1]}: {run.message} ({run.seconds:.0f} s)")
        if on_line:
            on_line(_expand(states), messages)
    return _expand(states), messages


def _expand(states: dict) -> dict:
    """The computed states mirrored and turned onto the whole grid: {P: (state, turns, mirror)}."""
    full = {}
    for key, s in states.items():
        for mirror in (False, True):
            P = (key[0], key[2], key[1]) if mirror else key
            for turns in range(3):
                full.setdefault(P, (s, turns, mirror))
                P = (P[2], P[0], P[1])
    return full


def _cc_end(lengths, d):
    k, t, p, lc = kin.forward(np.asarray(lengths), d)
    return kin.arc_point(t, p, lc), np.degrees(t)


def workspace_comparison(full: dict, single_fe: dict, d: float) -> tuple[list[dict], dict]:
    """Rows (one per grid triple) and the summary of the module docstring."""
    from scipy.spatial import ConvexHull

    acts = actuator_set("prototype")
    rows = []
    for P, (s, turns, mirror) in sorted(full.items()):
        end, l_fe = np.array(s.end_mm), np.array(s.lengths_mm)
        if mirror:
            end, l_fe = end * np.array([-1.0, 1.0, 1.0]), l_fe[[0, 2, 1]]
        end, l_fe = _rotate(end, turns), np.roll(l_fe, turns)
        l_a = np.array([single_fe[p] for p in P])
        l_b = np.array([float(acts[i].length(P[i], 0.0)) for i in range(3)])
        end_a, th_a = _cc_end(l_a, d)
        end_b, th_b = _cc_end(l_b, d)
        arc = float(l_fe.mean())
        rows.append(
            {
                "P1_kpa": P[0],
                "P2_kpa": P[1],
                "P3_kpa": P[2],
                "fe_x": end[0],
                "fe_y": end[1],
                "fe_z": end[2],
                "fe_theta_deg": s.theta_deg,
                "fe_arc_mm": arc,
                "arc_rms_mm": s.arc_rms_mm,
                "cc_fe_x": end_a[0],
                "cc_fe_y": end_a[1],
                "cc_fe_z": end_a[2],
                "cc_fe_theta_deg": float(th_a),
                "cc_eq3_x": end_b[0],
                "cc_eq3_y": end_b[1],
                "cc_eq3_z": end_b[2],
                "cc_eq3_theta_deg": float(th_b),
                "err_cc_fe_rel": float(np.linalg.norm(end_a - end) / arc),
                "err_cc_eq3_rel": float(np.linalg.norm(end_b - end) / arc),
                "computed": turns == 0,
            }  # fmt: skip
        )
    clouds = {
        k: np.array([[r[f"{k}_x"], r[f"{k}_y"], r[f"{k}_z"]] for r in rows])
        for k in ("fe", "cc_fe", "cc_eq3")
    }

    def volume(c):
        try:
            return float(ConvexHull(c).volume)
        except Exception:  # noqa: BLE001 - a flat cloud (too few points) has no volume
            return math.nan

    v_fe = volume(clouds["fe"])
    summary = {
        "n_points": len(rows),
        "fe_hull_mm3": v_fe,
        "max_theta_fe_deg": max(r["fe_theta_deg"] for r in rows),
    }
    for k in ("cc_fe", "cc_eq3"):
        errs = np.array([r[f"err_{k}_rel"] for r in rows])
        summary |= {f"median_err_{k}_rel": float(np.median(errs)), f"max_err_{k}_rel": float(errs.max()),
                    f"hull_ratio_{k}": volume(clouds[k]) / v_fe,
                    f"max_theta_{k}_deg": max(r[f"{k}_theta_deg"] for r in rows)}  # fmt: skip
    return rows, summary | {"clouds": {k: v.tolist() for k, v in clouds.items()}}


def single_actuator_lengths(material: str, mesh: str, levels) -> dict:
    """{P kPa: length mm} of the single guided FE ePSA (Table 1 design)."""
    positive = [p for p in levels if p > 0]
    curve = simulate_epsa(EPSADesign(), material=material, pressures_kpa=positive, mesh=mesh, guided=True)
    out = {0.0: EPSADesign().length}
    for row in curve.rows:
        if row.status == "converged":
            out[min(positive, key=lambda p: abs(p - row.pressure_kpa))] = row.length_mm
    return out


def run_workspace(out, material: str, quick: bool, progress=None) -> StudyOutcome:
    levels = QUICK_LEVELS_KPA if quick else LEVELS_KPA
    mesh = "quick" if quick else "default"
    folder = Path(out) / "robot-workspace" / (material + ("-quick" if quick else ""))
    robot = build_robot_model(None, material, mesh)
    single = single_actuator_lengths(material, mesh, levels)
    written = []

    def write(full, messages, partial=True):
        if not full:
            return None
        rows, summary = workspace_comparison(full, single, robot.design.d)
        clouds = summary.pop("clouds")
        summary |= {"material": material, "mesh": mesh, "levels_kpa": list(levels), "n_dofs": robot.n_dofs}
        summary |= {"single_fe_lengths_mm": {str(k): v for k, v in single.items()}, "problems": messages}
        summary |= {"partial": partial}
        folder.mkdir(parents=True, exist_ok=True)
        written[:] = [write_csv(rows, folder / "workspace.csv"), folder / "summary.json"]
        write_summary(folder / "summary.json", summary)
        arrays = [np.array(clouds[k]) for k in ("fe", "cc_fe", "cc_eq3")]
        written.append(plot_workspace(*arrays, folder / "workspace.png", _title(material, mesh)))
        return summary

    full, messages = fe_cloud(robot, levels, progress, on_line=write)
    summary = write(full, messages, partial=False)
    if summary is None:
        return StudyOutcome(ok=False, problems=("no workspace point converged", *messages))
    lines = [
        f"workspace ({material}, {mesh} mesh, {summary['n_points']} points): max theta FE "
        f"{summary['max_theta_fe_deg']:.1f} deg, CC(FE lengths) {summary['max_theta_cc_fe_deg']:.1f}, "
        f"CC(eq. 3) {summary['max_theta_cc_eq3_deg']:.1f}",
        f"end error / arc length, median (max): CC(FE lengths) {summary['median_err_cc_fe_rel']:.3f} "
        f"({summary['max_err_cc_fe_rel']:.3f}); CC(eq. 3) {summary['median_err_cc_eq3_rel']:.3f} "
        f"({summary['max_err_cc_eq3_rel']:.3f})",
        f"hull volume ratio CC/FE: {summary['hull_ratio_cc_fe']:.3f} (FE lengths), "
        f"{summary['hull_ratio_cc_eq3']:.3f} (eq. 3)",
    ]
    return StudyOutcome(tuple(lines), tuple(written), ok=not messages, problems=tuple(messages))


def run_request(request: StudyRequest) -> StudyOutcome:
    """`softcrawl study workspace` (the registry's entry point)."""
    return run_workspace(request.out, request.material, request.quick, print if request.progress else None)


def _title(material: str, mesh: str) -> str:
    return f"workspace: FE robot vs constant curvature ({material}, {mesh} mesh, ends at z = L0)"


def replot_folder(folder: Path) -> list[Path]:
    """workspace.png from workspace.csv and summary.json."""
    if not (folder / "workspace.csv").exists():
        return []
    summary = json.loads((folder / "summary.json").read_text())
    rows = read_csv(folder / "workspace.csv")
    arrays = [
        np.array([[float(r[f"{k}_{c}"]) for c in "xyz"] for r in rows]) for k in ("fe", "cc_fe", "cc_eq3")
    ]
    title = _title(summary["material"], summary["mesh"])
    return [plot_workspace(*arrays, folder / "workspace.png", title)]
