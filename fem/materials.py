"""Material library and tensile-data fitting for the soft pipe-crawling robot.

Units are the project's: mm, N, MPa (= N/mm^2), s, tonne. Density is in t/mm^3
(1.07 g/cm^3 = 1.07e-9 t/mm^3). Stretch is dimensionless.

Constitutive models
-------------------
``neo-hookean`` (compressible, for the FE solver)::

    W = mu/2 (I1_bar - 3) + K/2 (J - 1)^2,   I1_bar = J^(-2/3) tr(C)

``yeoh``::

    W = C10 (I1_bar - 3) + C20 (I1_bar - 3)^2 + C30 (I1_bar - 3)^3 + K/2 (J - 1)^2

with initial shear modulus mu = 2 C10. ``linear-elastic`` (ABS rings, Kevlar fiber trusses) is given
by Young's modulus E and Poisson's ratio nu; mu and K follow from

    mu = E / (2 (1 + nu)),   K = E / (3 (1 - 2 nu)).

For every model the small-strain constants are related by

    lambda = K - 2 mu / 3,   E = 9 K mu / (3 K + mu),   nu = (3 K - 2 mu) / (2 (3 K + mu)).

Nearly incompressible solids default to K = 1000 mu (DESIGN.md section 3: K/mu >= 1000), i.e.
nu = 0.4995: the volume change under the actuator's stresses stays below about 0.1 %, which is
incompressible for every purpose of this project, while the real bulk modulus of silicone
(K ~ 1 GPa, K/mu ~ 10^4-10^5) would make the stiffness matrix badly conditioned and aggravate
volumetric locking of displacement elements for no gain in accuracy.

Uniaxial tension of an incompressible solid
-------------------------------------------
With stretch lam = 1 + engineering strain and I1 = lam^2 + 2/lam, the nominal (engineering)
stress P = force / undeformed area is

    Neo-Hookean:  P = mu (lam - lam^-2)
    Yeoh:         P = 2 (lam - lam^-2) (C10 + 2 C20 (I1 - 3) + 3 C30 (I1 - 3)^2)

Both are linear in the constants, so `fit_neo_hookean` and `fit_yeoh` are linear least squares on
the nominal stress (absolute residuals, in MPa). See `select_fit_points` for the data handling and
`DEFAULT_MAX_STRAIN` for the default strain range.

Data: `load_tensile` reads the Soft Robotics Materials Database tensile tests shipped in
``fem/data`` (Marechal et al., Soft Robotics 8(3), 2021; ODbL 1.0 / DbCL 1.0, attribution in
``fem/data/README.md`` and in `DATA_ATTRIBUTION`, which must travel with every derived table).
"""
from __future__ import annotations

import dataclasses
import functools
import math
from dataclasses import replace, dataclass
from pathlib import Path
from typing import Callable

import numpy as np

MODELS = ("neo-hookean", "yeoh", "linear-elastic")
HYPERELASTIC_MODELS = ("neo-hookean", "yeoh")
FIT_MODELS = ("neo-hookean", "yeoh")

#: Default bulk-to-shear modulus ratio of the nearly incompressible solids (nu = 0.4995).
DEFAULT_K_OVER_MU = 1000.0

#: Default upper engineering strain of the fits (stretch 2). The ePSA's silicone works at
#: principal stretches up to about 1.5-2, so this is the range the FE model must get right. The
#: Neo-Hookean model cannot follow the strain stiffening of the pull-to-failure curve (to ~1600 %
#: strain): a least-squares fit over the whole curve is dominated by the large-strain points and
#: gives for Ecoflex 00-50 a mu about 4x the small-strain value (0.087 vs 0.022 MPa), which would
#: make the actuator far too stiff in its working range.
DEFAULT_MAX_STRAIN = 1.0

#: Upper plausibility bound on density in t/mm^3 (100 g/cm^3, above any solid). A value above it
#: is almost surely given in g/cm^3 or kg/m^3.
MAX_DENSITY = 1.0e-7

DATA_DIR = Path(__file__).resolve().parent / "data"

#: Shipped tensile tests: data name -> CSV file in DATA_DIR.
TENSILE_FILES = {
    "ecoflex-00-50": "ecoflex-00-50-tensile.csv",
    "ecoflex-00-30": "ecoflex-00-30-tensile.csv",
    "dragon-skin-30": "dragon-skin-30-tensile.csv",
}

DATA_ATTRIBUTION = (
    "Tensile data: Soft Robotics Materials Database, L. Marechal, L. Lindenroth et al. "
    "(Marechal et al., 'Toward a Common Framework and Database of Materials for Soft Robotics', "
    "Soft Robotics 8(3), 2021), repository LucMarechal/Soft-Robotics-Materials-Database, "
    "commit 8ff66c3, folder Tensile-Tests-Data."
)
DATA_LICENSE = (
    "Database: Open Database License (ODbL 1.0); contents: Database Contents License (DbCL 1.0). "
    "Derived constants are shared under the same terms; keep this attribution with them."
)


class MaterialError(ValueError):
    """Bad material input; `parameter` names the offending field or argument."""

    def __init__(self, parameter: str, message: str) -> None:
        super().__init__(f"{parameter}: {message}")
        self.parameter = parameter


# --------------------------------------------------------------------------------------------
# Small-strain relations
# --------------------------------------------------------------------------------------------


def shear_modulus_from_youngs(youngs: float, poisson: float) -> float:
    """mu = E / (2 (1 + nu)) [MPa]."""
    return youngs / (2.0 * (1.0 + poisson))


def bulk_modulus_from_youngs(youngs: float, poisson: float) -> float:
    """K = E / (3 (1 - 2 nu)) [MPa]."""
    return youngs / (3.0 * (1.0 - 2.0 * poisson))


def shear_modulus_nearly_incompressible(youngs: float,
                                        k_over_mu: float = DEFAULT_K_OVER_MU) -> float:
    """mu such that E = 9 K mu / (3 K + mu) with K = k_over_mu * mu: mu = E (3k + 1) / (9k)."""
    return youngs * (3.0 * k_over_mu + 1.0) / (9.0 * k_over_mu)


def shore_a_to_youngs(shore_a: float) -> float:
    """Young's modulus [MPa] from Shore A hardness by Gent's relation (Gent 1958):

        E = 0.0981 (56 + 7.62336 S) / (0.137505 (254 - 2.54 S))   [MPa]

    An empirical fit for rubbers, most trustworthy between about 40A and 90A; it diverges at
    S = 100. Shore 70A gives E = 5.52 MPa.
    """
    s = _finite(shore_a, "shore_a")
    if not 0.0 <= s < 100.0:
        raise MaterialError("shore_a", f"Shore A hardness must be in [0, 100), got {s:g}")
    return 0.0981 * (56.0 + 7.62336 * s) / (0.137505 * (254.0 - 2.54 * s))


# --------------------------------------------------------------------------------------------
# Material
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True, kw_only=True)
class Material:
    """An isotropic material, validated on construction.

    Give ``mu`` (and optionally ``bulk``, default ``DEFAULT_K_OVER_MU * mu``) for
    ``neo-hookean``; ``yeoh_c = (C10, C20, C30)`` for ``yeoh`` (``mu`` is then 2 C10);
    ``youngs`` and ``poisson`` for ``linear-elastic`` (``mu`` and ``bulk`` are derived). After
    construction ``mu`` and ``bulk`` are always set. Moduli in MPa, density in t/mm^3.
    """

    name: str
    model: str
    density: float
    mu: float | None = None
    bulk: float | None = None
    yeoh_c: tuple[float, float, float] | None = None
    youngs: float | None = None
    poisson: float | None = None
    source: str = ""

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name.strip():
            raise MaterialError("name", "must be a non-empty string")
        if self.model not in MODELS:
            raise MaterialError("model", f"unknown model {self.model!r}; valid: {', '.join(MODELS)}")
        density = _finite(self.density, "density")
        if density <= 0.0:
            raise MaterialError("density", f"must be > 0 t/mm^3, got {density:g}")
        if density > MAX_DENSITY:
            raise MaterialError("density", f"{density:g} t/mm^3 is implausible; density is in "
                                           "t/mm^3 (1.07 g/cm^3 = 1.07e-9 t/mm^3)")
        if not isinstance(self.source, str):
            raise MaterialError("source", "must be a string")
        if self.model == "linear-elastic":
            mu, bulk = self._linear_elastic_moduli()
        else:
            mu, bulk = self._hyperelastic_moduli()
        object.__setattr__(self, "density", density)
        object.__setattr__(self, "mu", mu)
        object.__setattr__(self, "bulk", bulk)

    def _linear_elastic_moduli(self) -> tuple[float, float]:
        if self.yeoh_c is not None:
            raise MaterialError("yeoh_c", "only for model 'yeoh'")
        if self.youngs is None:
            raise MaterialError("youngs", "required for model 'linear-elastic'")
        if self.poisson is None:
            raise MaterialError("poisson", "required for model 'linear-elastic'")
        youngs = _finite(self.youngs, "youngs")
        poisson = _finite(self.poisson, "poisson")
        if youngs <= 0.0:
            raise MaterialError("youngs", f"must be > 0 MPa, got {youngs:g}")
        if not -1.0 < poisson < 0.5:
            raise MaterialError("poisson", f"must be in (-1, 0.5), got {poisson:g}")
        object.__setattr__(self, "youngs", youngs)
        object.__setattr__(self, "poisson", poisson)
        mu = shear_modulus_from_youngs(youngs, poisson)
        bulk = bulk_modulus_from_youngs(youngs, poisson)
        _check_consistent(self.mu, mu, "mu")
        _check_consistent(self.bulk, bulk, "bulk")
        return mu, bulk

    def _hyperelastic_moduli(self) -> tuple[float, float]:
        for field_name in ("youngs", "poisson"):
            if getattr(self, field_name) is not None:
                raise MaterialError(field_name, f"only for model 'linear-elastic'; give mu (and "
                                                f"bulk) for model {self.model!r}")
        if self.model == "yeoh":
            coefficients = _yeoh_coefficients(self.yeoh_c)
            object.__setattr__(self, "yeoh_c", coefficients)
            mu = 2.0 * coefficients[0]
            _check_consistent(self.mu, mu, "mu")
        else:
            if self.yeoh_c is not None:
                raise MaterialError("yeoh_c", "only for model 'yeoh'")
            if self.mu is None:
                raise MaterialError("mu", f"required for model {self.model!r}")
            mu = _finite(self.mu, "mu")
            if mu <= 0.0:
                raise MaterialError("mu", f"must be > 0 MPa, got {mu:g}")
        bulk = DEFAULT_K_OVER_MU * mu if self.bulk is None else _finite(self.bulk, "bulk")
        if bulk <= 0.0:
            raise MaterialError("bulk", f"must be > 0 MPa, got {bulk:g}")
        if bulk < 2.0 * mu / 3.0:
            raise MaterialError("bulk", f"K/mu = {bulk / mu:g} < 2/3 gives a negative Poisson "
                                        f"ratio; nearly incompressible solids use K/mu >= 1000")
        return mu, bulk

    # -- derived constants (small strain) ------------------------------------------------------

    @property
    def lame_lambda(self) -> float:
        """First Lame parameter lambda = K - 2 mu / 3 [MPa]."""
        return self.bulk - 2.0 * self.mu / 3.0

    @property
    def youngs_modulus(self) -> float:
        """Small-strain Young's modulus E = 9 K mu / (3 K + mu) [MPa]."""
        return 9.0 * self.bulk * self.mu / (3.0 * self.bulk + self.mu)

    @property
    def poisson_ratio(self) -> float:
        """Small-strain Poisson ratio nu = (3 K - 2 mu) / (2 (3 K + mu))."""
        return (3.0 * self.bulk - 2.0 * self.mu) / (2.0 * (3.0 * self.bulk + self.mu))

    @property
    def k_over_mu(self) -> float:
        """Bulk-to-shear modulus ratio K / mu."""
        return self.bulk / self.mu

    @property
    def is_hyperelastic(self) -> bool:
        return self.model in HYPERELASTIC_MODELS

    def with_mu(self, mu: float) -> "Material":
        """A copy with shear modulus `mu` [MPa] and everything else scaled along.

        K/mu is kept (so the compressibility, nu, is unchanged); for Yeoh all three constants are
        scaled by mu_new / mu_old (same curve shape); for linear-elastic E is scaled and nu kept.
        The source text records the change. Used for calibration studies.
        """
        new_mu = _finite(mu, "mu")
        if new_mu <= 0.0:
            raise MaterialError("mu", f"must be > 0 MPa, got {new_mu:g}")
        scale = new_mu / self.mu
        note = f"{self.source}; mu rescaled {self.mu:.6g} -> {new_mu:.6g} MPa (K/mu kept)"
        if self.model == "linear-elastic":
            return dataclasses.replace(self, youngs=self.youngs * scale, mu=None, bulk=None,
                                       source=note)
        if self.model == "yeoh":
            return dataclasses.replace(self, yeoh_c=tuple(c * scale for c in self.yeoh_c),
                                       mu=None, bulk=self.bulk * scale, source=note)
        return dataclasses.replace(self, mu=new_mu, bulk=self.bulk * scale, source=note)

    def uniaxial_nominal_stress(self, stretch) -> np.ndarray:
        """Nominal stress [MPa] in incompressible uniaxial tension (hyperelastic models only)."""
        if self.model == "neo-hookean":
            return neo_hookean_uniaxial(stretch, self.mu)
        if self.model == "yeoh":
            return yeoh_uniaxial(stretch, self.yeoh_c)
        raise MaterialError("model", "uniaxial_nominal_stress is for hyperelastic models")

    def to_dict(self) -> dict:
        """Fields plus derived constants, JSON-ready (units: MPa, t/mm^3)."""
        record = dataclasses.asdict(self)
        if record["yeoh_c"] is not None:
            record["yeoh_c"] = list(record["yeoh_c"])
        record.update(youngs_modulus=self.youngs_modulus, poisson_ratio=self.poisson_ratio,
                      lame_lambda=self.lame_lambda, k_over_mu=self.k_over_mu)
        return record


def _finite(value, parameter: str) -> float:
    if isinstance(value, bool):
        raise MaterialError(parameter, f"must be a number, got {value!r}")
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise MaterialError(parameter, f"must be a number, got {value!r}") from None
    if not math.isfinite(number):
        raise MaterialError(parameter, f"must be finite, got {number!r}")
    return number


def _check_consistent(given, derived: float, parameter: str) -> None:
    """A redundant field may be given only if it equals the derived value."""
    if given is None:
        return
    value = _finite(given, parameter)
    if not math.isclose(value, derived, rel_tol=1e-9):
        raise MaterialError(parameter, f"{value:g} contradicts the value {derived:g} derived from "
                                       f"the other constants; leave it out")


def _yeoh_coefficients(yeoh_c) -> tuple[float, float, float]:
    """Validate (C10, C20, C30): C10 > 0 and dW/dI1 > 0 for every I1 >= 3.

    dW/dI1 = C10 + 2 C20 x + 3 C30 x^2 with x = I1 - 3 >= 0 stays positive for all x iff
    C30 >= 0 and (C20 >= 0 or C20^2 < 3 C10 C30). Otherwise the model loses stability (the
    uniaxial stress turns down) at some finite stretch, which a path-following solver would find.
    """
    if yeoh_c is None:
        raise MaterialError("yeoh_c", "required for model 'yeoh': (C10, C20, C30) in MPa")
    try:
        values = tuple(yeoh_c)
    except TypeError:
        raise MaterialError("yeoh_c", f"must be a sequence (C10, C20, C30), got {yeoh_c!r}") from None
    if len(values) != 3:
        raise MaterialError("yeoh_c", f"needs 3 constants (C10, C20, C30), got {len(values)}")
    c10, c20, c30 = (_finite(v, "yeoh_c") for v in values)
    if c10 <= 0.0:
        raise MaterialError("yeoh_c", f"initial shear modulus 2 C10 must be > 0, got C10 = {c10:g}")
    if not yeoh_is_stable((c10, c20, c30)):
        raise MaterialError("yeoh_c", f"(C10, C20, C30) = ({c10:g}, {c20:g}, {c30:g}) is unstable: "
                                      "dW/dI1 turns negative at large strain (need C30 >= 0 and "
                                      "C20 >= 0 or C20^2 < 3 C10 C30)")
    return (c10, c20, c30)


def yeoh_is_stable(yeoh_c) -> bool:
    """True if dW/dI1 = C10 + 2 C20 x + 3 C30 x^2 > 0 for all x = I1 - 3 >= 0."""
    c10, c20, c30 = yeoh_c
    return c10 > 0.0 and c30 >= 0.0 and (c20 >= 0.0 or c20 * c20 < 3.0 * c10 * c30)


# --------------------------------------------------------------------------------------------
# Uniaxial response of the incompressible models
# --------------------------------------------------------------------------------------------


def neo_hookean_uniaxial(stretch, mu: float) -> np.ndarray:
    """Nominal stress P = mu (lam - lam^-2) [MPa], incompressible uniaxial tension."""
    lam = np.asarray(stretch, dtype=float)
    return mu * (lam - lam**-2)


def yeoh_uniaxial(stretch, yeoh_c) -> np.ndarray:
    """Nominal stress P = 2 (lam - lam^-2)(C10 + 2 C20 x + 3 C30 x^2), x = lam^2 + 2/lam - 3."""
    lam = np.asarray(stretch, dtype=float)
    return _yeoh_design_matrix(lam) @ np.asarray(yeoh_c, dtype=float)


def _yeoh_design_matrix(lam: np.ndarray) -> np.ndarray:
    x = lam**2 + 2.0 / lam - 3.0
    g = 2.0 * (lam - lam**-2)
    return np.column_stack([g, 2.0 * g * x, 3.0 * g * x**2])


# --------------------------------------------------------------------------------------------
# Tensile data
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True, kw_only=True, eq=False)
class TensileData:
    """One uniaxial tensile test: engineering strain [-] and nominal stress [MPa], loading branch.

    `metadata` holds the PARAMETER;INFO header lines (specimen, machine, material...).
    """

    name: str
    path: str
    strain: np.ndarray
    nominal_stress: np.ndarray
    metadata: tuple[tuple[str, str], ...] = ()
    attribution: str = ""

    @property
    def stretch(self) -> np.ndarray:
        """lam = 1 + engineering strain."""
        return 1.0 + self.strain


def load_tensile(name: str) -> TensileData:
    """Read a tensile test: a shipped data name (see `TENSILE_FILES`) or a path to a CSV file.

    The file format is the Soft Robotics Materials Database one: semicolon-separated
    ``PARAMETER;INFO`` metadata lines, then a header row naming the columns (found by name, in
    any order, case-insensitively: ``Engineering Strain`` and ``Engineering Stress (MPa)``), then
    data rows. Blank rows and rows with a non-numeric strain or stress are skipped; a decimal
    comma is accepted. Rows after the peak stress (specimen failure) are dropped, and the strain
    must then be strictly increasing.
    """
    path, shipped = _tensile_path(name)
    text = path.read_text(encoding="utf-8-sig")
    metadata, strain, stress = _parse_tensile_csv(text, str(path))
    peak = int(np.argmax(stress))
    strain, stress = strain[: peak + 1], stress[: peak + 1]
    if np.any(np.diff(strain) <= 0.0):
        raise MaterialError("data", f"{path}: engineering strain is not strictly increasing on "
                                    "the loading branch")
    return TensileData(name=name if shipped else path.stem, path=str(path), strain=strain,
                       nominal_stress=stress, metadata=metadata,
                       attribution=DATA_ATTRIBUTION if shipped else "")


def _tensile_path(name: str) -> tuple[Path, bool]:
    if name in TENSILE_FILES:
        return DATA_DIR / TENSILE_FILES[name], True
    path = Path(name)
    if path.is_file():
        return path, False
    raise MaterialError("data", f"{name!r} is neither a shipped data set "
                                f"({', '.join(TENSILE_FILES)}) nor a file")


def _parse_tensile_csv(text: str, label: str):
    lines = text.splitlines()
    header_index = None
    for index, line in enumerate(lines):
        cells = [cell.strip().lower() for cell in line.split(";")]
        if "engineering strain" in cells:
            header_index = index
            break
    if header_index is None:
        raise MaterialError("data", f"{label}: no header row with an 'Engineering Strain' column")
    columns = [cell.strip().lower() for cell in lines[header_index].split(";")]
    strain_col = columns.index("engineering strain")
    stress_col = next((i for i, c in enumerate(columns) if c.startswith("engineering stress")), None)
    if stress_col is None:
        raise MaterialError("data", f"{label}: no 'Engineering Stress (MPa)' column")
    metadata = tuple(_metadata_pair(line) for line in lines[:header_index]
                     if line.strip(" ;") and not line.upper().startswith("PARAMETER;"))
    strain, stress = [], []
    for line in lines[header_index + 1:]:
        cells = line.split(";")
        if len(cells) <= max(strain_col, stress_col):
            continue
        e, s = _number(cells[strain_col]), _number(cells[stress_col])
        if e is None or s is None:
            continue
        strain.append(e)
        stress.append(s)
    if len(strain) < 3:
        raise MaterialError("data", f"{label}: fewer than 3 numeric data rows")
    return metadata, np.array(strain), np.array(stress)


def _metadata_pair(line: str) -> tuple[str, str]:
    key, _, rest = line.partition(";")
    return key.strip(), rest.split(";")[0].strip()


def _number(cell: str) -> float | None:
    cell = cell.strip()
    if "," in cell and "." not in cell:
        cell = cell.replace(",", ".")
    try:
        value = float(cell)
    except ValueError:
        return None
    return value if math.isfinite(value) else None


# --------------------------------------------------------------------------------------------
# Fitting
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True, kw_only=True)
class FitResult:
    """A least-squares fit of an incompressible hyperelastic model to uniaxial tension.

    `param_names`/`values` are the constants in MPa (``mu`` or ``C10, C20, C30``);
    `strain_range` is the (min, max) engineering strain of the points used, `max_strain` the
    requested upper bound; errors are on the nominal stress: `rms_error` [MPa],
    `relative_rms_error` = rms_error / RMS(measured stress), `r_squared` = 1 - SS_res / SS_tot.
    """

    model: str
    param_names: tuple[str, ...]
    values: tuple[float, ...]
    max_strain: float
    strain_range: tuple[float, float]
    n_points: int
    rms_error: float
    relative_rms_error: float
    r_squared: float
    notes: tuple[str, ...] = ()

    @property
    def params(self) -> dict[str, float]:
        return dict(zip(self.param_names, self.values))

    @property
    def initial_shear_modulus(self) -> float:
        """mu for Neo-Hookean, 2 C10 for Yeoh [MPa]."""
        return self.values[0] if self.model == "neo-hookean" else 2.0 * self.values[0]

    def predict(self, stretch) -> np.ndarray:
        """Model nominal stress [MPa] at `stretch`."""
        if self.model == "neo-hookean":
            return neo_hookean_uniaxial(stretch, self.values[0])
        return yeoh_uniaxial(stretch, self.values)

    def to_material(self, *, name: str, density: float, source: str,
                    k_over_mu: float = DEFAULT_K_OVER_MU) -> Material:
        mu = self.initial_shear_modulus
        if self.model == "neo-hookean":
            return Material(name=name, model="neo-hookean", mu=mu, bulk=k_over_mu * mu,
                            density=density, source=source)
        return Material(name=name, model="yeoh", yeoh_c=tuple(self.values), bulk=k_over_mu * mu,
                        density=density, source=source)

    def to_dict(self) -> dict:
        return {
            "model": self.model,
            "params_mpa": self.params,
            "initial_shear_modulus_mpa": self.initial_shear_modulus,
            "max_strain": self.max_strain,
            "strain_range": list(self.strain_range),
            "n_points": self.n_points,
            "rms_error_mpa": self.rms_error,
            "relative_rms_error": self.relative_rms_error,
            "r_squared": self.r_squared,
            "notes": list(self.notes),
        }


def select_fit_points(stretch, nominal_stress, max_strain: float = DEFAULT_MAX_STRAIN):
    """The (stretch, stress) points a fit uses, as two arrays.

    * Toe region: crosshead strain includes the take-up of slack and the load cell zero offset,
      so the first readings can be zero or negative (Ecoflex 00-50 starts at -0.0009 MPa). All
      points up to and including the last non-positive stress are dropped. The strain origin is
      not shifted: that would be one more fitted parameter, and the offset is a few % strain.
    * Range: only points with engineering strain lam - 1 <= max_strain are kept.
    * Noise is left to the least squares (no smoothing): the residual RMS is reported instead.
    """
    lam, stress = _validated_curve(stretch, nominal_stress)
    limit = _finite(max_strain, "max_strain")
    if limit <= 0.0:
        raise MaterialError("max_strain", f"must be > 0, got {limit:g}")
    non_positive = np.flatnonzero(stress <= 0.0)
    start = int(non_positive[-1]) + 1 if non_positive.size else 0
    keep = np.arange(lam.size) >= start
    keep &= lam - 1.0 <= limit
    return lam[keep], stress[keep]


def fit_neo_hookean(stretch, nominal_stress, max_strain: float = DEFAULT_MAX_STRAIN) -> FitResult:
    """Fit mu of P = mu (lam - lam^-2) by linear least squares: mu = sum(g P) / sum(g^2).

    `stretch` = 1 + engineering strain, `nominal_stress` in MPa; points are chosen by
    `select_fit_points` (default strain range 0-`DEFAULT_MAX_STRAIN` = 0-100 %, stretch <= 2, the
    ePSA's operating range; see that constant for why not the whole curve).
    """
    lam, stress = _points_for_fit(stretch, nominal_stress, max_strain, n_params=1)
    g = lam - lam**-2
    mu = float(g @ stress / (g @ g))
    if mu <= 0.0:
        raise MaterialError("nominal_stress", f"fitted mu = {mu:g} MPa is not positive")
    return _fit_result("neo-hookean", ("mu",), (mu,), lam, stress, mu * g, max_strain, ())


def fit_yeoh(stretch, nominal_stress, max_strain: float = DEFAULT_MAX_STRAIN,
             stable: bool = True) -> FitResult:
    """Fit (C10, C20, C30) of the incompressible uniaxial Yeoh law by linear least squares.

    P = 2 (lam - lam^-2)(C10 + 2 C20 (I1 - 3) + 3 C30 (I1 - 3)^2), I1 = lam^2 + 2/lam.

    Stability (`stable=True`, default): the unconstrained fit is kept if dW/dI1 > 0 for every
    I1 >= 3 (see `yeoh_is_stable`). Otherwise it is refitted with bounds C10 > 0, C30 >= 0 and C20
    free. A negative C20 is accepted (it captures the softening of the initial slope typical of
    silicones) as long as C20^2 < 3 C10 C30; if not, the fit is repeated with C20 >= 0 as well,
    which is always stable (a conservative choice, not the best stable fit). Each such step is
    recorded in `FitResult.notes`. With `stable=False` the unconstrained fit is returned as is,
    which may not be usable as a `Material` (on the shipped Ecoflex data C30 comes out < 0).
    """
    lam, stress = _points_for_fit(stretch, nominal_stress, max_strain, n_params=3)
    design = _yeoh_design_matrix(lam)
    coefficients = np.linalg.lstsq(design, stress, rcond=None)[0]
    notes: list[str] = []
    if stable and not yeoh_is_stable(coefficients):
        notes.append(f"unconstrained fit (C10, C20, C30) = ({', '.join(f'{c:.4g}' for c in coefficients)})"
                     " is unstable at large strain; refitted with C10 > 0, C30 >= 0")
        coefficients = _bounded_lstsq(design, stress, c20_min=-np.inf)
        if not yeoh_is_stable(coefficients):
            notes.append(f"C20 = {coefficients[1]:.4g} < 0 with C20^2 >= 3 C10 C30; refitted "
                         "with C20 >= 0")
            coefficients = _bounded_lstsq(design, stress, c20_min=0.0)
    values = tuple(float(c) for c in coefficients)
    if values[0] <= 0.0:
        raise MaterialError("nominal_stress", f"fitted C10 = {values[0]:g} MPa is not positive")
    return _fit_result("yeoh", ("C10", "C20", "C30"), values, lam, stress, design @ coefficients,
                       max_strain, tuple(notes))


def fit_tensile(data: TensileData, model: str = "neo-hookean",
                max_strain: float = DEFAULT_MAX_STRAIN) -> FitResult:
    """Fit `model` ('neo-hookean' or 'yeoh') to a loaded tensile test."""
    if model == "neo-hookean":
        return fit_neo_hookean(data.stretch, data.nominal_stress, max_strain)
    if model == "yeoh":
        return fit_yeoh(data.stretch, data.nominal_stress, max_strain)
    raise MaterialError("model", f"unknown fit model {model!r}; valid: {', '.join(FIT_MODELS)}")


def _bounded_lstsq(design: np.ndarray, stress: np.ndarray, c20_min: float) -> np.ndarray:
    from scipy.optimize import lsq_linear

    # C10 > 0 strictly: a tiny positive floor far below any elastomer's modulus.
    lower = [1e-12, c20_min, 0.0]
    upper = [np.inf, np.inf, np.inf]
    return lsq_linear(design, stress, bounds=(lower, upper), method="bvls").x


def _validated_curve(stretch, nominal_stress) -> tuple[np.ndarray, np.ndarray]:
    lam = np.asarray(stretch, dtype=float)
    stress = np.asarray(nominal_stress, dtype=float)
    if lam.ndim != 1:
        raise MaterialError("stretch", f"must be a 1-D array, got shape {lam.shape}")
    if stress.shape != lam.shape:
        raise MaterialError("nominal_stress", f"shape {stress.shape} differs from stretch "
                                              f"shape {lam.shape}")
    if not np.all(np.isfinite(lam)) or np.any(lam <= 0.0):
        raise MaterialError("stretch", "must be finite and > 0 (stretch = 1 + engineering strain)")
    if not np.all(np.isfinite(stress)):
        raise MaterialError("nominal_stress", "must be finite")
    return lam, stress


def _points_for_fit(stretch, nominal_stress, max_strain, n_params: int):
    lam, stress = select_fit_points(stretch, nominal_stress, max_strain)
    if lam.size < n_params + 2:
        raise MaterialError("max_strain", f"only {lam.size} usable points up to strain "
                                          f"{max_strain:g}; need at least {n_params + 2}")
    return lam, stress


def _fit_result(model, names, values, lam, stress, predicted, max_strain, notes) -> FitResult:
    residual = stress - predicted
    rms = float(np.sqrt(np.mean(residual**2)))
    ss_tot = float(np.sum((stress - stress.mean()) ** 2))
    return FitResult(
        model=model, param_names=names, values=values, max_strain=float(max_strain),
        strain_range=(round(float(lam.min() - 1.0), 9), round(float(lam.max() - 1.0), 9)),
        n_points=int(lam.size),
        rms_error=rms, relative_rms_error=rms / float(np.sqrt(np.mean(stress**2))),
        r_squared=1.0 - float(np.sum(residual**2)) / ss_tot if ss_tot > 0.0 else float("nan"),
        notes=notes)


# --------------------------------------------------------------------------------------------
# Presets
# --------------------------------------------------------------------------------------------

_G_PER_CM3 = 1.0e-9  # t/mm^3 per g/cm^3

#: Densities [t/mm^3]. Smooth-On technical bulletins give specific gravity 1.07 (Ecoflex 00-30,
#: 00-50) and 1.08 (Dragon Skin 30). The datasheet numbers quoted in the preset sources are from
#: the bulletins as the author knows them, not re-checked against the current editions.
_SILICONE_DENSITY = {"ecoflex-00-50": 1.07 * _G_PER_CM3, "ecoflex-00-30": 1.07 * _G_PER_CM3,
                     "dragon-skin-30": 1.08 * _G_PER_CM3}


def _ecoflex_00_50() -> Material:
    return Material(
        name="ecoflex-00-50", model="neo-hookean", mu=0.030,
        density=_SILICONE_DENSITY["ecoflex-00-50"],
        source="DESIGN.md sec. 3 default mu = 0.030 MPa (literature 0.022-0.047 MPa; Smooth-On "
               "TDS (not re-checked) 100 % modulus 12 psi = 0.083 MPa -> NH secant mu = 0.047 MPa); SG 1.07 "
               "(Smooth-On TDS)")


def _ecoflex_00_30() -> Material:
    return Material(
        name="ecoflex-00-30", model="neo-hookean", mu=0.018,
        density=_SILICONE_DENSITY["ecoflex-00-30"],
        source="literature mu ~ 0.0125-0.023 MPa, mid value 0.018 MPa (SRMD tensile fit 0-100 % "
               "gives 0.016 MPa; Smooth-On TDS (not re-checked) 100 % modulus 10 psi = 0.069 MPa -> NH secant "
               "0.039 MPa, an upper bound); SG 1.07 (Smooth-On TDS)")


def _dragon_skin_30() -> Material:
    return Material(
        name="dragon-skin-30", model="neo-hookean", mu=0.20,
        density=_SILICONE_DENSITY["dragon-skin-30"],
        source="literature mu ~ 0.1-0.2 MPa, upper value 0.20 MPa since the SRMD tensile fit "
               "0-100 % gives 0.22 MPa (0-50 %: 0.19 MPa; Smooth-On TDS (not re-checked) 100 % modulus 86 psi = "
               "0.59 MPa -> NH secant 0.34 MPa); SG 1.08 (Smooth-On TDS)")


def _rubber_70a() -> Material:
    youngs = shore_a_to_youngs(70.0)
    return Material(
        name="rubber-70a", model="neo-hookean", mu=shear_modulus_nearly_incompressible(youngs),
        density=1.15 * _G_PER_CM3,
        source=f"3D-printed rubber foot, Shore 70A: E = {youngs:.3f} MPa by Gent's relation "
               "(DESIGN.md sec. 3), mu from E with K = 1000 mu; density 1.15 g/cm^3 assumed "
               "(typical of rubber-like PolyJet photopolymers, not measured)")


def _abs() -> Material:
    return Material(
        name="abs", model="linear-elastic", youngs=2000.0, poisson=0.35, density=1.04 * _G_PER_CM3,
        source="DESIGN.md sec. 3 (rings, seal heads): E = 2000 MPa, nu = 0.35; density "
               "1.04 g/cm^3 (typical ABS)")


def _kevlar() -> Material:
    return Material(
        name="kevlar", model="linear-elastic", youngs=31067.0, poisson=0.36,
        density=1.44 * _G_PER_CM3,
        source="DESIGN.md sec. 3 fiber thread E = 31067 MPa (for a truss; diameter 0.3 mm is a "
               "geometry parameter); nu = 0.36 nominal (Kevlar 49), unused by truss elements; "
               "density 1.44 g/cm^3 (Kevlar 49)")


@functools.lru_cache(maxsize=None)
def _fitted(data_name: str) -> Material:
    """Neo-Hookean fit at the default strain range, computed at first use and cached."""
    data = load_tensile(data_name)
    fit = fit_tensile(data, "neo-hookean", DEFAULT_MAX_STRAIN)
    source = (f"Neo-Hookean least-squares fit to SRMD uniaxial tensile data ({TENSILE_FILES[data_name]}), "
              f"engineering strain {fit.strain_range[0]:.3f}-{fit.strain_range[1]:.3f}, "
              f"{fit.n_points} points, RMS error {fit.rms_error:.2g} MPa "
              f"({100 * fit.relative_rms_error:.1f} %); crosshead strain tends to under-estimate "
              f"stiffness. {DATA_ATTRIBUTION} {DATA_LICENSE}")
    return fit.to_material(name=f"{data_name}-fit", density=_SILICONE_DENSITY[data_name],
                           source=source)


PRESETS: dict[str, Callable[[], Material]] = {
    "ecoflex-00-50": _ecoflex_00_50,
    "ecoflex-00-50-fit": functools.partial(_fitted, "ecoflex-00-50"),
    "ecoflex-00-30": _ecoflex_00_30,
    "ecoflex-00-30-fit": functools.partial(_fitted, "ecoflex-00-30"),
    "dragon-skin-30": _dragon_skin_30,
    "dragon-skin-30-fit": functools.partial(_fitted, "dragon-skin-30"),
    "rubber-70a": _rubber_70a,
    "abs": _abs,
    "kevlar": _kevlar,
}


def material_names() -> tuple[str, ...]:
    """Names of the presets, in registry order."""
    return tuple(PRESETS)


def get_material(name: str) -> Material:
    """The preset called `name` (fit presets are computed at first use, then cached).

    `NAME@mu=VALUE` is the preset with its shear modulus replaced by VALUE MPa (K/mu kept, see
    `Material.with_mu`): how a calibrated modulus (`softcrawl calibrate`) is used in studies.
    """
    base, _, override = str(name).partition("@")
    try:
        factory = PRESETS[base]
    except (KeyError, TypeError):
        raise MaterialError("material", f"unknown material {name!r}; valid: "
                                        f"{', '.join(PRESETS)} (optionally NAME@mu=VALUE)") from None
    if not override:
        return factory()
    key, _, value = override.partition("=")
    try:
        mu = float(value)
    except ValueError:
        mu = float("nan")
    if key.strip() != "mu" or not math.isfinite(mu) or mu <= 0:
        raise MaterialError("material", f"{name!r}: write NAME@mu=VALUE with a positive VALUE in MPa")
    return replace(factory().with_mu(mu), name=f"{base}@mu={value}")
