"""`softcrawl mesh {epsa,foot,ring,robot}`: mesh one part or the robot and write it to a folder.

Writes DIR/mesh.vtu, DIR/mesh.msh (Gmsh 2.2 with named physical groups), DIR/mesh.json (counts,
volume, area per tag, fiber length, quality, design and its hash), DIR/design.json and DIR/mesh.png
(off-screen render). Design parameters are options named after the dataclass fields, dashed
(``--chamber-radius 4``; the field's own ``--chamber_radius`` is accepted with a deprecation
warning); for the robot, part parameters are prefixed with the part (``--epsa.chamber-radius 4``,
``--foot.angle 100``, ``--ring.thickness 4``). ``--mesh-size`` (formerly ``--edge-length``) is the
target tet edge. ``--design FILE``
starts from a saved design (.json/.toml); options override it.
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import logging
import sys
import typing

# Project modules are imported inside the functions that use them: softcrawl --help stays fast.

KINDS = ("epsa", "foot", "ring", "robot")


def _design_classes():
    from softcrawl.geometry import design as d

    return {"epsa": d.EPSADesign, "foot": d.FootDesign, "ring": d.RingDesign, "robot": d.RobotDesign}


def _scalar_fields(cls) -> list[tuple[str, type]]:
    hints = typing.get_type_hints(cls)
    out = []
    for f in dataclasses.fields(cls):
        t = hints[f.name]
        if t == float | None:  # a derived default (FootDesign.hub_thickness): set it as a float
            t = float
        if t in (int, float):
            out.append((f.name, t))
    return out


def _add_param(parser, name: str, typ: type, field: dataclasses.Field, default) -> None:
    """A design field as an option; the design class checks its value (and names it)."""
    from softcrawl.studies.commands.options import add_alias

    doc, unit = field.metadata.get("doc", name), field.metadata.get("unit", "")
    action = parser.add_argument(
        "--" + name.replace("_", "-"),
        dest=f"p:{name}",
        type=typ,
        default=None,
        metavar=typ.__name__.upper(),
        help=f"{doc} ({unit + '; ' if unit else ''}default {default:g})",
    )
    if "_" in name:  # the field's own spelling, accepted with a deprecation warning
        add_alias(parser, action, f"--{name}")


def _add_design_options(parser, kind: str, classes: dict) -> None:
    from softcrawl.geometry.design import RobotDesign

    default = classes[kind]()
    for name, typ in _scalar_fields(classes[kind]):
        field = next(f for f in dataclasses.fields(classes[kind]) if f.name == name)
        _add_param(parser, name, typ, field, getattr(default, name))
    if kind == "robot":
        robot = RobotDesign()
        for part in ("epsa", "foot", "ring"):
            for name, typ in _scalar_fields(classes[part]):
                field = next(f for f in dataclasses.fields(classes[part]) if f.name == name)
                _add_param(parser, f"{part}.{name}", typ, field, getattr(getattr(robot, part), name))


def register(subparsers) -> None:
    from softcrawl.geometry.design import EPSADesign, FootDesign, RingDesign, RobotDesign
    from softcrawl.geometry.foot_meshers import FOOT_MESHERS
    from softcrawl.geometry.tetwild import MAX_EDGE_LENGTH, MIN_EDGE_LENGTH
    from softcrawl.studies.commands.options import add_alias, add_number

    classes = {"epsa": EPSADesign, "foot": FootDesign, "ring": RingDesign, "robot": RobotDesign}
    parser = subparsers.add_parser(
        "mesh", help="tetrahedral mesh of a part or of the robot", description=__doc__.splitlines()[0]
    )
    kinds = parser.add_subparsers(dest="kind", required=True, parser_class=type(parser))
    for kind in KINDS:
        sp = kinds.add_parser(kind, help=f"mesh the {kind}", description=f"Mesh the {kind} (pytetwild).")
        sp.add_argument("--out", required=True, help="output folder (created if needed)")
        sp.add_argument("--design", default=None, help="design file (.json or .toml) to start from")
        edge = add_number(
            sp,
            "--mesh-size",
            dest="edge_length",
            help="target tet edge length",
            unit="mm",
            default_text="5 %% of the part's bounding-box diagonal",
            minimum=MIN_EDGE_LENGTH,
            maximum=MAX_EDGE_LENGTH,
        )
        add_alias(sp, edge, "--edge-length")
        sp.add_argument(
            "--cache-dir",
            default=None,
            help="mesh cache (default $SOFTCRAWL_CACHE or ~/.cache/softcrawl/meshes)",
        )
        sp.add_argument("--no-cache", action="store_true", help="always mesh anew")
        sp.add_argument("--no-png", action="store_true", help="skip the PNG render")
        if kind == "foot":
            sp.add_argument(
                "--mesher",
                default="tetwild",
                choices=FOOT_MESHERS,
                help="tetwild (default) or revolved: the foot study's structured mesh, three cells "
                "through the skirt (geometry.foot_revolved; no --mesh-size, no cache)",
            )
        _add_design_options(sp, kind, classes)
        sp.set_defaults(func=run)


def build_design(kind: str, params: dict, base=None):
    """Design of ``kind`` from a base design (or the defaults) and overrides {name: value}."""
    from softcrawl.geometry.design import DesignError, RobotDesign

    cls = _design_classes()[kind]
    if base is not None and not isinstance(base, cls):
        raise DesignError("design", f"the design file holds a {base.kind!r}, not a {kind!r}")
    if kind != "robot":
        return (base or cls()).replace(**params) if base else cls(**params)
    top = {k: v for k, v in params.items() if "." not in k}
    nested = {
        part: {k.split(".", 1)[1]: v for k, v in params.items() if k.startswith(part + ".")}
        for part in ("epsa", "foot", "ring")
    }
    base = base or RobotDesign()
    epsa = _part(base.epsa, "epsa", nested["epsa"])
    d = top.get("d", base.d)
    # Parts derived from d unless the base file set them or the user overrides them.
    derived = RobotDesign(epsa=epsa, d=d, n_rings=top.get("n_rings", base.n_rings))
    foot = base.foot if d == base.d and epsa == base.epsa else derived.foot
    ring = base.ring if d == base.d and epsa == base.epsa else derived.ring
    foot = _part(foot, "foot", nested["foot"])
    ring = _part(ring, "ring", nested["ring"])
    return base.replace(epsa=epsa, foot=foot, ring=ring, **top)


def _part(design, name: str, changes: dict):
    """``design.replace(**changes)`` with errors named ``<name>.<parameter>``."""
    from softcrawl.geometry.design import DesignError

    if not changes:
        return design
    try:
        return design.replace(**changes)
    except DesignError as exc:
        raise DesignError(f"{name}.{exc.parameter}", exc.detail) from None


@contextlib.contextmanager
def _progress_lines(logger_name: str):
    """INFO lines of a library logger printed on stdout while the block runs."""
    handler = logging.StreamHandler(sys.stdout)
    handler.setFormatter(logging.Formatter("%(message)s"))
    logger = logging.getLogger(logger_name)
    level = logger.level
    logger.addHandler(handler)
    logger.setLevel(logging.INFO)
    try:
        yield
    finally:
        logger.removeHandler(handler)
        logger.setLevel(level)


def run(args: argparse.Namespace) -> int:
    import time

    from softcrawl import jsonio
    from softcrawl.geometry.assembly import MESHERS
    from softcrawl.geometry.design import EPSADesign, load_design
    from softcrawl.studies.commands.options import make_folder, output_folder

    params = {k[2:]: v for k, v in vars(args).items() if k.startswith("p:") and v is not None}
    base = load_design(args.design, parameter="design") if args.design else None
    design = build_design(args.kind, params, base)
    out = output_folder(args.out)
    if args.cache_dir is not None and not args.no_cache:
        output_folder(args.cache_dir, "cache-dir")
    cache = False if args.no_cache else args.cache_dir
    t0 = time.perf_counter()
    revolved = getattr(args, "mesher", "tetwild") == "revolved"
    if revolved and args.edge_length is not None:
        from softcrawl.studies.commands.options import CommandLineError

        raise CommandLineError(
            "mesh-size", "the revolved foot mesh has no edge length (geometry.foot_revolved)"
        )
    with _progress_lines("geometry"):  # the mesher's log lines: what it meshes, not a cache hit
        if args.kind == "foot":
            from softcrawl.geometry.foot_meshers import mesh_foot_with

            mesh = mesh_foot_with(design, args.mesher, edge_length=args.edge_length, cache_dir=cache)
        else:
            mesh = MESHERS[args.kind](design, edge_length=args.edge_length, cache_dir=cache)
    seconds = time.perf_counter() - t0
    make_folder(out)
    mesh.write(out / "mesh.vtu")
    mesh.write(out / "mesh.msh")
    design.save(out / "design.json")
    summary = {
        "kind": args.kind,
        **mesh.summary(),
        "seconds": round(seconds, 2),
        "physical_ids": mesh.physical_ids(),
        "design": design.to_dict(),
    }
    if isinstance(design, EPSADesign):
        summary["analytic"] = {
            "volume_mm3": design.body_volume,
            "helix_length_mm": design.helix_length,
            "chamber_wall_area_mm2": design.chamber_wall_area,
        }
    if not args.no_png:
        from softcrawl.studies.plots.mesh_render import render_png

        cut = ", cut open at y = 0" if len(mesh.region_names) == 1 else ""
        title = f"{args.kind} mesh: {mesh.n_tets} tetrahedra{cut}"
        summary["png_renderer"] = render_png(mesh, out / "mesh.png", title=title)
    jsonio.write(out / "mesh.json", summary)
    print(
        f"{args.kind}: {mesh.n_nodes} nodes, {mesh.n_tets} tets, volume {mesh.volume():.1f} mm^3, "
        f"min quality {summary['min_quality']:.3f}, {seconds:.1f} s -> {out}"
    )
    return 0
