"""`softcrawl material`: list the material presets and fit hyperelastic constants to tensile data.

    softcrawl material list [--json]
    softcrawl material show NAME [--json]
    softcrawl material fit [--data NAME|PATH] [--model neo-hookean|yeoh|gent] [--max-strain X]
                           [--weighting absolute|relative]
                           [--out DIR] [--json]
    softcrawl material fit-table [--max-strain X] [--json]

Units: moduli in MPa, density in t/mm^3, strain is engineering strain (stretch - 1).
"""

from __future__ import annotations

import argparse

# Project modules are imported inside the functions that use them: softcrawl --help stays fast.
from softcrawl.studies.commands.options import add_json, write_json

DATA_CHOICES_HELP = "ecoflex-00-50 | ecoflex-00-30 | dragon-skin-30 | PATH to a CSV"


def register(subparsers) -> None:
    from softcrawl.fem.laws import LAWS

    parser = subparsers.add_parser(
        "material", help="material presets and tensile-data fits", description=__doc__.splitlines()[0]
    )
    sub = parser.add_subparsers(dest="material_command", required=True)

    list_parser = sub.add_parser("list", help="table of the material presets")
    add_json(list_parser)
    list_parser.set_defaults(func=_run_list)

    show = sub.add_parser("show", help="all constants of one preset")
    show.add_argument("name", help="preset name (see `softcrawl material list`)")
    add_json(show)
    show.set_defaults(func=_run_show)

    fit = sub.add_parser("fit", help="fit a law's constants (--model) to uniaxial tensile data")
    fit.add_argument("--data", default="ecoflex-00-50", help=f"{DATA_CHOICES_HELP} (default ecoflex-00-50)")
    fit.add_argument(
        "--model",
        default="neo-hookean",
        choices=tuple(LAWS),
        help="law (default neo-hookean)",
    )
    fit.add_argument(
        "--weighting",
        default="absolute",
        choices=("absolute", "relative"),
        help="least-squares residuals in MPa (default) or relative to the measured stress (full-range fits)",
    )
    _max_strain_option(fit, "upper engineering strain of the fit (1.0: stretch 2, the actuator's range)")
    fit.add_argument("--out", default=None, help="folder for fit.json and fit.png (created if needed)")
    add_json(fit)
    fit.set_defaults(func=_run_fit)

    table = sub.add_parser("fit-table", help="every law fitted to every shipped data set")
    _max_strain_option(table, "upper engineering strain of the fits")
    add_json(table)
    table.set_defaults(func=_run_fit_table)


#: Largest upper strain of a fit: 100 (stretch 101), beyond any elastomer's elongation at break
#: (Ecoflex 00-50: ~9); the fit then simply uses every point of the test.
MAX_FIT_STRAIN = 100.0


def _max_strain_option(parser, help_text: str) -> None:
    from softcrawl.studies.commands.options import add_number

    add_number(
        parser,
        "--max-strain",
        help=help_text,
        default_text="1.0",
        minimum=0.0,
        min_open=True,
        maximum=MAX_FIT_STRAIN,
    )


# -- list / show --------------------------------------------------------------------------------


def _run_list(args: argparse.Namespace) -> int:
    from softcrawl import materials

    records = [materials.get_material(name) for name in materials.material_names()]
    if args.json:
        write_json(args.json, [m.to_dict() for m in records])
        return 0
    header = (
        f"{'name':<20} {'model':<15} {'mu [MPa]':>10} {'K [MPa]':>10} {'E [MPa]':>10} "
        f"{'nu':>7} {'rho [t/mm^3]':>12}  source"
    )
    print(header)
    for m in records:
        print(
            f"{m.name:<20} {m.model:<15} {m.mu:>10.4g} {m.bulk:>10.4g} "
            f"{m.youngs_modulus:>10.4g} {m.poisson_ratio:>7.4f} {m.density:>12.3g}  "
            f"{_first_clause(m.source)}"
        )
    print(
        "Full source text: softcrawl material show NAME. Fit presets are derived from the Soft "
        "Robotics Materials Database (ODbL 1.0 / DbCL 1.0), see softcrawl/materials/data/README.md."
    )
    return 0


def _first_clause(text: str, width: int = 70) -> str:
    return text if len(text) <= width else text[: width - 3] + "..."


def _run_show(args: argparse.Namespace) -> int:
    from softcrawl import materials

    record = materials.get_material(args.name).to_dict()
    if args.json:
        write_json(args.json, record)
    else:
        for key, value in record.items():
            print(f"{key:<15} {value}")
    return 0


# -- fit ------------------------------------------------------------------------------------------


def _max_strain(args: argparse.Namespace) -> float:
    from softcrawl import materials

    return materials.DEFAULT_MAX_STRAIN if args.max_strain is None else args.max_strain


def _fit_record(data, fit) -> dict:
    from softcrawl import materials

    record = {"data": data.name, "file": data.path}
    record.update(fit.to_dict())
    record["units"] = {
        "params": "MPa",
        "strain": "engineering strain (stretch - 1)",
        "rms_error": "MPa, on nominal (engineering) stress",
    }
    if data.attribution:
        record["attribution"] = data.attribution
        record["license"] = materials.DATA_LICENSE
    else:
        record["attribution"] = "user-supplied file"
    return record


def _run_fit(args: argparse.Namespace) -> int:
    from softcrawl import jsonio, materials
    from softcrawl.studies.commands.options import make_folder, output_folder
    from softcrawl.studies.material.plot_fit import plot_fit

    if args.out is not None:
        output_folder(args.out)  # before the fit: a bad folder is reported first

    data = materials.load_tensile(args.data)
    fit = materials.fit_tensile(data, args.model, _max_strain(args), args.weighting)
    record = _fit_record(data, fit)
    if args.out is not None:
        out = make_folder(args.out)
        jsonio.write(out / "fit.json", record)
        plot_fit(data, fit, out / "fit.png")
        record["outputs"] = [str(out / "fit.json"), str(out / "fit.png")]
    if args.json:
        write_json(args.json, record)
    else:
        _print_fit(record)
    return 0


def _print_fit(record: dict) -> None:
    params = ", ".join(f"{k} = {v:.5g} MPa" for k, v in record["params_mpa"].items())
    lo, hi = record["strain_range"]
    print(f"{record['data']}: {record['model']} {params}")
    print(f"  initial shear modulus {record['initial_shear_modulus_mpa']:.5g} MPa")
    print(
        f"  strain range {lo:.3f}-{hi:.3f} (max_strain {record['max_strain']:g}), {record['n_points']} points"
    )
    print(
        f"  RMS error {record['rms_error_mpa']:.3g} MPa ({100 * record['relative_rms_error']:.2f} %"
        f" of RMS stress), R^2 = {record['r_squared']:.5f}"
    )
    for note in record["notes"]:
        print(f"  note: {note}")
    for path in record.get("outputs", []):
        print(f"  wrote {path}")
    print(f"  {record['attribution']}")


def _run_fit_table(args: argparse.Namespace) -> int:
    from softcrawl import materials
    from softcrawl.fem.laws import LAWS

    records = []
    for name in materials.TENSILE_FILES:
        data = materials.load_tensile(name)
        for model in LAWS:
            records.append(_fit_record(data, materials.fit_tensile(data, model, _max_strain(args))))
    if args.json:
        write_json(args.json, records)
        return 0
    print(
        f"{'data':<15} {'model':<12} {'constants [MPa]':<44} {'mu0 [MPa]':>9} {'strain':>11} "
        f"{'n':>3} {'RMS [MPa]':>9} {'rel':>6} {'R^2':>7}"
    )
    for r in records:
        params = ", ".join(f"{k}={v:.4g}" for k, v in r["params_mpa"].items())
        lo, hi = r["strain_range"]
        print(
            f"{r['data']:<15} {r['model']:<12} {params:<44} {r['initial_shear_modulus_mpa']:>9.4g}"
            f" {lo:>5.3f}-{hi:<5.3f} {r['n_points']:>3} {r['rms_error_mpa']:>9.2g} "
            f"{100 * r['relative_rms_error']:>5.1f}% {r['r_squared']:>7.4f}"
        )
    notes = sorted({f"{r['data']} {r['model']}: {n}" for r in records for n in r["notes"]})
    for note in notes:
        print(f"note: {note}")
    print(materials.DATA_ATTRIBUTION)
    print(materials.DATA_LICENSE)
    return 0
