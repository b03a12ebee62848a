r"""The feet's inputs, identified from the data named for them (issue 29 step 5,
docs/decisions/070-identify-feet.md).

Modulus: not fitted. The printed Shore 70A rubber's Young's modulus comes from Gent's published
Shore-A relation (`softcrawl.materials.shore_a_to_youngs`, the preset ``rubber-70a``).

Friction coefficients: each fitted to ONE measurement, under the reading that record 062 keeps:
eq. 26's friction in the 70 mm pipe is the force the bundle transmits to the one foot that slides,
and its printed value counts that force once per actuator, so one foot's sliding resistance is
eq. 26 / 3 (`EQ26_COUNT`). At face value (15.3 N) no foot crawls under the prototype's statics
(record 062, section b); divided by three the forward and backward values agree with the 70 mm
crawl speeds within 2.4 % and 4.2 %. Table 2 itself is not read, at any diameter:

    mu_smooth:   F_fwd(mu_smooth)   = 15.3 / 3 = 5.10 N   forward crawl: the skirt leans back and
                                                          its smooth front face slides forward;
    mu_grooved:  F_slide(mu_grooved) = 16.9 / 3 = 5.63 N  backward crawl: the flipped skirt's
                                                          grooved face slides (issue 29 step 4).

F is the largest wall resistance of a drag from the inserted state (`studies.foot.model`), the
foot study's F_fwd. On slipping points the tangential traction is mu p_N, so F rises with mu; the
root is found by regula falsi inside the sourced range (`MU_RANGE`): both ends are solved first,
then the secant through the bracket, until |F - target| <= `TOL_N`. A target outside [F(lo),
F(hi)] is reported as out of range with its residual at the nearer end, never clipped silently.

Everything else the paper measured (Table 2's speeds, Fig. 21's statements) is a held-out check:
this module reads only `softcrawl.paper.FRICTION_N` (tests/studies/foot/test_identify_feet.py
fails if the identification touches Table 2 or Fig. 21).

The predictions read the committed identification (`prediction_friction`): `softcrawl crawl` and
`softcrawl.simulate_crawl` take their default mu_smooth and mu_grooved from it (issue 29 step 9),
at `COMMITTED` in the source tree (the README's editable install), or at the file that the
environment variable `ENV` names.
The studies read the one under their --out folder (`study_friction`). Either way a missing file
is one error, `IdentificationMissing`: exit 2 with one line naming the parameter.
"""

from __future__ import annotations

import json
import math
import os
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from pathlib import Path

from softcrawl.errors import InputError
from softcrawl.materials import get_material, shore_a_to_youngs
from softcrawl.paper import FRICTION_N

#: The pipe of the friction measurement (paper Section VII-D, eq. 26), mm.
DIAMETER_MM = 70.0
#: Sourced range of the friction coefficient of printed rubber on a smooth plastic pipe: the
#: engineering tables' ~0.3-0.9 for dry rubber on smooth plastic or steel, the range the groove
#: study already states (studies/foot/contact_studies.py).
MU_RANGE = (0.3, 0.9)
MU_SOURCE = "dry rubber on smooth plastic or steel, engineering tables (~0.3-0.9)"
#: Stop when the resistance is within this of the measurement, N (the paper gives 15.3 and 16.9:
#: one decimal).
TOL_N = 0.1
MAX_SOLVES = 6
#: How many times eq. 26's printed friction counts one foot's resistance: once per actuator
#: (docs/decisions/062-crawl-reconciliation.md, "Decision").
EQ26_COUNT = 3
TARGET_N = {
    "smooth": FRICTION_N["forward"] / EQ26_COUNT,  # the forward crawl: the smooth front face slides
    "grooved": FRICTION_N["backward"] / EQ26_COUNT,  # the backward crawl: the flipped grooved face
}
SHORE_A = 70.0
MATERIAL = "rubber-70a"
#: The committed identification (`softcrawl study identify-feet --out results/`), relative to the
#: source tree: the prediction commands read it. `ENV` names another file.
COMMITTED = Path(__file__).resolve().parents[2] / "results" / "identify" / "feet" / "feet.json"
ENV = "SOFTCRAWL_FEET"
#: Where `softcrawl study identify-feet --out DIR` writes the identification, under DIR: the studies
#: that read it (feet, optimise-feet, predict-crawl) look for it there (`study_friction`).
STUDY_FILE = Path("identify") / "feet" / "feet.json"


class IdentificationMissing(InputError):
    """No identification file where a prediction looks for one."""


@dataclass(frozen=True)
class MuFit:
    """One friction coefficient fitted to one measured resistance."""

    face: str
    target_n: float
    mu: float | None  # None: the target lies outside the range's resistances
    resistance_n: float  # at mu (or at the nearer end of the range)
    residual_n: float  # resistance - target
    in_range: bool
    solves: tuple[tuple[float, float], ...]  # (mu, F) of every solve, in order
    note: str = ""


@dataclass(frozen=True)
class FeetIdentification:
    material: str
    shore_a: float
    youngs_mpa: float
    youngs_source: str
    diameter_mm: float
    mu_range: tuple[float, float]
    mu_source: str
    fits: tuple[MuFit, ...]
    settings: dict = field(default_factory=dict)

    def mu(self, face: str) -> float | None:
        return next((f.mu for f in self.fits if f.face == face), None)

    def prediction_mu(self, face: str) -> tuple[float, str]:
        """The mu a prediction uses for `face`, and what it is: the identified value, or, where
        the measurement lies outside the sourced range, the range's end nearer to it (the input
        is never moved beyond its source to get closer to a measurement)."""
        fit = next((f for f in self.fits if f.face == face), None)
        if fit is None:
            raise ValueError(f"mu_{face} was not identified (run softcrawl study identify-feet)")
        if fit.mu is not None:
            return fit.mu, "identified"
        lo, hi = self.mu_range
        end = lo if fit.residual_n > 0 else hi  # above the target at every mu in range: the lower end
        return end, f"outside the sourced range: its nearer end ({fit.note})"

    def to_dict(self) -> dict:
        return asdict(self)


def fit_mu(
    resistance: Callable[[float], float],
    target: float,
    face: str,
    mu_range: tuple[float, float] = MU_RANGE,
    tol: float = TOL_N,
    max_solves: int = MAX_SOLVES,
) -> MuFit:
    """The mu in `mu_range` whose resistance(mu) is `target` (module docstring)."""
    lo, hi = mu_range
    solves: list[tuple[float, float]] = []

    def f(mu: float) -> float:
        value = float(resistance(mu))
        solves.append((mu, value))
        return value

    f_lo = f(lo)
    if math.isfinite(f_lo) and f_lo > target + tol:  # F rises with mu: every mu in range is too large
        note = f"{target:g} N is below F({lo:g}) = {f_lo:.2f} N, the least resistance in the range"
        if target > 0.0:  # F(0) = 0: a cylindrical wall's normal force has no axial part
            note += f"; F proportional to mu below {lo:g} would need mu = {lo * target / f_lo:.3f}"
        return MuFit(
            face, target, None, f_lo, f_lo - target, False, tuple(solves), note + f" (nearer end mu = {lo:g})"
        )
    f_hi = f(hi) if math.isfinite(f_lo) else math.nan
    if not (math.isfinite(f_lo) and math.isfinite(f_hi)):
        return MuFit(face, target, None, math.nan, math.nan, False, tuple(solves), "a drag did not converge")
    if not min(f_lo, f_hi) <= target <= max(f_lo, f_hi):
        mu_end, f_end = (lo, f_lo) if abs(f_lo - target) <= abs(f_hi - target) else (hi, f_hi)
        note = f"{target:g} N is outside F({lo:g}) = {f_lo:.2f} N .. F({hi:g}) = {f_hi:.2f} N"
        note += f" (nearer end mu = {mu_end:g})"
        return MuFit(face, target, None, f_end, f_end - target, False, tuple(solves), note)
    a, fa, b, fb = lo, f_lo - target, hi, f_hi - target
    best = min(((lo, f_lo), (hi, f_hi)), key=lambda s: abs(s[1] - target))
    while abs(best[1] - target) > tol and len(solves) < max_solves:
        mu = a - fa * (b - a) / (fb - fa) if fb != fa else 0.5 * (a + b)
        value = f(mu)
        if not math.isfinite(value):
            break
        best = min((best, (mu, value)), key=lambda s: abs(s[1] - target))
        if (value - target) * fa < 0:
            b, fb = mu, value - target
        else:
            a, fa = mu, value - target
    mu, value = best
    note = "" if abs(value - target) <= tol else f"stopped after {len(solves)} solves"
    return MuFit(face, target, mu, value, value - target, True, tuple(solves), note)


def identify(
    forward: Callable[[float], float],
    backward: Callable[[float], float] | None,
    settings: dict | None = None,
) -> FeetIdentification:
    """Fit mu_smooth to the forward measurement with `forward(mu)` and mu_grooved to the backward
    one with `backward(mu)` (the flipped foot's sliding resistance; None: not identified)."""
    fits = [fit_mu(forward, TARGET_N["smooth"], "smooth")]
    if backward is not None:
        fits.append(fit_mu(backward, TARGET_N["grooved"], "grooved"))
    youngs = get_material(MATERIAL).youngs_modulus
    gent = shore_a_to_youngs(SHORE_A)
    if not math.isclose(youngs, gent, rel_tol=1e-9):  # the preset is the relation, not a fit
        raise ValueError(f"{MATERIAL}: E = {youngs} MPa is not Gent's {gent} MPa")
    return FeetIdentification(
        material=MATERIAL,
        shore_a=SHORE_A,
        youngs_mpa=youngs,
        youngs_source="Gent (1958): E = 0.0981 (56 + 7.62336 S) / (0.137505 (254 - 2.54 S)) MPa",
        diameter_mm=DIAMETER_MM,
        mu_range=MU_RANGE,
        mu_source=MU_SOURCE,
        fits=tuple(fits),
        settings=dict(settings or {}),
    )


def load(path) -> FeetIdentification:
    """The identification a prediction reads (`softcrawl study identify-feet` wrote it)."""
    data = json.loads(Path(path).read_text())
    fits = tuple(MuFit(**(f | {"solves": tuple(map(tuple, f["solves"]))})) for f in data.pop("fits"))
    return FeetIdentification(**(data | {"fits": fits, "mu_range": tuple(data["mu_range"])}))


def committed_path() -> Path:
    """The identification file the predictions read: $SOFTCRAWL_FEET, else `COMMITTED`."""
    return Path(os.environ[ENV]) if os.environ.get(ENV) else COMMITTED


def prediction_friction(path=None) -> dict:
    """The friction coefficients a prediction uses by default, from the identification at `path`
    (None: `committed_path()`): {"mu_smooth", "mu_grooved", "mu_smooth_flag", "mu_grooved_flag",
    "source"}: each flag is `prediction_mu`'s verdict for its face (identified, or the sourced
    range's nearer end), the source names both."""
    path = Path(path) if path is not None else committed_path()
    if not path.is_file():
        raise IdentificationMissing(
            "mu_smooth",
            f"no feet identification at {path}: run `softcrawl study identify-feet --out results/`, "
            f"set {ENV}, or give both friction coefficients",
        )
    ident = load(path)
    out, notes = {}, []
    for face in ("smooth", "grooved"):
        mu, how = ident.prediction_mu(face)
        out[f"mu_{face}"] = mu
        out[f"mu_{face}_flag"] = how
        notes.append(f"mu_{face} = {mu:g}: {how.split(' (')[0]}")
    record = "docs/decisions/070-identify-feet.md"
    out["source"] = f"the committed feet identification ({record}): {'; '.join(notes)}"
    return out


def study_friction(out) -> dict:
    """`prediction_friction` of the identification under a study's --out folder (`STUDY_FILE`);
    missing, `IdentificationMissing` naming "out", with the command that writes it."""
    path = Path(out) / STUDY_FILE
    try:
        return prediction_friction(path)
    except IdentificationMissing:
        raise IdentificationMissing(
            "out", f"no feet identification at {path}: run softcrawl study identify-feet --out {out} first"
        ) from None
