"""`softcrawl calibrate --out DIR`: the body's shear modulus that makes the FE Table 1 ePSA match the
prototype statics model (eqs. 19-24) over 0-100 kPa; writes calibration.json and calibration.png."""

from __future__ import annotations

from dataclasses import asdict
from pathlib import Path

from softcrawl import jsonio


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "calibrate",
        help="calibrate mu to the prototype statics (eqs. 19-24)",
        description=__doc__.splitlines()[0],
    )
    p.add_argument("--material", default="ecoflex-00-50", help="base material (its K/mu is kept)")
    p.add_argument("--full-mesh", action="store_true", help="default mesh instead of the quick one")
    p.add_argument("--out", required=True, help="output folder")
    p.set_defaults(func=run)


def run(args) -> int:
    from studies.catalogue.calibration import calibrate_mu
    from studies.plots.calibration import plot_calibration

    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    cal = calibrate_mu(
        base_material=args.material,
        mesh="default" if args.full_mesh else "quick",
        progress=lambda m: print("  " + m, flush=True),
    )
    jsonio.write(out / "calibration.json", asdict(cal))
    plot_calibration(cal, out / "calibration.png")
    print(
        f"calibrated mu = {cal.mu_mpa:.4f} MPa (base {cal.base_material}), RMS length error "
        f"{cal.rms_error_mm:.3g} mm -> {out}"
    )
    return 0
