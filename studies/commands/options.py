"""Options shared by the commands, checked once, before any work: numbers with their ranges,
pressure lists in kPa, output folders and files, materials.

Every check ends in one line that names the option: `add_number` turns a bad number into an
argparse error (``argument --length: must be ...``, exit code 2), the other helpers raise
`CommandLineError`, an `InputError` that `studies.cli` prints as one line with exit code 2. The
limits are named constants here or in the library module that owns the quantity
(docs/decisions/024-input-limits.md).
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
from pathlib import Path

from softcrawl.checks import brief, number
from softcrawl.errors import InputError

# Project modules are imported inside the functions that use them: softcrawl --help stays fast.

#: Highest pressure of a ramp (kPa): 1 MPa, ten times the paper's 100 kPa; silicone ePSAs burst
#: far below it (the unreinforced Table 1 chamber has a limit point near 25 kPa).
MAX_PRESSURE_KPA = 1000.0
#: Most pressure targets of one ramp. Each is a converged solve (1-5 s on the quick and default
#: meshes) and a VTU file; the paper's curves have 5-10 points, and 200 (0.5 kPa steps to
#: 100 kPa) already take ~15 min on the default mesh. 0:100:1e-4 asked for a million.
MAX_PRESSURE_TARGETS = 200
#: Most element sizes of one mesh-convergence study (each a full ramp on a finer mesh).
MAX_CONVERGENCE_SIZES = 8


class CommandLineError(InputError):
    """A bad command-line option that is not a field of a design, a material or a model."""


def _fmt(value) -> str:
    """An int in full (2**32 - 1 = 4294967295), a float in %g."""
    return str(value) if isinstance(value, int) else format(value, "g")


def number_type(
    *,
    minimum: float | None = None,
    maximum: float | None = None,
    min_open: bool = False,
    max_open: bool = False,
    integer: bool = False,
    unit: str = "",
):
    """An argparse ``type=``: the text as a finite int/float within the bounds, or an argparse error
    (one line naming the option, exit code 2)."""

    def parse(text: str):
        try:
            value = int(text) if integer else float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(
                f"must be {'an integer' if integer else 'a number'}, got {brief(text)}"
            ) from None
        try:
            return number(
                value,
                "",
                minimum=minimum,
                maximum=maximum,
                min_open=min_open,
                max_open=max_open,
                integer=integer,
                unit=unit,
            )
        except InputError as exc:
            expected = exc.detail.rsplit(", got ", 1)[0]
            raise argparse.ArgumentTypeError(f"{expected}, got {brief(text)}") from None

    parse.__name__ = "integer" if integer else "number"
    return parse


def range_text(minimum, maximum, min_open: bool = False, max_open: bool = False) -> str:
    lo = "" if minimum is None else f"{'(' if min_open else '['}{_fmt(minimum)}"
    hi = "" if maximum is None else f"{_fmt(maximum)}{')' if max_open else ']'}"
    if lo and hi:
        return f"{lo}, {hi}"
    return f">{'' if min_open else '='} {_fmt(minimum)}" if lo else f"<= {_fmt(maximum)}"


def add_number(
    parser,
    *flags: str,
    help: str,
    unit: str = "",
    default=None,
    default_text: str | None = None,
    minimum: float | None = None,
    maximum: float | None = None,
    min_open: bool = False,
    max_open: bool = False,
    integer: bool = False,
    **kwargs,
):
    """``parser.add_argument`` for a number: its type checks the range, and its help ends with the
    unit, the default and the accepted range, e.g. "pipe inner diameter (mm; default 70; range
    (0, 10000])"."""
    parts = [unit] if unit else []
    if default_text is not None or default is not None:
        parts.append(f"default {default_text if default_text is not None else format(default, 'g')}")
    if minimum is not None or maximum is not None:
        parts.append(f"range {range_text(minimum, maximum, min_open, max_open)}")
    text = f"{help} ({'; '.join(parts)})" if parts else help
    kwargs.setdefault("metavar", "N" if integer else "X")
    return parser.add_argument(
        *flags,
        type=number_type(
            minimum=minimum, maximum=maximum, min_open=min_open, max_open=max_open, integer=integer, unit=unit
        ),
        default=default,
        help=text,
        **kwargs,
    )


def parse_pressures(spec: str, parameter: str = "pressures") -> tuple[float, ...]:
    """'0:100:20' -> (20, 40, 60, 80, 100) (kPa; the 0 kPa reference row is always written, so a
    0 in the list is dropped); '10,30,50' -> (10, 30, 50). Pressures must be finite, >= 0,
    increasing, at most `MAX_PRESSURE_KPA`, with at most `MAX_PRESSURE_TARGETS` of them."""
    if not isinstance(spec, str) or not spec.strip():
        raise CommandLineError(parameter, "give START:STOP:STEP or a comma list (kPa)")
    try:
        if ":" in spec:
            a, b, s = (float(v) for v in spec.split(":"))
        else:
            values = [float(v) for v in spec.split(",")]
    except ValueError:
        raise CommandLineError(
            parameter, f"{brief(spec)} is not START:STOP:STEP or a comma list of numbers (kPa)"
        ) from None
    if ":" in spec:
        values = _range(a, b, s, parameter, spec)  # its own range errors, naming START, STOP, STEP
    _within_limit(values, parameter, spec)
    if len(values) > MAX_PRESSURE_TARGETS + 1:
        raise CommandLineError(
            parameter, f"{brief(spec)} gives {len(values)} pressures; at most {MAX_PRESSURE_TARGETS}"
        )
    for v in values:
        number(v, parameter, minimum=0.0, maximum=MAX_PRESSURE_KPA, unit="kPa", error=CommandLineError)
    if any(b <= a for a, b in zip(values, values[1:])):
        raise CommandLineError(parameter, f"{brief(spec)}: pressures must increase")
    positive = tuple(v for v in values if v > 0)
    if not positive:
        raise CommandLineError(parameter, f"{brief(spec)}: give at least one pressure above 0 kPa")
    if len(positive) > MAX_PRESSURE_TARGETS:
        raise CommandLineError(
            parameter, f"{brief(spec)} gives {len(positive)} pressures; at most {MAX_PRESSURE_TARGETS}"
        )
    return positive


def _within_limit(values, parameter: str, spec: str) -> None:
    """A pressure above `MAX_PRESSURE_KPA` is named with the limit (not "is not START:STOP:STEP")."""
    high = [v for v in values if v == v and v > MAX_PRESSURE_KPA]
    if high:
        raise CommandLineError(
            parameter,
            f"{brief(spec)}: {high[0]:g} kPa is above the {MAX_PRESSURE_KPA:g} kPa limit "
            f"(pressures in [0, {MAX_PRESSURE_KPA:g}] kPa)",
        )


def _range(start: float, stop: float, step: float, parameter: str, spec: str) -> list[float]:
    _within_limit((start, stop), f"{parameter} {'STOP' if stop > MAX_PRESSURE_KPA else 'START'}", spec)
    for name, v in (("START", start), ("STOP", stop), ("STEP", step)):
        number(v, f"{parameter} {name}", minimum=0.0, maximum=MAX_PRESSURE_KPA, error=CommandLineError)
    if step <= 0 or stop <= start:
        raise CommandLineError(parameter, f"{brief(spec)}: need START < STOP and STEP > 0 (kPa)")
    count = int((stop - start) / step + 1e-9) + 1
    if count > MAX_PRESSURE_TARGETS + 1:
        raise CommandLineError(
            parameter, f"{brief(spec)} gives {count} pressures; at most {MAX_PRESSURE_TARGETS}"
        )
    return [start + k * step for k in range(count)]


def parse_sizes(spec: str, parameter: str = "convergence") -> list[float]:
    """'10,5,2.5' -> [10, 5, 2.5]: element sizes in mm, coarse to fine (strictly decreasing), at
    most `MAX_CONVERGENCE_SIZES` of them (each is checked against the mesh limits by the model)."""
    try:
        sizes = [float(v) for v in spec.split(",")]
    except ValueError:
        raise CommandLineError(parameter, f"{brief(spec)}: give element sizes in mm, e.g. 10,5,2.5") from None
    if len(sizes) > MAX_CONVERGENCE_SIZES:
        raise CommandLineError(parameter, f"{len(sizes)} sizes; at most {MAX_CONVERGENCE_SIZES}")
    for h in sizes:
        number(h, parameter, minimum=0.0, min_open=True, unit="mm", error=CommandLineError)
    if any(b >= a for a, b in zip(sizes, sizes[1:])):
        raise CommandLineError(parameter, f"{brief(spec)}: sizes must go from coarse to fine (decreasing)")
    return sizes


def output_folder(path, parameter: str = "out") -> Path:
    """Check, before any work, that the folder `path` can be written, without creating it: it is
    a folder, or its nearest existing ancestor is, and a file can be created there (one is made
    and removed at once). The command creates the folder (`make_folder`) when it writes. An
    existing file, a path through a file and a read-only folder are a `CommandLineError` naming
    `parameter`; so is an empty name (it would write into the current folder). A folder that
    cannot be created is named, beside the existing ancestor that refuses it."""
    if not isinstance(path, (str, os.PathLike)) or not str(path).strip():
        raise CommandLineError(parameter, "is empty; give a folder name (. for the current folder)")
    folder = Path(path)
    if folder.exists() and not folder.is_dir():
        raise CommandLineError(parameter, f"{folder} exists and is not a folder")
    probe = folder
    while not probe.exists():
        if probe.parent == probe:
            break
        probe = probe.parent
    if not probe.is_dir():
        raise CommandLineError(parameter, f"cannot create {folder}: {probe} is not a folder")
    try:
        with tempfile.TemporaryFile(dir=probe):
            pass
    except OSError as exc:
        why = f"cannot write to {probe}: {exc.strerror or exc}"
        raise CommandLineError(
            parameter, why if probe == folder else f"cannot create {folder}: {why}"
        ) from None
    return folder


def make_folder(path, parameter: str = "out") -> Path:
    """Create the (checked) output folder just before the first file is written."""
    folder = Path(path)
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise CommandLineError(parameter, f"cannot create {folder}: {exc.strerror or exc}") from None
    return folder


def output_file(path, parameter: str) -> Path:
    """A file `path` that can be written: not a folder, in a folder that can be written or
    created (checked as `output_folder`; create it with `make_folder(path.parent)`)."""
    if not isinstance(path, (str, os.PathLike)) or not str(path).strip():
        raise CommandLineError(parameter, "is empty; give a file name")
    target = Path(path)
    if target.is_dir():
        raise CommandLineError(parameter, f"{target} is a folder, not a file")
    if target.exists() and not os.access(target, os.W_OK):
        raise CommandLineError(parameter, f"{target} is not writable")
    output_folder(target.parent if str(target.parent) else ".", parameter)
    return target


def body_material(name: str, parameter: str = "material"):
    """The `materials` preset of an ePSA body (a hyperelastic material; `NAME@mu=VALUE` allowed),
    checked before any work."""
    from softcrawl.materials import MaterialError, get_material
    from softcrawl.materials.fem_law import solid_law

    try:
        material = get_material(name)
        solid_law(material, hyperelastic_only=True)
    except MaterialError as exc:
        raise exc.renamed(parameter) if exc.parameter != parameter else exc from None
    return material


def emit(args, payload, text: str | None) -> None:
    """`payload` as JSON with --json (on stdout, or into the FILE that --json names), else
    `text` (None: nothing)."""
    target = getattr(args, "json", None)
    if target:
        write_json(target, payload)
    elif text is not None:
        print(text)


#: The value of a bare --json: standard output.
STDOUT = "-"


def write_json(target: str, payload) -> None:
    """Strict JSON (null, not NaN) on stdout (`STDOUT`) or into the file `target` (its folder
    created)."""
    from softcrawl.jsonio import dumps, write

    if target == STDOUT:
        sys.stdout.write(dumps(payload, indent=2))
        sys.stdout.write("\n")
        return
    make_folder(Path(target).parent if str(Path(target).parent) else ".", "json")
    write(target, payload)


def add_length(parser, flag: str, help: str, default=None, **kwargs) -> None:
    """A length option in (0, MAX_LENGTH_MM] mm (the analytic models' limit)."""
    from softcrawl.analytic.limits import MAX_LENGTH_MM

    add_number(
        parser,
        flag,
        help=help,
        unit="mm",
        default=default,
        minimum=0.0,
        min_open=True,
        maximum=MAX_LENGTH_MM,
        **kwargs,
    )


def add_json(parser, help: str = "the result as JSON") -> None:
    """--json [FILE], the same in every command: JSON on stdout, or into FILE (checked before any
    work by `check_json`). Give FILE after --json as the last word, or as --json=FILE."""
    parser.add_argument(
        "--json",
        nargs="?",
        const=STDOUT,
        default=None,
        metavar="FILE",
        help=f"{help}: on stdout, or into FILE",
    )


def check_json(args) -> None:
    """A --json FILE that can be written (checked before any work)."""
    target = getattr(args, "json", None)
    if target and target != STDOUT:
        output_file(target, "json")


class _DeprecatedAlias(argparse.Action):
    """An old spelling of an option: does what the canonical one does, with one line on stderr."""

    def __init__(self, option_strings, dest, canonical: str = "", **kwargs):
        self.canonical = canonical
        super().__init__(option_strings, dest, **kwargs)

    def __call__(self, parser, namespace, values, option_string=None):
        from softcrawl.console import warn

        warn(f"softcrawl: warning: {option_string} is deprecated; use {self.canonical}")
        setattr(namespace, self.dest, self.const if self.nargs == 0 else values)


def add_alias(parser, action: argparse.Action, *old: str) -> None:
    """Accept the old spellings `old` of the option `action` (hidden from --help), each with a
    one-line deprecation warning on stderr."""
    kwargs = {"dest": action.dest, "default": argparse.SUPPRESS, "help": argparse.SUPPRESS}
    if action.nargs == 0:
        kwargs |= {"nargs": 0, "const": action.const}
    else:
        kwargs |= {"type": action.type, "nargs": action.nargs, "metavar": action.metavar}
        if action.choices is not None:
            kwargs["choices"] = action.choices
    parser.add_argument(*old, action=_DeprecatedAlias, canonical=action.option_strings[0], **kwargs)


def add_vtu_precision(parser) -> None:
    """--vtu-precision 32|64: the bits of the VTU files' floating-point arrays (decision 063)."""
    parser.add_argument(
        "--vtu-precision",
        type=int,
        choices=(32, 64),
        default=32,
        metavar="{32,64}",
        help="bits of the floats in the VTU files (default 32: half the size, 7 digits; 64: full)",
    )


def checkpoint(store, resume: bool, command: str = "crawl"):
    """The state of a crawl's checkpoint `store` (`studies.crawl.resume.CrawlStore`,
    `studies.crawl_fe.resume.BodyStore`) to continue from (`--resume`), or None for a fresh start;
    one line either way when there is something to say, and a `CommandLineError` (exit 2) for a
    checkpoint that is not this run's or an unfinished run without --resume."""
    if not resume:
        if store.unfinished():
            raise CommandLineError(
                "resume",
                f"{store.folder} holds the checkpoint of an unfinished run; add --resume to continue it, "
                "or remove the folder to start again",
            )
        store.clear()  # a manifest without states: nothing to keep
        return None
    resumed = store.load()
    if resumed is None:
        print(f"{command}: no checkpoint in {store.folder}; starting from the beginning")
    else:
        print(f"{command}: resuming from {resumed.describe()} in {store.folder}")
    return resumed
