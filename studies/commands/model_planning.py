"""`softcrawl model workspace | plan | elbow-scan`: the tip workspace and the gait planners.

The searches are bounded (`analytic.limits`): at most MAX_WORKSPACE_LEVELS pressure levels per
actuator, a pressure grid no finer than MIN_PLAN_STEP_KPA, a beam of at most MAX_BEAM states, at
most MAX_CONTINUOUS_CYCLES cycles of the continuous search and MAX_SCAN_RADII radii per scan.
"""

from __future__ import annotations

import argparse
from dataclasses import asdict

from softcrawl import jsonio
from softcrawl.analytic.limits import (
    MAX_BEAM,
    MAX_CONTINUOUS_CYCLES,
    MAX_LENGTH_MM,
    MAX_SCAN_RADII,
    MAX_WORKSPACE_LEVELS,
    MIN_PLAN_STEP_KPA,
)
from softcrawl.paper import D_MM, P_MAX_KPA
from softcrawl.studies.commands.options import (
    CommandLineError,
    add_json,
    add_length,
    add_number,
    emit,
    make_folder,
    output_folder,
)

# Project modules are imported inside the functions that use them: softcrawl --help stays fast.

# -- workspace -------------------------------------------------------------------------------------


def _workspace(args) -> int:
    from softcrawl.analytic.workspace import sample, save_csv
    from softcrawl.studies.plots.analytic import plot_workspace

    out = output_folder(args.out)
    ws = sample(args.n, args.actuators, args.d)
    make_folder(out)
    save_csv(ws, out / "workspace.csv")
    plot_workspace(ws, out / "workspace.png")
    tip = ws.tip_mm
    payload = dict(
        points=int(tip.shape[0]),
        csv=str(out / "workspace.csv"),
        png=str(out / "workspace.png"),
        bounds_mm={axis: [float(tip[:, i].min()), float(tip[:, i].max())] for i, axis in enumerate("xyz")},
        max_theta_rad=float(ws.theta.max()),
        max_kappa_per_mm=float(ws.kappa.max()),
        min_bending_radius_mm=float(1.0 / ws.kappa.max()),
    )
    emit(
        args,
        payload,
        f"{tip.shape[0]} tips -> {out}/workspace.csv, {out}/workspace.png; "
        f"smallest body bending radius {1.0 / ws.kappa.max():.1f} mm",
    )
    return 0


# -- plan ------------------------------------------------------------------------------------------


def _check_search(args) -> None:
    """The search variants accept only the options they implement (before any work)."""
    if args.pipe == "elbow" and args.bend_radius is None:
        raise CommandLineError("bend-radius", "required for --pipe elbow")
    if args.search == "bfs" and (args.body != "tube" or args.deflation != "paper"):
        raise CommandLineError("search", "bfs supports --body tube and --deflation paper only")
    if args.search == "continuous" and (
        args.pipe != "elbow"
        or args.body != "tube"
        or args.deflation != "paper"
        or args.actuators != "nominal"
    ):
        raise CommandLineError(
            "search",
            "continuous supports --pipe elbow, --body tube, --deflation paper and --actuators nominal only",
        )


def _search(args, pipe):
    if args.search == "bfs":
        from softcrawl.analytic.planar import bfs_plan

        print("breadth-first search over the planar gait (can take minutes):", flush=True)
        return bfs_plan(
            pipe, actuators=args.actuators, step_kpa=args.step, progress=lambda m: print("  " + m, flush=True)
        )
    if args.search == "continuous":
        from softcrawl.analytic.refine import continuous_plan

        return continuous_plan(pipe, cycles=args.cycles)
    from softcrawl.analytic.planner import plan

    return plan(
        pipe,
        actuators=args.actuators,
        step_kpa=args.step,
        beam=args.beam,
        deflation=args.deflation,
        body=args.body,
        cell_mm=1.0,
        cell_deg=1.0,
    )


def _write_gait_csv(result, path) -> None:
    with open(path, "w") as fh:
        fh.write("cycle,phase,P1_kpa,P2_kpa,P3_kpa,rear_x,rear_y,rear_z,front_x,front_y,front_z\n")
        for c in result.cycles:
            for ph, P, feet in (
                ("inflate", c.pressures_inflated, c.rear_before + c.front),
                ("deflate", c.pressures_deflated, c.rear_after + c.front),
            ):
                fh.write(f"{c.index},{ph}," + ",".join(f"{v:.4f}" for v in P + feet) + "\n")


def _plan_text(pipe, result, out) -> str:
    text = [
        f"{pipe.kind}: {'through' if result.success else 'NOT through'} in {len(result.cycles)} "
        f"cycles ({result.message}); files in {out}"
    ]
    for c in result.cycles:
        inflate = ", ".join(f"{v:.2f}" for v in c.pressures_inflated)
        text.append(
            f"  cycle {c.index:2d}: inflate ({inflate}) kPa, deflate to "
            f"({', '.join(f'{v:.1f}' for v in c.pressures_deflated)}) kPa, rear foot at "
            f"s = {c.progress:.1f} mm, clearance {c.clearance:.3f} mm"
        )
    return "\n".join(text)


def _plan(args) -> int:
    from softcrawl.analytic.cycle import pressure_grid
    from softcrawl.analytic.pipe import Pipe
    from softcrawl.studies.plots.analytic import plot_plan

    _check_search(args)
    pipe = Pipe(args.pipe, args.diameter, args.bend_radius or 40.0, entry=args.length, exit=args.exit_length)
    if args.search != "continuous":
        pressure_grid(args.step)  # a step that does not divide 100 kPa, before the folder is made
    out = output_folder(args.out)
    result = _search(args, pipe)
    payload = dict(
        pipe=dict(
            kind=pipe.kind,
            diameter_mm=pipe.diameter,
            bend_radius_mm=pipe.bend_radius if pipe.kind == "elbow" else None,
            goal_mm=pipe.goal(),
        ),
        success=result.success,
        message=result.message,
        cycles=len(result.cycles),
        body_radius_mm=result.body_radius,
        actuators=result.actuators,
        deflation=args.deflation,
        body=args.body,
        search=args.search,
        gait=[dict(phase=g[0], pressures_kpa=list(g[1:])) for g in result.gait()],
        steps=[asdict(c) for c in result.cycles],
    )
    make_folder(out)
    jsonio.write(out / "plan.json", payload)
    _write_gait_csv(result, out / "gait.csv")
    plot_plan(result, out / "plan.png")
    emit(args, payload, _plan_text(pipe, result, out))
    return 0 if result.success else 1


# -- elbow scan ------------------------------------------------------------------------------------


def _scan_one(args, radius: float):
    from softcrawl.analytic.pipe import Pipe

    if args.search == "bfs":
        from softcrawl.analytic.planar import bfs_plan

        print(f"R = {radius:g} mm: breadth-first search (can take minutes)", flush=True)
        return bfs_plan(
            Pipe("elbow", args.diameter, radius),
            step_kpa=args.step,
            progress=lambda m: print("  " + m, flush=True),
        )
    if args.search == "continuous":
        from softcrawl.analytic.refine import continuous_plan

        return continuous_plan(Pipe("elbow", args.diameter, radius), cycles=args.cycles)
    from softcrawl.analytic.planner import scan_bend_radius

    ((_, result),) = scan_bend_radius(
        [radius], args.diameter, step_kpa=args.step, beam=args.beam, body=args.body, cell_mm=1.0, cell_deg=1.0
    )
    return result


def _elbow_scan(args) -> int:
    from softcrawl.analytic.cycle import pressure_grid
    from softcrawl.analytic.pipe import Pipe

    if len(args.radii) > MAX_SCAN_RADII:
        raise CommandLineError("radii", f"{len(args.radii)} radii; at most {MAX_SCAN_RADII} per scan")
    if args.search == "continuous" and args.body != "tube":
        raise CommandLineError("search", "continuous supports --body tube only")
    for r in args.radii:
        Pipe("elbow", args.diameter, r)  # every pipe is valid before the first plan runs
    pressure_grid(args.step)
    rows = []
    for r in sorted(args.radii):
        result = _scan_one(args, r)
        rows.append(
            dict(
                bend_radius_mm=r,
                success=result.success,
                cycles=len(result.cycles),
                rear_progress_mm=result.cycles[-1].progress if result.cycles else 0.0,
            )
        )
        if not args.json:
            print(
                f"R = {r:g} mm: {'through' if result.success else 'stuck'} after {len(result.cycles)} cycles",
                flush=True,
            )
    passed = [row["bend_radius_mm"] for row in rows if row["success"]]
    smallest = min(passed) if passed else None
    payload = dict(
        diameter_mm=args.diameter,
        beam=args.beam,
        step_kpa=args.step,
        body=args.body,
        search=args.search,
        smallest_passed_mm=smallest,
        rows=rows,
    )
    emit(args, payload, f"smallest bend radius passed: {smallest} mm (of {sorted(args.radii)})")
    return 0


# -- parsers ---------------------------------------------------------------------------------------


def _add_search_options(s, beam: int) -> None:
    add_number(
        s,
        "--step",
        help="pressure grid step, dividing 100 kPa",
        unit="kPa",
        default=5.0,
        minimum=MIN_PLAN_STEP_KPA,
        maximum=P_MAX_KPA,
    )
    add_number(
        s,
        "--beam",
        help="beam width of the search (1 = greedy)",
        default=beam,
        minimum=1,
        maximum=MAX_BEAM,
        integer=True,
    )
    add_number(
        s,
        "--cycles",
        help="number of cycles of the continuous search",
        default=25,
        minimum=1,
        maximum=MAX_CONTINUOUS_CYCLES,
        integer=True,
    )
    s.add_argument(
        "--body",
        choices=["tube", "epsa"],
        default="tube",
        help="clearance of a 23 mm tube, or of the three 9 mm ePSA tubes (default tube)",
    )


def register(sub: argparse._SubParsersAction) -> None:
    s = sub.add_parser("workspace", help="tip cloud over 0-100 kPa (Fig. 11(d))")
    add_json(s)
    s.add_argument("--out", required=True, help="output folder (created if needed)")
    add_number(
        s,
        "--n",
        help="pressure levels per actuator (n^3 tips)",
        default=11,
        minimum=2,
        maximum=MAX_WORKSPACE_LEVELS,
        integer=True,
    )
    s.add_argument(
        "--actuators",
        choices=["nominal", "prototype"],
        default="prototype",
        help="identified laws: the nominal ePSA for all three, or the three prototypes (default prototype)",
    )
    add_length(s, "--d", "actuator circle radius", default=D_MM)
    s.set_defaults(func=_workspace)

    s = sub.add_parser("plan", help="gait through a pipe (Section IV, Fig. 25)")
    add_json(s)
    s.add_argument("--pipe", choices=["straight", "vertical", "elbow"], required=True, help="pipe shape")
    add_length(s, "--bend-radius", "elbow centreline radius", default_text="none, required for --pipe elbow")
    add_length(s, "--diameter", "pipe inner diameter", default=70.0)
    add_length(s, "--length", "straight length (straight/vertical) or entry leg (elbow)", default=150.0)
    add_number(
        s,
        "--exit-length",
        help="elbow exit leg",
        unit="mm",
        default=150.0,
        minimum=0.0,
        maximum=MAX_LENGTH_MM,
    )
    s.add_argument(
        "--actuators",
        choices=["nominal", "prototype"],
        default="nominal",
        help="identified laws: the nominal ePSA for all three, or the three prototypes (default nominal)",
    )
    s.add_argument(
        "--deflation", choices=["paper", "held"], default="paper", help="deflation rule (default paper)"
    )
    _add_search_options(s, beam=1)
    s.add_argument(
        "--search",
        choices=["beam", "bfs", "continuous"],
        default="beam",
        help="beam search (any pipe), exhaustive planar breadth-first on the pressure "
        "grid (elbow), or continuous pressures refined by SLSQP (elbow) (default beam)",
    )
    s.add_argument("--out", required=True, help="output folder (created if needed)")
    s.set_defaults(func=_plan)

    s = sub.add_parser("elbow-scan", help="which elbow bend radii the planner passes")
    add_json(s)
    add_length(s, "--radii", f"bend radii (at most {MAX_SCAN_RADII})", nargs="+", required=True)
    add_length(s, "--diameter", "pipe inner diameter", default=70.0)
    _add_search_options(s, beam=32)
    s.add_argument(
        "--search",
        choices=["beam", "bfs", "continuous"],
        default="beam",
        help="planner (see model plan --help; default beam)",
    )
    s.set_defaults(func=_elbow_scan)
