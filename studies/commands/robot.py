"""`softcrawl robot`: the whole robot in FE under three chamber pressures.

    softcrawl robot --pressures P1,P2,P3 [--first P1,P2,P3] [--steps N] [--mesh quick|default|fine]
                    [--material M] [--rings N] [--d MM] [--gravity] [--out DIR]

The tied assembly of `studies.parts.robot_model` (rear foot hub clamped) follows the pressures
(kPa) from zero: in --steps proportional steps to --pressures, or first to --first and then to
--pressures (a sequential path: --first 0,40,60 --pressures 100,40,60 is the paper's Fig. 11
load case). --gravity adds the weight, acting along -y (the robot lying in a horizontal pipe).
Prints each converged state (tip, theta, phi, FE lengths, arc-fit RMS, d_eff, splay, and phi of
eq. 6 fed with the FE lengths); with --out writes states.csv, a VTU series (vtu/robot.pvd) and a
render of the last state (robot.png).
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

from geometry.design import DesignError


def register(subparsers) -> None:
    from geometry.robot_mesh import MESH_PRESETS
    from studies.parts.robot_model import DEFAULT_MATERIAL

    p = subparsers.add_parser(
        "robot",
        help="the whole robot in FE (three chamber pressures)",
        description=__doc__.splitlines()[0],
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog="\n".join(__doc__.splitlines()[1:]),
    )
    p.add_argument("--pressures", required=True, help="P1,P2,P3 in kPa (the last target)")
    p.add_argument("--first", default=None, help="P1,P2,P3 in kPa reached before --pressures")
    p.add_argument("--steps", type=int, default=5, help="proportional steps per segment (default 5)")
    p.add_argument("--mesh", default="default", choices=sorted(MESH_PRESETS), help="mesh preset")
    p.add_argument("--material", default=DEFAULT_MATERIAL, help=f"ePSA silicone (default {DEFAULT_MATERIAL})")
    p.add_argument("--rings", type=int, default=None, help="number of connecting rings (Table 1: 3)")
    p.add_argument("--d", type=float, default=None, help="foot radius d, mm (Table 1: 14)")
    p.add_argument("--gravity", action="store_true", help="add the weight along -y")
    p.add_argument("--out", default=None, help="folder for states.csv, vtu/ and robot.png")
    p.set_defaults(func=run)


def _triple(text: str, name: str) -> tuple[float, float, float]:
    try:
        values = tuple(float(v) for v in text.split(","))
    except ValueError:
        raise DesignError(name, f"{text!r} is not three comma-separated pressures in kPa") from None
    if len(values) != 3 or not all(math.isfinite(v) and 0 <= v <= 1000 for v in values):
        raise DesignError(name, f"{text!r}: give three pressures in [0, 1000] kPa")
    return values


def targets_kpa(pressures, first, steps: int) -> list[tuple[float, float, float]]:
    """The proportional sub-targets of the (sequential) path, kPa."""
    if steps < 1:
        raise DesignError("steps", f"must be >= 1, got {steps}")
    out, start = [], (0.0, 0.0, 0.0)
    for end in ([first] if first else []) + [pressures]:
        out += [tuple(a + (b - a) * k / steps for a, b in zip(start, end)) for k in range(1, steps + 1)]
        start = end
    return out


def run(args) -> int:
    from geometry.design import RobotDesign
    from studies.parts.robot_model import build_robot_model
    from studies.parts.robot_response import simulate_robot

    pressures = _triple(args.pressures, "pressures")
    first = _triple(args.first, "first") if args.first else None
    targets = targets_kpa(pressures, first, args.steps)
    kwargs = {k: v for k, v in (("n_rings", args.rings), ("d", args.d)) if v is not None}
    robot = build_robot_model(
        RobotDesign(**kwargs), args.material, args.mesh, gravity=(0.0, -1.0, 0.0) if args.gravity else None
    )
    print(f"robot: {robot.n_dofs} DOFs, materials {robot.materials}, {args.mesh} mesh")
    run_ = simulate_robot(robot, [tuple(p / 1e3 for p in P) for P in targets], gravity=args.gravity)
    for s in run_.states:
        print(
            f"P = ({', '.join(f'{p:.4g}' for p in s.pressures_kpa)}) kPa: theta {s.theta_deg:.2f} deg, "
            f"phi {s.phi_deg:.1f} deg (eq. 6 with FE lengths {s.phi_cc_deg:.1f}), tip "
            f"({', '.join(f'{v:.1f}' for v in s.tip_mm)}) mm, "
            f"l = ({', '.join(f'{v:.1f}' for v in s.lengths_mm)}) mm, arc RMS {s.arc_rms_mm:.3f} mm, "
            f"d_eff {s.d_eff_mm:.2f} mm, splay {s.splay_mm:.3f} mm"
        )
    print(f"{run_.message}; {run_.newton_iterations} Newton iterations, {run_.seconds:.1f} s")
    if args.out:
        write_outputs(robot, run_, Path(args.out))
    return 0 if run_.converged else 1


def write_outputs(robot, run_, folder: Path) -> None:
    """states.csv, vtu/robot.pvd (one VTU per converged state) and robot.png (the last state)."""
    from fem.vtu import write_state
    from studies.plots.robot import render_robot
    from studies.sweeps.engine import write_csv

    write_csv([s.row() | {"material": run_.material} for s in run_.states], folder / "states.csv")
    lines = ['<?xml version="1.0"?>', '<VTKFile type="Collection" version="0.1">', "<Collection>"]
    for k, step in enumerate(run_.path.steps):
        name = f"robot_{k:03d}.vtu"
        write_state(folder / "vtu" / name, robot.model, step.x)
        lines.append(f'<DataSet timestep="{k}" file="{name}"/>')
    (folder / "vtu" / "robot.pvd").write_text("\n".join(lines + ["</Collection>", "</VTKFile>"]) + "\n")
    if run_.path.steps:
        last = run_.states[-1]
        title = f"P = {tuple(round(p, 1) for p in last.pressures_kpa)} kPa, {run_.material}"
        render_robot(robot, run_.path.steps[-1].x, folder / "robot.png", title)
    print(f"wrote {folder / 'states.csv'}, {folder / 'vtu' / 'robot.pvd'}, {folder / 'robot.png'}")
