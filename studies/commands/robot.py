"""`softcrawl robot`: the whole robot in FE under three chamber pressures.

    softcrawl robot --pressures P1,P2,P3 [--first P1,P2,P3] [--steps N] [--mesh quick|default|fine]
                    [--material M] [--rings N] [--d MM] [--gravity] [--out DIR [--resume]]

The tied assembly of `studies.robot_fe.model` (rear foot hub clamped) follows the pressures
(kPa) from zero: in --steps proportional steps to --pressures, or first to --first and then to
--pressures (a sequential path: --first 0,40,60 --pressures 100,40,60 is the paper's Fig. 11
load case). --gravity adds the weight, acting along -y (the robot lying in a horizontal pipe).
Prints each converged state (tip, theta, phi, FE lengths, arc-fit RMS, d_eff, splay, and phi of
eq. 6 fed with the FE lengths); with --out writes states.csv, a VTU series (vtu/robot.pvd) and a
render of the last state (robot.png).

With --out, every converged sub-step is written to OUT/checkpoints (the newest 3 kept; removed once
the outputs are written); after a kill -9, a SIGTERM or a full disk the same command with --resume
continues from the newest (`fem.path_cursor`). The rules of `softcrawl crawl --resume`: another
option or softcrawl version is refused in one line naming it (exit 2); --resume without a
checkpoint starts from the beginning and says so; an unfinished run's checkpoint is not
overwritten without --resume (exit 2).
"""

from __future__ import annotations

import argparse
import math
import shutil
from pathlib import Path

from softcrawl.console import progress
from softcrawl.errors import InputError
from softcrawl.units import kpa_to_mpa

# Project modules are imported inside the functions that use them: softcrawl --help stays fast.


def register(subparsers) -> None:
    from softcrawl.geometry.robot_mesh import MESH_PRESETS
    from softcrawl.studies.commands.options import add_number, add_vtu_precision
    from softcrawl.studies.robot_fe.model import DEFAULT_MATERIAL

    p = subparsers.add_parser(
        "robot",
        help="the whole robot in FE (three chamber pressures)",
        description=__doc__.splitlines()[0],
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog="\n".join(__doc__.splitlines()[1:]),
    )
    p.add_argument("--pressures", required=True, help="P1,P2,P3 in kPa, the last target (each in [0, 1000])")
    p.add_argument(
        "--first", default=None, help="P1,P2,P3 in kPa reached before --pressures (sequential path)"
    )
    add_number(p, "--steps", help="proportional steps per segment", default=5, minimum=1, maximum=1000,
               integer=True)  # fmt: skip
    p.add_argument(
        "--mesh", default="default", choices=sorted(MESH_PRESETS), help="mesh preset (default: default)"
    )
    p.add_argument(
        "--material",
        default=DEFAULT_MATERIAL,
        help=f"ePSA silicone (default {DEFAULT_MATERIAL}); see `softcrawl material list`",
    )
    add_number(p, "--rings", help="number of connecting rings", default_text="3 (Table 1)", minimum=0,
               maximum=50, integer=True)  # fmt: skip
    add_number(p, "--d", help="foot radius d: robot axis to actuator axes", unit="mm",
               default_text="14 (Table 1)", minimum=0.0, min_open=True, maximum=1000.0)  # fmt: skip
    p.add_argument("--gravity", action="store_true", help="add the weight along -y (a horizontal pipe)")
    p.add_argument(
        "--out", default=None, help="folder for states.csv, vtu/ and robot.png (default: print only)"
    )
    add_vtu_precision(p)
    p.add_argument(
        "--resume", action="store_true", help="continue from the last state in OUT/checkpoints (same options)"
    )
    p.set_defaults(func=run)


def _triple(text: str, name: str) -> tuple[float, float, float]:
    from softcrawl.studies.commands.options import MAX_PRESSURE_KPA, CommandLineError

    try:
        values = tuple(float(v) for v in text.split(","))
    except ValueError:
        raise CommandLineError(name, f"{text!r} is not three comma-separated pressures in kPa") from None
    if len(values) != 3 or not all(math.isfinite(v) and 0 <= v <= MAX_PRESSURE_KPA for v in values):
        raise CommandLineError(name, f"{text!r}: give three pressures in [0, {MAX_PRESSURE_KPA:g}] kPa")
    return values


def targets_kpa(pressures, first, steps: int) -> list[tuple[float, float, float]]:
    """The proportional sub-targets of the (sequential) path, kPa."""
    if steps < 1:
        raise InputError("steps", f"must be >= 1, got {steps}")
    out, start = [], (0.0, 0.0, 0.0)
    for end in ([first] if first else []) + [pressures]:
        out += [tuple(a + (b - a) * k / steps for a, b in zip(start, end)) for k in range(1, steps + 1)]
        start = end
    return out


def run(args) -> int:
    from softcrawl.geometry.design import RobotDesign
    from softcrawl.studies.commands.options import body_material, output_folder
    from softcrawl.studies.robot_fe.model import build_robot_model
    from softcrawl.studies.robot_fe.response import simulate_robot

    pressures = _triple(args.pressures, "pressures")
    first = _triple(args.first, "first") if args.first else None
    targets = targets_kpa(pressures, first, args.steps)
    kwargs = {k: v for k, v in (("n_rings", args.rings), ("d", args.d)) if v is not None}
    design = RobotDesign(**kwargs)  # DesignError naming the field, before any meshing
    body_material(args.material)
    if args.out is not None:  # an empty name too: it is an error, not "no output"
        output_folder(args.out)
    checkpoints = robot_checkpoints(args)
    robot = build_robot_model(
        design, args.material, args.mesh, gravity=(0.0, -1.0, 0.0) if args.gravity else None
    )
    progress(f"robot: {robot.n_dofs} DOFs, materials {robot.materials}, {args.mesh} mesh")
    run_ = simulate_robot(
        robot,
        [tuple(kpa_to_mpa(p) for p in P) for P in targets],
        gravity=args.gravity,
        checkpoints=checkpoints,
        resume=args.resume,
    )
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
        write_outputs(robot, run_, Path(args.out), args.vtu_precision)
        shutil.rmtree(checkpoints.folder, ignore_errors=True)  # the run ended and its files are written
    return 0 if run_.converged else 1


def robot_checkpoints(args):
    """The run's `fem.checkpoint.Checkpoints` in OUT/checkpoints (None without --out), checked
    before any work: a folder of other options or another version with --resume, or an unfinished
    run's without it, is refused (exit 2)."""
    from softcrawl.fem.checkpoint import Checkpoints
    from softcrawl.studies.commands.options import CommandLineError

    if args.out is None:
        if args.resume:
            raise CommandLineError("resume", "needs --out (the checkpoints are in OUT/checkpoints)")
        return None
    options = {k: getattr(args, k) for k in ("pressures", "first", "steps", "mesh", "material", "rings", "d")}
    checkpoints = Checkpoints(Path(args.out) / "checkpoints", options | {"gravity": bool(args.gravity)})
    if args.resume:
        checkpoints.check()
        if not checkpoints.states():
            print(f"robot: no checkpoint in {checkpoints.folder}; starting from the beginning")
        else:
            print(f"robot: resuming from {checkpoints.states()[-1]}")
    elif checkpoints.states():
        raise CommandLineError(
            "resume",
            f"{checkpoints.folder} holds the checkpoint of an unfinished run; add --resume to continue it, "
            "or remove the folder to start again",
        )
    else:
        shutil.rmtree(checkpoints.folder, ignore_errors=True)  # a manifest without states
    return checkpoints


def write_outputs(robot, run_, folder: Path, precision: int = 32) -> None:
    """states.csv, vtu/robot.pvd (one VTU per converged state, at the ramp's path parameter,
    `fem.vtu.path_times`) and robot.png (the last state)."""
    from softcrawl.fem.vtu import path_times, write_pvd, write_state
    from softcrawl.studies.robot_fe.plots import render_robot
    from softcrawl.studies.sweeps.tables import write_csv

    write_csv([s.row() | {"material": run_.material} for s in run_.states], folder / "states.csv")
    files, pairs = [], list(zip(run_.path.steps, run_.states))
    times = path_times([s.pressures_kpa for _, s in pairs], [step.factor for step, _ in pairs])
    for k, ((step, state), t) in enumerate(zip(pairs, times)):
        pressure = [kpa_to_mpa(p) for p in state.pressures_kpa]
        load = {"pressure_mpa": pressure, "factor": step.factor, "time": t, "precision": precision}
        files.append(write_state(folder / "vtu" / f"robot_{k:03d}.vtu", robot.model, step.x, **load))
    write_pvd(folder / "vtu" / "robot.pvd", files, times)
    if run_.path.steps:
        last = run_.states[-1]
        title = f"P = {tuple(round(p, 1) for p in last.pressures_kpa)} kPa, {run_.material}"
        render_robot(robot, run_.path.steps[-1].x, folder / "robot.png", title)
    print(f"wrote {folder / 'states.csv'}, {folder / 'vtu' / 'robot.pvd'}, {folder / 'robot.png'}")
