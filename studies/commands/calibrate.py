"""`softcrawl calibrate`: the body's shear modulus that makes the FE Table 1 ePSA match the prototype.

    softcrawl calibrate [--material M] [--full-mesh] --out DIR

Finds the shear modulus mu of the body (the base material's K/mu kept) whose FE Table 1 actuator
follows the prototype statics model (mean of eqs. 19-24, g = 0) over 20-100 kPa with the least RMS
length error; writes DIR/calibration.json and DIR/calibration.png."""

from __future__ import annotations

from dataclasses import asdict

from softcrawl import jsonio
from softcrawl.console import progress

# Project modules are imported inside the functions that use them: softcrawl --help stays fast.


def register(subparsers) -> None:
    import argparse

    p = subparsers.add_parser(
        "calibrate",
        help="calibrate mu to the prototype statics (eqs. 19-24)",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument(
        "--material",
        default="ecoflex-00-50",
        help="base material, a Neo-Hookean preset (its K/mu is kept; default ecoflex-00-50)",
    )
    p.add_argument(
        "--full-mesh", action="store_true", help="the default (converged) mesh instead of the quick one"
    )
    p.add_argument("--out", required=True, help="output folder (created if needed)")
    p.set_defaults(func=run)


def run(args) -> int:
    from softcrawl.studies.commands.options import CommandLineError, body_material, make_folder, output_folder
    from softcrawl.studies.material.calibration import calibrate_mu
    from softcrawl.studies.material.plot_calibration import plot_calibration

    material = body_material(args.material)
    if type(material.law).__name__ != "NeoHookean":
        law = type(material.law).__name__
        raise CommandLineError(
            "material", f"{args.material} has a {law} law; calibrate takes a Neo-Hookean preset"
        )
    out = output_folder(args.out)
    cal = calibrate_mu(
        base_material=args.material,
        mesh="default" if args.full_mesh else "quick",
        progress=lambda m: progress("  " + m),
    )
    make_folder(out)
    jsonio.write(out / "calibration.json", asdict(cal))
    plot_calibration(cal, out / "calibration.png")
    print(
        f"calibrated mu = {cal.mu_mpa:.4f} MPa (base {cal.base_material}), RMS length error "
        f"{cal.rms_error_mm:.3g} mm -> {out}"
    )
    return 0
