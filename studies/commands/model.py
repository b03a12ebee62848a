"""`softcrawl model ...`: the paper's analytic models (package `robot`).

Subcommands: statics, fk, ik, load, speed, identify (here) and workspace, plan, elbow-scan
(`studies.commands.model_planning`). Pressures are entered in kPa, lengths in mm, masses in g,
gravity in m/s^2; `--json` prints a JSON object on stdout instead of text. Every number is checked
against the ranges of `analytic.limits` when it is parsed.
"""

from __future__ import annotations

from softcrawl.analytic.limits import (
    MAX_FORCE_N,
    MAX_G,
    MAX_LENGTH_MM,
    MAX_MASS_G,
    MAX_PRESSURE_KPA,
    MAX_SPEED_MM_S,
    MAX_TIME_S,
)
from softcrawl.paper import D_MM, F_EPSA_MAX_N, FRICTION_N, G_EQ27_M_S2, ROBOT_MASS_G, table2
from softcrawl.studies.commands.options import add_alias, add_json, add_length, add_number, emit

# Project modules are imported inside the functions that use them: softcrawl --help stays fast.


def _g(args) -> float:
    return args.g * 1000.0  # m/s^2 -> mm/s^2 (the range is checked when parsed)


def add_gravity(parser, default: float, help: str, positive: bool = False) -> None:
    add_number(
        parser, "--g", help=help, unit="m/s^2", default=default, minimum=0.0, min_open=positive, maximum=MAX_G
    )


# -- statics, kinematics, loads --------------------------------------------------------------


def _statics(args) -> int:
    from softcrawl.analytic.prototype import nominal_epsa, prototype_epsa

    a = nominal_epsa() if args.actuator == "nominal" else prototype_epsa(int(args.actuator))
    g, p = _g(args), args.pressure
    length, force = float(a.length(p, g)), float(a.blocked_force(p, g))
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
    emit(
        args,
        payload,
        f"{a.name} at {p:g} kPa (g = {args.g:g} m/s^2): length {length:.3f} mm "
        f"(extension {length - a.l0:.3f} mm), blocked force {force:.3f} N",
    )
    return 0


def _fk(args) -> int:
    from softcrawl.analytic import kinematics as kin

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
    emit(
        args,
        payload,
        f"kappa {k:.7g} 1/mm, theta {t:.6g} rad, phi {p:.6g} rad, "
        f"tip ({tip[0]:.3f}, {tip[1]:.3f}, {tip[2]:.3f}) mm",
    )
    return 0


def _ik(args) -> int:
    from softcrawl.analytic import kinematics as kin

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
    emit(args, payload, "lengths " + " ".join(f"{v:.4f}" for v in lengths) + " mm")
    return 0


def _load(args) -> int:
    from softcrawl.analytic.loads import theoretical_load

    m = theoretical_load(args.force, args.robot_mass * 1e-6, _g(args)) * 1e3  # tonne -> kg
    payload = dict(force_n=args.force, robot_mass_g=args.robot_mass, g_m_s2=args.g, load_kg=m)
    emit(
        args,
        payload,
        f"theoretical load {m:.3f} kg (F = {args.force:g} N, M_r = "
        f"{args.robot_mass:g} g, g = {args.g:g} m/s^2)",
    )
    return 0


def _speed(args) -> int:
    from softcrawl.analytic.dynamics import gait_stride
    from softcrawl.analytic.loads import crawl_speed, friction_for_speed
    from softcrawl.analytic.prototype import actuator_set

    acts = actuator_set(args.actuators)
    est = crawl_speed(acts, args.pressure, args.friction, args.cycle, _g(args))
    need = friction_for_speed(acts, args.pressure, args.paper_speed, args.cycle, _g(args))
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
    emit(
        args,
        payload,
        f"stride {est.stride_mm:.2f} mm, speed {est.speed_mm_s:.2f} mm/s at "
        f"{args.cycle:g} s cycle (paper {args.paper_speed:g} mm/s; the model "
        f"matches it with {need:.2f} N total friction); friction-free with eq. (1) "
        f"dynamics over a {0.75 * args.cycle:g} s + {0.25 * args.cycle:g} s cycle: "
        f"{sum(dyn) / 3.0 / args.cycle:.2f} mm/s",
    )
    return 0


def _breakpoint(text: str):
    """--breakpoint: 'fit' or a pressure in (0, 100) kPa."""
    import argparse

    if text.strip().lower() == "fit":
        return "fit"
    from softcrawl.studies.commands.options import number_type

    try:
        return number_type(minimum=0.0, maximum=100.0, min_open=True, max_open=True, unit="kPa")(text)
    except argparse.ArgumentTypeError as exc:
        raise argparse.ArgumentTypeError(f"'fit' or {exc}") from None


def _identify(args) -> int:
    from softcrawl.analytic.identification import identify, read_table

    P, W, y = read_table(args.table)
    bp = None if args.breakpoint == "fit" else float(args.breakpoint)
    r = identify(P, W, y, mass_t=args.mass * 1e-6, g=_g(args), breakpoint=bp)

    def lines(pw, scale):
        out = {"breakpoint_kpa": pw.breakpoint_kpa, "low": [pw.low.slope * scale, pw.low.intercept * scale]}
        if pw.high is not None:
            out["high"] = [pw.high.slope * scale, pw.high.intercept * scale]
        return out

    per = r.per_pressure
    payload = dict(
        table=str(args.table),
        k_p_n_per_m=lines(r.k_p, 1e3),
        f_p_n=lines(r.f_p, 1.0),
        per_pressure=[
            dict(pressure_kpa=float(p), k_p_n_per_m=float(k) * 1e3, f_p_n=float(f), rms_mm=float(e))
            for p, k, f, e in zip(per.pressure_kpa, per.k_p, per.f_p, per.rms_mm)
        ],
    )
    kp, fp = payload["k_p_n_per_m"], payload["f_p_n"]
    emit(args, payload, f"k_p [N/m] = {kp}\nf_p [N] = {fp}")
    return 0


# -- parsers -------------------------------------------------------------------------------------


def _register_statics(sub) -> None:
    s = sub.add_parser("statics", help="ePSA length and blocked force at a pressure (eq. 3)")
    add_json(s)
    add_number(
        s, "--pressure", help="pressure", unit="kPa", required=True, minimum=0.0, maximum=MAX_PRESSURE_KPA
    )
    s.add_argument(
        "--actuator", choices=["1", "2", "3", "nominal"], default="1", help="prototype ePSA (default 1)"
    )
    add_gravity(s, 9.81, "gravity along the axis (0 = horizontal)")
    s.set_defaults(func=_statics)

    s = sub.add_parser("fk", help="lengths -> kappa, theta, phi, tip (eqs. 4-6, 9)")
    add_json(s)
    add_length(s, "--lengths", "the three ePSA lengths", nargs=3, required=True, metavar=("L1", "L2", "L3"))
    add_length(s, "--d", "actuator circle radius", default=D_MM)
    s.set_defaults(func=_fk)

    s = sub.add_parser("ik", help="tip -> lengths (exact inverse of fk)")
    add_json(s)
    add_number(
        s,
        "--tip",
        help="tip position",
        unit="mm",
        nargs=3,
        required=True,
        metavar=("X", "Y", "Z"),
        minimum=-MAX_LENGTH_MM,
        maximum=MAX_LENGTH_MM,
    )
    add_length(s, "--d", "actuator circle radius", default=D_MM)
    s.set_defaults(func=_ik)


def _register_loads(sub) -> None:
    s = sub.add_parser("load", help="theoretical load (eq. 27)")
    add_json(s)
    add_number(
        s,
        "--force",
        help="ePSA output force",
        unit="N",
        default=F_EPSA_MAX_N,
        minimum=0.0,
        maximum=MAX_FORCE_N,
    )
    add_number(
        s, "--robot-mass", help="robot mass", unit="g", default=ROBOT_MASS_G, minimum=0.0, maximum=MAX_MASS_G
    )
    add_gravity(s, G_EQ27_M_S2, "gravity (the paper used 10)", positive=True)
    s.set_defaults(func=_load)

    s = sub.add_parser("speed", help="stride and crawling speed with friction (eq. 25)")
    add_json(s)
    add_number(s, "--pressure", help="gait pressure", unit="kPa", default=100.0, minimum=0.0, maximum=100.0)
    add_number(
        s,
        "--friction",
        help="total sliding friction",
        unit="N",
        default=FRICTION_N["forward"],
        minimum=0.0,
        maximum=MAX_FORCE_N,
    )
    cycle = add_number(
        s,
        "--cycle-time",
        dest="cycle",
        help="cycle time",
        unit="s",
        default=2.0,
        minimum=0.0,
        min_open=True,
        maximum=MAX_TIME_S,
    )
    add_alias(s, cycle, "--cycle")
    add_gravity(s, 0.0, "axial gravity (0 = horizontal)")
    s.add_argument(
        "--actuators",
        choices=["nominal", "prototype"],
        default="prototype",
        help="identified laws: the nominal ePSA for all three, or the three prototypes (default prototype)",
    )
    add_number(
        s,
        "--paper-speed",
        help="speed to compare with",
        unit="mm/s",
        default=table2(70.0, "forward"),
        minimum=0.0,
        maximum=MAX_SPEED_MM_S,
    )
    s.set_defaults(func=_speed)

    s = sub.add_parser("identify", help="fit k_p, f_p from a (P, load, extension) CSV")
    add_json(s)
    s.add_argument("--table", required=True, help="CSV with columns pressure_kpa, load_n, extension_mm")
    s.add_argument(
        "--breakpoint", type=_breakpoint, default="60", help="kPa in (0, 100), or 'fit' (default 60)"
    )
    add_number(s, "--mass", help="ePSA mass", unit="g", default=23.4, minimum=0.0, maximum=MAX_MASS_G)
    add_gravity(s, 9.81, "gravity along the axis")
    s.set_defaults(func=_identify)


def register(subparsers) -> None:
    from softcrawl.studies.commands import model_planning

    p = subparsers.add_parser(
        "model",
        help="the paper's analytic models (statics, kinematics, planning)",
        description=__doc__.splitlines()[0],
    )
    sub = p.add_subparsers(dest="model_command", required=True, parser_class=type(p))
    _register_statics(sub)
    _register_loads(sub)
    model_planning.register(sub)
