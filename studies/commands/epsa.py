"""`softcrawl epsa`: simulate one ePSA under a pressure ramp (or blocked, for its output force).

Writes DIR/curve.csv (pressure_kPa, length_mm, outer_radius_mm, chamber_volume_mm3,
max_principal_stretch, max_fiber_tension_N, status, tip_lateral_mm[, blocked_force_N]),
DIR/summary.json,
DIR/vtu/step_NNN.vtu (+ steps.pvd for ParaView) and DIR/epsa.png (length and radius against
pressure, and the deformed shape). Pressures are entered in kPa.

The free actuator is a slender pressurised column: with soft silicone it can bend over sideways
at high pressure (tip_lateral_mm grows past 5 % of the length, and the run prints a note). The
default smeared winding (--fibers sheet) is mirror-symmetric, so --side-load N (say 1e-4) adds the
small sideways imperfection that reveals such bending; --guided keeps the top on the axis, as the
rings and the other actuators do in the robot.
"""

from __future__ import annotations

import sys

from softcrawl.console import progress
from softcrawl.provenance import write_summary

# Project modules are imported inside the functions that use them: softcrawl --help stays fast.


def register(subparsers) -> None:
    from softcrawl.studies.commands.options import add_number, add_vtu_precision
    from softcrawl.studies.epsa.model import (
        DEFAULT_FIBERS,
        FIBER_MODELS,
        MAX_SIDE_LOAD_N,
        MIN_MESH_SIZE,
    )

    p = subparsers.add_parser(
        "epsa", help="simulate one actuator under a pressure ramp", description=__doc__.splitlines()[0]
    )
    p.add_argument("--chamber-radius", type=float, default=None, metavar="X", help="r0 (mm; Table 1: 3)")
    p.add_argument(
        "--fiber-turns", type=int, default=None, metavar="N", help="turns of each helix (Table 1: 20)"
    )
    p.add_argument("--outer-radius", type=float, default=None, metavar="X", help="R0 (mm; Table 1: 9)")
    p.add_argument("--length", type=float, default=None, metavar="X", help="L0 (mm; Table 1: 100)")
    p.add_argument("--design", default=None, help="ePSA design file (.json/.toml) to start from")
    p.add_argument(
        "--material",
        default="ecoflex-00-50",
        help="body material preset, or NAME@mu=VALUE (MPa) (default ecoflex-00-50; softcrawl material list)",
    )
    p.add_argument(
        "--pressures",
        default="0:100:20",
        help="kPa: START:STOP:STEP or an increasing comma list (default 0:100:20; at most "
        "1000 kPa and 200 targets)",
    )
    add_number(
        p,
        "--mesh-size",
        help="element size",
        unit="mm",
        default_text="the converged preset (about 5 mm)",
        minimum=MIN_MESH_SIZE,
        maximum=1000.0,
    )
    p.add_argument("--quick", action="store_true", help="coarse mesh (seconds; for CI and trials)")
    p.add_argument("--blocked", action="store_true", help="fix both ends: blocked force (paper Fig. 19)")
    p.add_argument(
        "--guided",
        action="store_true",
        help="keep the top on the axis (u_x = u_y = 0): no sideways bending of the free end",
    )
    p.add_argument(
        "--fibers",
        choices=FIBER_MODELS,
        default=None,
        help="Kevlar winding as embedded truss lines or as a smeared two-family sheet on the "
        f"outer surface (default {DEFAULT_FIBERS})",
    )
    add_number(
        p,
        "--side-load",
        help="small sideways force on the free top, an imperfection that shows bending over",
        unit="N",
        default_text="none",
        minimum=0.0,
        min_open=True,
        maximum=MAX_SIDE_LOAD_N,
    )
    p.add_argument("--no-vtu", action="store_true", help="skip the VTU files")
    add_vtu_precision(p)
    p.add_argument(
        "--render",
        action="store_true",
        help="also write render-PkPa.png: 3D cut-away of the reference state and of every computed "
        "state, coloured by von Mises stress (one colour scale for all)",
    )
    p.add_argument(
        "--convergence",
        metavar="SIZES",
        default=None,
        help="mesh study instead: element sizes in mm, coarse to fine (e.g. 10,5,2.5); "
        "extension at the last pressure -> convergence.csv",
    )
    p.add_argument("--out", required=True, help="output folder (created if needed)")
    p.set_defaults(func=run)


def design_from_args(args):
    from softcrawl.geometry.design import EPSADesign

    base = EPSADesign.load(args.design, parameter="design") if args.design else EPSADesign()
    changes = {
        k: v
        for k, v in (
            ("chamber_radius", args.chamber_radius),
            ("fiber_turns", args.fiber_turns),
            ("outer_radius", args.outer_radius),
            ("length", args.length),
        )
        if v is not None
    }
    return base.replace(**changes) if changes else base


def _end_condition(args) -> str:
    return "blocked" if args.blocked else "guided top" if args.guided else "free end"


def run(args) -> int:
    from softcrawl.geometry.design import DesignError
    from softcrawl.studies.commands.options import (
        body_material,
        make_folder,
        output_folder,
        parse_pressures,
        parse_sizes,
    )
    from softcrawl.studies.epsa.model import DEFAULT_FIBERS, check_end_conditions, resolve_mesh
    from softcrawl.studies.epsa.plot_run import plot_epsa
    from softcrawl.studies.epsa.response import simulate_epsa
    from softcrawl.studies.sweeps.tables import write_csv

    # every input is checked before the output folder is made and any mesh is built
    design = design_from_args(args)
    pressures = parse_pressures(args.pressures)
    body_material(args.material)
    check_end_conditions(args.blocked, args.guided, None, args.side_load)
    args.fibers = args.fibers or DEFAULT_FIBERS
    if args.convergence:
        sizes = parse_sizes(args.convergence)
        for h in sizes:
            try:
                resolve_mesh(design, mesh_size=h)
            except DesignError as exc:
                raise exc.renamed("convergence") from None
        return run_convergence(args, design, pressures, sizes, output_folder(args.out))
    resolve_mesh(design, mesh_size=args.mesh_size, quick=args.quick)
    out = output_folder(args.out)
    print(
        f"ePSA {design.short_hash()}: r0 = {design.chamber_radius} mm, N = {design.fiber_turns}, "
        f"material {args.material}, {args.fibers} fibers, {_end_condition(args)}, "
        f"{len(pressures)} pressure targets up to {pressures[-1]:g} kPa",
        flush=True,
    )
    solved = simulate_epsa(
        design,
        material=args.material,
        pressures_kpa=pressures,
        quick=args.quick,
        mesh_size=args.mesh_size,
        blocked=args.blocked,
        guided=args.guided,
        keep_model=True,
        fibers=args.fibers,
        side_load_n=args.side_load,
        progress=lambda msg: progress("  " + msg),
    )
    curve = solved.curve
    make_folder(out)
    write_csv(curve.table(args.blocked), out / "curve.csv")
    summary = curve.to_dict()
    summary["limit_point"] = (
        f"limit point at P ~ {curve.limit_pressure_kpa:.4g} kPa"
        if curve.limit_pressure_kpa is not None
        else None
    )
    if curve.volumetric_error:
        summary["volumetric_error_last_state"] = dict(
            zip(("pressure_kpa", "max", "volume_average"), curve.volumetric_error[-1])
        )
    write_summary(out / "summary.json", summary)
    if not args.no_vtu:
        from softcrawl.fem.vtu import write_path

        files = write_path(out / "vtu", solved.model, solved.path, stem="step", precision=args.vtu_precision)
        print(f"  wrote {len(files)} VTU states from 0 kPa on: {out / 'vtu' / 'step.pvd'}", flush=True)
    plot_epsa(out / "epsa.png", curve, solved.model, solved.path, side_load_n=args.side_load)
    if args.render:
        from softcrawl.studies.epsa.plot_renders import render_path

        for path in render_path(out, design, solved, args.material):
            print(f"  wrote {path}", flush=True)
    for event in curve.events:
        if "sways" in event:
            print(f"note: {event}")
    print(
        f"{curve.message}; {curve.n_dofs} DOFs, {curve.wall_s:.1f} s "
        f"-> {out} (curve.csv, summary.json, epsa.png)"
    )
    print(f"material law: {curve.material_law}")
    if curve.volumetric_error:
        p_kpa, vmax, vmean = curve.volumetric_error[-1]
        print(f"volumetric constraint |J - 1 - p/K| at {p_kpa:.4g} kPa: max {vmax:.3g}, mean {vmean:.3g}")
    if curve.limit_pressure_kpa is not None:
        print(f"limit point at P ~ {curve.limit_pressure_kpa:.4g} kPa")
    if not curve.converged:
        print(f"warning: {curve.message}", file=sys.stderr)
    return 0


def run_convergence(args, design, pressures, sizes, out) -> int:
    from softcrawl.studies.commands.options import make_folder
    from softcrawl.studies.epsa.convergence import convergence_table, mesh_convergence
    from softcrawl.studies.sweeps.tables import write_csv

    rows = mesh_convergence(
        design,
        material=args.material,
        pressure_kpa=pressures[-1],
        sizes=sizes,
        steps=len(pressures),
        fibers=args.fibers,
        progress=lambda m: progress("  " + m),
    )
    make_folder(out)
    write_csv(convergence_table(rows), out / "convergence.csv")
    print(f"-> {out / 'convergence.csv'}")
    return 0
