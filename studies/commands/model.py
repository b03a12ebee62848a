"""`softcrawl model ...`: the paper's analytic models (package `robot`).

Subcommands: statics, fk, ik, load, speed, identify, workspace, plan, elbow-scan. Pressures are entered
in kPa,
lengths in mm; `--json` prints a JSON object on stdout instead of text.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

from robot.errors import ModelInputError as _ArgError
from softcrawl import jsonio


def _emit(args, payload: dict, text: str) -> None:
    if getattr(args, "json", False):
        from softcrawl.jsonio import dumps

        sys.stdout.write(dumps(payload, indent=2))
        sys.stdout.write("\n")
    else:
        print(text)


def _g(args) -> float:
    if not math.isfinite(args.g) or args.g < 0:
        raise _ArgError("g", "must be a finite value >= 0 m/s^2")
    return args.g * 1000.0  # m/s^2 -> mm/s^2


def _statics(args) -> int:
    from robot.prototype import nominal_epsa, prototype_epsa

    if not math.isfinite(args.pressure) or not 0 <= args.pressure:
        raise _ArgError("pressure", "must be a finite pressure >= 0 kPa")
    a = nominal_epsa() if args.actuator == "nominal" else prototype_epsa(int(args.actuator))
    g = _g(args)
    p = args.pressure
    length = float(a.length(p, g))
    force = float(a.blocked_force(p, g))
    payload = dict(
        actuator=a.name,
        pressure_kpa=p,
        g_m_s2=args.g,
        length_mm=length,
        extension_mm=length - a.l0,
        blocked_force_n=force,
        k_p_n_per_m=float(a.k_p(p)) * 1e3,
        f_p_n=float(a.f_p(p)),
        branch="low" if p <= a.k_p.breakpoint_kpa else "high",
    )
    lo, hi, jump = a.length_jump(g)
    payload["at_breakpoint_mm"] = dict(
        pressure_kpa=a.k_p.breakpoint_kpa, lower_branch=lo, upper_branch=hi, jump=jump
    )
    if p > 100:
        payload["warning"] = "above the identified 0-100 kPa range"
    _emit(
        args,
        payload,
        f"{a.name} at {p:g} kPa (g = {args.g:g} m/s^2): length {length:.3f} mm "
        f"(extension {length - a.l0:.3f} mm), blocked force {force:.3f} N",
    )
    return 0


def _fk(args) -> int:
    from robot import kinematics as kin

    k, t, p, lc = (float(v) for v in kin.forward(args.lengths, args.d))
    tip = [float(v) for v in kin.arc_point(t, p, lc)]
    payload = dict(
        lengths_mm=list(args.lengths),
        d_mm=args.d,
        kappa_per_mm=k,
        theta_rad=t,
        phi_rad=p,
        centreline_length_mm=lc,
        tip_mm=tip,
    )
    _emit(
        args,
        payload,
        f"kappa {k:.7g} 1/mm, theta {t:.6g} rad, phi {p:.6g} rad, "
        f"tip ({tip[0]:.3f}, {tip[1]:.3f}, {tip[2]:.3f}) mm",
    )
    return 0


def _ik(args) -> int:
    from robot import kinematics as kin

    k, t, p, lc = (float(v) for v in kin.inverse_configuration(args.tip))
    lengths = [float(v) for v in kin.inverse(args.tip, args.d)]
    payload = dict(
        tip_mm=list(args.tip),
        d_mm=args.d,
        kappa_per_mm=k,
        theta_rad=t,
        phi_rad=p,
        centreline_length_mm=lc,
        lengths_mm=lengths,
    )
    _emit(args, payload, "lengths " + " ".join(f"{v:.4f}" for v in lengths) + " mm")
    return 0


def _load(args) -> int:
    from robot.loads import theoretical_load

    g = _g(args)
    m = theoretical_load(args.force, args.robot_mass * 1e-6, g) * 1e3  # tonne -> kg
    payload = dict(force_n=args.force, robot_mass_g=args.robot_mass, g_m_s2=args.g, load_kg=m)
    _emit(
        args,
        payload,
        f"theoretical load {m:.3f} kg (F = {args.force:g} N, M_r = "
        f"{args.robot_mass:g} g, g = {args.g:g} m/s^2)",
    )
    return 0


def _speed(args) -> int:
    from robot.loads import crawl_speed, friction_for_speed
    from robot.prototype import actuator_set

    acts = actuator_set(args.actuators)
    if not 0 <= args.pressure <= 100:
        raise _ArgError("pressure", "must be within 0-100 kPa")
    est = crawl_speed(acts, args.pressure, args.friction, args.cycle, _g(args))
    need = friction_for_speed(acts, args.pressure, args.paper_speed, args.cycle, _g(args))
    from robot.dynamics import gait_stride

    dyn = [gait_stride(a, args.pressure, 0.75 * args.cycle, 0.25 * args.cycle, g=_g(args)) for a in acts]
    payload = dict(
        pressure_kpa=args.pressure,
        friction_n=args.friction,
        cycle_s=args.cycle,
        extensions_mm=list(est.extensions_mm),
        stride_mm=est.stride_mm,
        speed_mm_s=est.speed_mm_s,
        paper_speed_mm_s=args.paper_speed,
        difference_mm_s=est.speed_mm_s - args.paper_speed,
        friction_for_paper_speed_n=need,
        dynamic_friction_free_stride_mm=sum(dyn) / 3.0,
        dynamic_friction_free_speed_mm_s=sum(dyn) / 3.0 / args.cycle,
    )
    _emit(
        args,
        payload,
        f"stride {est.stride_mm:.2f} mm, speed {est.speed_mm_s:.2f} mm/s at "
        f"{args.cycle:g} s cycle (paper {args.paper_speed:g} mm/s; the model "
        f"matches it with {need:.2f} N total friction); friction-free with eq. (1) "
        f"dynamics over a {0.75 * args.cycle:g} s + {0.25 * args.cycle:g} s cycle: "
        f"{sum(dyn) / 3.0 / args.cycle:.2f} mm/s",
    )
    return 0


def _identify(args) -> int:
    from robot.identification import identify, read_table

    P, W, y = read_table(args.table)
    bp = None if args.breakpoint == "fit" else float(args.breakpoint)
    r = identify(P, W, y, mass_t=args.mass * 1e-6, g=_g(args), breakpoint=bp)

    def lines(pw, scale):
        out = {"breakpoint_kpa": pw.breakpoint_kpa, "low": [pw.low.slope * scale, pw.low.intercept * scale]}
        if pw.high is not None:
            out["high"] = [pw.high.slope * scale, pw.high.intercept * scale]
        return out

    payload = dict(
        table=str(args.table),
        k_p_n_per_m=lines(r.k_p, 1e3),
        f_p_n=lines(r.f_p, 1.0),
        per_pressure=[
            dict(pressure_kpa=float(p), k_p_n_per_m=float(k) * 1e3, f_p_n=float(f), rms_mm=float(e))
            for p, k, f, e in zip(
                r.per_pressure.pressure_kpa, r.per_pressure.k_p, r.per_pressure.f_p, r.per_pressure.rms_mm
            )
        ],
    )
    kp, fp = payload["k_p_n_per_m"], payload["f_p_n"]
    _emit(args, payload, f"k_p [N/m] = {kp}\nf_p [N] = {fp}")
    return 0


def _out_dir(path) -> Path:
    out = Path(path)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise _ArgError("out", f"cannot create {out}: {exc.strerror}") from None
    return out


def _workspace(args) -> int:
    from robot.workspace import sample, save_csv
    from studies.plots.analytic import plot_workspace

    out = _out_dir(args.out)
    ws = sample(args.n, args.actuators, args.d)
    save_csv(ws, out / "workspace.csv")
    plot_workspace(ws, out / "workspace.png")
    tip = ws.tip_mm
    payload = dict(
        points=int(tip.shape[0]),
        csv=str(out / "workspace.csv"),
        png=str(out / "workspace.png"),
        bounds_mm=dict(
            x=[float(tip[:, 0].min()), float(tip[:, 0].max())],
            y=[float(tip[:, 1].min()), float(tip[:, 1].max())],
            z=[float(tip[:, 2].min()), float(tip[:, 2].max())],
        ),
        max_theta_rad=float(ws.theta.max()),
        max_kappa_per_mm=float(ws.kappa.max()),
        min_bending_radius_mm=float(1.0 / ws.kappa.max()),
    )
    _emit(
        args,
        payload,
        f"{tip.shape[0]} tips -> {out}/workspace.csv, {out}/workspace.png; "
        f"smallest body bending radius {1.0 / ws.kappa.max():.1f} mm",
    )
    return 0


def _plan(args) -> int:
    from dataclasses import asdict

    from robot.pipe import Pipe
    from robot.planner import plan
    from studies.plots.analytic import plot_plan

    if args.pipe == "elbow" and args.bend_radius is None:
        raise _ArgError("bend-radius", "required for --pipe elbow")
    pipe = Pipe(args.pipe, args.diameter, args.bend_radius or 40.0, entry=args.length, exit=args.exit_length)
    out = _out_dir(args.out)
    if args.search == "bfs":
        from robot.planar import bfs_plan

        if args.body != "tube" or args.deflation != "paper":
            raise _ArgError("search", "bfs supports --body tube and --deflation paper only")
        print("breadth-first search over the planar gait (can take minutes):", flush=True)
        result = bfs_plan(
            pipe, actuators=args.actuators, step_kpa=args.step, progress=lambda m: print("  " + m, flush=True)
        )
    elif args.search == "continuous":
        from robot.refine import continuous_plan

        if (
            args.pipe != "elbow"
            or args.body != "tube"
            or args.deflation != "paper"
            or args.actuators != "nominal"
        ):
            raise _ArgError(
                "search",
                "continuous supports --pipe elbow, --body tube, "
                "--deflation paper and --actuators nominal only",
            )
        if args.cycles < 1:
            raise _ArgError("cycles", "must be >= 1")
        result = continuous_plan(pipe, cycles=args.cycles)
    else:
        result = plan(
            pipe,
            actuators=args.actuators,
            step_kpa=args.step,
            beam=args.beam,
            deflation=args.deflation,
            body=args.body,
            cell_mm=1.0,
            cell_deg=1.0,
        )
    cycles = [asdict(c) for c in result.cycles]
    payload = dict(
        pipe=dict(
            kind=pipe.kind,
            diameter_mm=pipe.diameter,
            bend_radius_mm=pipe.bend_radius if pipe.kind == "elbow" else None,
            goal_mm=pipe.goal(),
        ),
        success=result.success,
        message=result.message,
        cycles=len(cycles),
        body_radius_mm=result.body_radius,
        actuators=result.actuators,
        deflation=args.deflation,
        body=args.body,
        search=args.search,
        gait=[dict(phase=g[0], pressures_kpa=list(g[1:])) for g in result.gait()],
        steps=cycles,
    )
    jsonio.write(out / "plan.json", payload)
    with open(out / "gait.csv", "w") as fh:
        fh.write("cycle,phase,P1_kpa,P2_kpa,P3_kpa,rear_x,rear_y,rear_z,front_x,front_y,front_z\n")
        for c in result.cycles:
            for ph, P, feet in (
                ("inflate", c.pressures_inflated, c.rear_before + c.front),
                ("deflate", c.pressures_deflated, c.rear_after + c.front),
            ):
                fh.write(f"{c.index},{ph}," + ",".join(f"{v:.4f}" for v in P + feet) + "\n")
    plot_plan(result, out / "plan.png")
    text = [
        f"{pipe.kind}: {'through' if result.success else 'NOT through'} in {len(cycles)} "
        f"cycles ({result.message}); files in {out}"
    ]
    for c in result.cycles:
        inflate = ", ".join(f"{v:.2f}" for v in c.pressures_inflated)
        text.append(
            f"  cycle {c.index:2d}: inflate ({inflate}) kPa, deflate to "
            f"({', '.join(f'{v:.1f}' for v in c.pressures_deflated)}) kPa, rear foot at "
            f"s = {c.progress:.1f} mm, clearance {c.clearance:.3f} mm"
        )
    _emit(args, payload, "\n".join(text))
    return 0 if result.success else 1


def _elbow_scan(args) -> int:
    from robot.planner import scan_bend_radius

    if any(not r > 0 for r in args.radii):
        raise _ArgError("radii", "bend radii must be > 0 mm")
    rows = []
    for r in sorted(args.radii):
        if args.search == "bfs":
            from robot.pipe import Pipe
            from robot.planar import bfs_plan

            print(f"R = {r:g} mm: breadth-first search (can take minutes)", flush=True)
            result = bfs_plan(
                Pipe("elbow", args.diameter, r),
                step_kpa=args.step,
                progress=lambda m: print("  " + m, flush=True),
            )
        elif args.search == "continuous":
            from robot.pipe import Pipe
            from robot.refine import continuous_plan

            if args.body != "tube":
                raise _ArgError("search", "continuous supports --body tube only")
            result = continuous_plan(Pipe("elbow", args.diameter, r), cycles=args.cycles)
        else:
            ((_, result),) = scan_bend_radius(
                [r],
                args.diameter,
                step_kpa=args.step,
                beam=args.beam,
                body=args.body,
                cell_mm=1.0,
                cell_deg=1.0,
            )
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
    _emit(args, payload, f"smallest bend radius passed: {smallest} mm (of {sorted(args.radii)})")
    return 0


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "model",
        help="the paper's analytic models (statics, kinematics, planning)",
        description=__doc__.splitlines()[0],
    )
    sub = p.add_subparsers(dest="model_command", required=True, parser_class=type(p))

    def common(sp, json_flag=True):
        if json_flag:
            sp.add_argument("--json", action="store_true", help="print JSON on stdout")
        return sp

    s = common(sub.add_parser("statics", help="ePSA length and blocked force at a pressure (eq. 3)"))
    s.add_argument("--pressure", type=float, required=True, help="kPa")
    s.add_argument("--actuator", choices=["1", "2", "3", "nominal"], default="1")
    s.add_argument("--g", type=float, default=9.81, help="gravity along the axis, m/s^2 (0 = horizontal)")
    s.set_defaults(func=_statics)

    s = common(sub.add_parser("fk", help="lengths -> kappa, theta, phi, tip (eqs. 4-6, 9)"))
    s.add_argument("--lengths", type=float, nargs=3, required=True, metavar=("L1", "L2", "L3"))
    s.add_argument("--d", type=float, default=14.0, help="actuator circle radius, mm")
    s.set_defaults(func=_fk)

    s = common(sub.add_parser("ik", help="tip -> lengths (exact inverse of fk)"))
    s.add_argument("--tip", type=float, nargs=3, required=True, metavar=("X", "Y", "Z"))
    s.add_argument("--d", type=float, default=14.0, help="actuator circle radius, mm")
    s.set_defaults(func=_ik)

    s = common(sub.add_parser("load", help="theoretical load (eq. 27)"))
    s.add_argument("--force", type=float, default=8.42, help="ePSA output force, N")
    s.add_argument("--robot-mass", type=float, default=70.2, help="robot mass, g")
    s.add_argument("--g", type=float, default=10.0, help="m/s^2 (the paper used 10)")
    s.set_defaults(func=_load)

    s = common(sub.add_parser("speed", help="stride and crawling speed with friction (eq. 25)"))
    s.add_argument("--pressure", type=float, default=100.0, help="gait pressure, kPa")
    s.add_argument("--friction", type=float, default=15.3, help="total sliding friction, N")
    s.add_argument("--cycle", type=float, default=2.0, help="cycle time, s")
    s.add_argument("--g", type=float, default=0.0, help="axial gravity, m/s^2 (0 = horizontal)")
    s.add_argument("--actuators", choices=["nominal", "prototype"], default="prototype")
    s.add_argument("--paper-speed", type=float, default=18.3, help="mm/s to compare with")
    s.set_defaults(func=_speed)

    s = common(sub.add_parser("identify", help="fit k_p, f_p from a (P, load, extension) CSV"))
    s.add_argument("--table", required=True, help="CSV: pressure_kpa, load_n, extension_mm")
    s.add_argument("--breakpoint", default="60", help="kPa, or 'fit'")
    s.add_argument("--mass", type=float, default=23.4, help="ePSA mass, g")
    s.add_argument("--g", type=float, default=9.81, help="m/s^2")
    s.set_defaults(func=_identify)

    s = common(sub.add_parser("workspace", help="tip cloud over 0-100 kPa (Fig. 11(d))"))
    s.add_argument("--out", required=True)
    s.add_argument("--n", type=int, default=11, help="pressure levels per actuator")
    s.add_argument("--actuators", choices=["nominal", "prototype"], default="prototype")
    s.add_argument("--d", type=float, default=14.0)
    s.set_defaults(func=_workspace)

    s = common(sub.add_parser("plan", help="gait through a pipe (Section IV, Fig. 25)"))
    s.add_argument("--pipe", choices=["straight", "vertical", "elbow"], required=True)
    s.add_argument("--bend-radius", type=float, default=None, help="elbow centreline radius, mm")
    s.add_argument("--diameter", type=float, default=70.0, help="pipe inner diameter, mm")
    s.add_argument(
        "--length",
        type=float,
        default=150.0,
        help="straight length (straight/vertical) or entry leg (elbow), mm",
    )
    s.add_argument("--exit-length", type=float, default=150.0, help="elbow exit leg, mm")
    s.add_argument("--actuators", choices=["nominal", "prototype"], default="nominal")
    s.add_argument("--deflation", choices=["paper", "held"], default="paper")
    s.add_argument("--step", type=float, default=5.0, help="pressure grid step, kPa")
    s.add_argument("--beam", type=int, default=1, help="beam width of the search (1 = greedy)")
    s.add_argument(
        "--body",
        choices=["tube", "epsa"],
        default="tube",
        help="clearance of a 23 mm tube, or of the three 9 mm ePSA tubes",
    )
    s.add_argument(
        "--search",
        choices=["beam", "bfs", "continuous"],
        default="beam",
        help="beam search (any pipe), exhaustive planar breadth-first on the pressure "
        "grid (elbow), or continuous pressures refined by SLSQP (elbow)",
    )
    s.add_argument("--cycles", type=int, default=25, help="number of cycles of the continuous search")
    s.add_argument("--out", required=True)
    s.set_defaults(func=_plan)

    s = common(sub.add_parser("elbow-scan", help="which elbow bend radii the planner passes"))
    s.add_argument("--radii", type=float, nargs="+", required=True, help="mm")
    s.add_argument("--diameter", type=float, default=70.0)
    s.add_argument("--beam", type=int, default=32)
    s.add_argument("--step", type=float, default=5.0, help="pressure grid step, kPa")
    s.add_argument("--body", choices=["tube", "epsa"], default="tube")
    s.add_argument("--search", choices=["beam", "bfs", "continuous"], default="beam")
    s.add_argument("--cycles", type=int, default=25, help="cycles of the continuous search")
    s.set_defaults(func=_elbow_scan)
