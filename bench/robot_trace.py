"""Trace of the robot's Newton iterations: where the residual sits and how the steps behave.

    python bench/robot_trace.py [--mesh quick] [--abs-modulus E] [--targets P1,P2,P3;...]
                                [--predictor tangent|secant|none] [--tol T] [--out trace.csv]

Runs the robot path (default: the Fig. 11 path (0, 40, 60) -> (100, 40, 60) kPa in the 10 kPa
targets of the ring study) and prints one line per Newton iteration of every sub-step, accepted
or cut back: the relative force residual, the share of the squared residual held by the
displacement dofs of the ABS parts (rings, seal heads: nodes touching only ABS elements), the
silicone, the feet and the interfaces, the pressure-constraint residual / solid volume, the line-
search step length and the largest displacement increment. --abs-modulus replaces the ABS
Young's modulus (MPa) for a measurement of its effect (docs/decisions/050-rigid-abs.md).
"""

from __future__ import annotations

import argparse
import csv
import dataclasses
import time

import numpy as np

from softcrawl.units import kpa_to_mpa, mpa_to_kpa


def _node_classes(robot) -> dict[str, np.ndarray]:
    """Boolean masks over the P2 nodes: which part kinds' elements touch each node."""
    m = robot.model
    elem_nodes = m.space.elem_nodes  # (E, 10)
    names = robot.mesh.region_names
    kinds = np.array([next(k for k in ("epsa", "seal_head", "ring", "foot") if names[r].startswith(k))
                      for r in robot.mesh.region])  # fmt: skip
    touch = {}
    for k in ("epsa", "seal_head", "ring", "foot"):
        mask = np.zeros(m.space.n_nodes, bool)
        mask[elem_nodes[kinds == k].ravel()] = True
        touch[k] = mask
    abs_ = touch["seal_head"] | touch["ring"]
    n_kinds = touch["epsa"].astype(int) + abs_ + touch["foot"]
    return {
        "silicone": touch["epsa"] & (n_kinds == 1),
        "abs": abs_ & (n_kinds == 1),
        "foot": touch["foot"] & (n_kinds == 1),
        "interface": n_kinds > 1,
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mesh", default="quick")
    ap.add_argument("--abs-modulus", type=float, default=None)
    ap.add_argument("--targets", default=None, help="P1,P2,P3 kPa targets separated by ';'")
    ap.add_argument("--predictor", default="tangent")
    ap.add_argument("--tol", type=float, default=1e-8)
    ap.add_argument("--out", default=None)
    ap.add_argument("--rigid-ratio", type=float, default=None, help="NewtonOptions.rigid_ratio (0: off)")
    args = ap.parse_args()

    import softcrawl.materials.presets as presets
    from softcrawl.fem import newton
    from softcrawl.studies.robot_fe.model import build_robot_model
    from softcrawl.studies.robot_fe.response import ROBOT_NEWTON, simulate_robot
    from softcrawl.studies.robot_fe.robot_studies import LOAD_CASES_KPA

    if args.abs_modulus is not None:
        base = presets.PRESETS["abs"]
        presets.PRESETS["abs"] = lambda: dataclasses.replace(
            base(), youngs=args.abs_modulus, mu=None, bulk=None
        )
    robot = build_robot_model(None, mesh=args.mesh)
    classes = _node_classes(robot)
    m = robot.model
    dof_class = {k: np.repeat(v, 3) for k, v in classes.items()}
    rows: list[dict] = []
    state = {"step": 0, "load": None}
    original_load_step = newton.NewtonSolver.load_step
    original_line_search = newton.NewtonSolver._line_search
    original_merit = newton.NewtonSolver._merit

    def load_step(self, x, P, factor, start=None):
        state["step"] += 1
        state["load"] = tuple(mpa_to_kpa(float(p)) for p in np.atleast_1d(P))
        state["t0"] = time.perf_counter()
        try:
            out = original_load_step(self, x, P, factor, start)
            rows[-1]["outcome"] = "converged"
            return out
        except newton.Diverged as exc:
            if rows:
                rows[-1]["outcome"] = f"diverged: {exc}"
            raise

    def merit(self, R, x, P, f):
        out = original_merit(self, R, x, P, f)
        if state.get("in_search"):
            return out
        Ru = np.zeros(m.n_u)
        Ru[self.free_u] = R[self.free_u]
        total = float(Ru @ Ru) or 1.0
        row = {"step": state["step"], "load": state["load"], "merit": out[0],
               "p_res": float(np.linalg.norm(R[m.n_u:]) / self._volume) if m.mixed else 0.0}  # fmt: skip
        for k, mask in dof_class.items():
            row[f"share_{k}"] = float(Ru[mask] @ Ru[mask]) / total
        node = int(np.argmax(np.linalg.norm(Ru.reshape(-1, 3), axis=1)))
        row["max_node_z"] = float(m.space.nodes[2, node])
        row["max_node_class"] = next(k for k, v in classes.items() if v[node])
        row["outcome"] = ""
        rows.append(row)
        return out

    def line_search(self, x, dx, R0, P, f, history):
        state["in_search"] = True
        try:
            trial = original_line_search(self, x, dx, R0, P, f, history)
        finally:
            state["in_search"] = False
        du = trial[self.free] - x[self.free]
        k = int(np.argmax(np.abs(dx)))
        rows[-1]["alpha"] = float(du[k] / dx[k]) if dx[k] else 1.0
        rows[-1]["max_du"] = float(np.abs(dx).max())
        return trial

    original_tangent = newton.NewtonSolver.load_tangent

    def load_tangent(self, x, L, direction):
        state["in_search"] = True
        try:
            return original_tangent(self, x, L, direction)
        finally:
            state["in_search"] = False

    newton.NewtonSolver.load_tangent = load_tangent
    newton.NewtonSolver.load_step = load_step
    newton.NewtonSolver._merit = merit
    newton.NewtonSolver._line_search = line_search
    if args.targets:
        targets_kpa = [tuple(float(v) for v in t.split(",")) for t in args.targets.split(";")]
    else:
        targets_kpa = LOAD_CASES_KPA["asymmetric"]
    opts = dataclasses.replace(ROBOT_NEWTON, predictor=args.predictor, tol=args.tol)
    if args.rigid_ratio is not None:
        opts = dataclasses.replace(opts, rigid_ratio=args.rigid_ratio or None)
    t0 = time.perf_counter()
    run = simulate_robot(robot, [tuple(kpa_to_mpa(p) for p in P) for P in targets_kpa], options=opts)
    wall = time.perf_counter() - t0
    for r in rows:
        print(
            f"{r['step']:4d} {str(tuple(round(p, 2) for p in r['load'])):24s} r={r['merit']:.2e} "
            f"p={r['p_res']:.1e} abs={r['share_abs']:.2f} sil={r['share_silicone']:.2f} "
            f"foot={r['share_foot']:.2f} itf={r['share_interface']:.2f} "
            f"max@{r['max_node_class']}/z={r['max_node_z']:.1f} a={r.get('alpha', float('nan')):.2f} "
            f"du={r.get('max_du', float('nan')):.2e} {r['outcome']}"
        )
    s = run.states[-1]
    print(f"{run.message}; {run.newton_iterations} iterations, {wall:.1f} s, {robot.n_dofs} DOFs")
    print(f"final {s.pressures_kpa}: theta {s.theta_deg:.4f} phi {s.phi_deg:.4f} tip {s.tip_mm}")
    for st in run.states:
        print(f"  {st.pressures_kpa} theta {st.theta_deg:.4f} phi {st.phi_deg:.4f} "
              f"tip {tuple(round(v, 4) for v in st.tip_mm)}")  # fmt: skip
    if args.out:
        with open(args.out, "w", newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=sorted({k for r in rows for k in r}))
            w.writeheader()
            w.writerows(rows)


if __name__ == "__main__":
    main()
