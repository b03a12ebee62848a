"""Static identification of k_p and f_p (paper Section VII-A), on any (P, load, extension) table.

Step 1, per pressure. Eq. (3) with a hanging/added load W (N) opposing extension reads
k_p y + m g + W = f_p, so at fixed P the extension is linear in the load,

    y = (f_p - m g)/k_p - W / k_p,

and a least-squares line y = a + b W gives k_p = -1/b and f_p = a k_p + m g. (The paper fits with the
load as the independent variable and the extension as the dependent one; we do the same.) Needs at
least two distinct loads per pressure; repeated measurements are simply more rows.

Step 2, per parameter. k_p(P) and f_p(P) are each fitted by two least-squares lines, the lower one
for P <= breakpoint, the upper one above (the paper's eqs. 19-24 are of this form and are not
continuous). The breakpoint is either given (60 kPa in the paper) or fitted: every data pressure
that leaves at least two pressures on each side is tried and the one with the smallest residual
sum of squares wins (the residual is constant between data pressures, so the fitted breakpoint is
reported as the largest pressure of the lower segment, matching "P <= 60 kPa"). `breakpoint=None`
with `piecewise=False` fits a single line.

Units: P in kPa, loads in N, extensions in mm; results in N/mm and N (use `.scaled(1000)` on k_p for
the paper's N/m). The table can be synthetic (`synthetic_table`), measured, or FE output.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from softcrawl.analytic.errors import ModelInputError
from softcrawl.analytic.statics import G_STANDARD, EPSAParams, Line, PiecewiseLinear


@dataclass(frozen=True)
class PerPressureFit:
    pressure_kpa: np.ndarray  # (n,)
    k_p: np.ndarray  # N/mm
    f_p: np.ndarray  # N
    rms_mm: np.ndarray  # residual of the per-pressure line


@dataclass(frozen=True)
class Identification:
    per_pressure: PerPressureFit
    k_p: PiecewiseLinear
    f_p: PiecewiseLinear


def fit_per_pressure(
    pressure_kpa: ArrayLike,
    load_n: ArrayLike,
    extension_mm: ArrayLike,
    mass_t: float = 0.0,
    g: float = G_STANDARD,
) -> PerPressureFit:
    p = np.asarray(pressure_kpa, dtype=float).ravel()
    w = np.asarray(load_n, dtype=float).ravel()
    y = np.asarray(extension_mm, dtype=float).ravel()
    if not (p.shape == w.shape == y.shape) or p.size == 0:
        raise ModelInputError("table", "pressure, load and extension columns must have equal length")
    if not (np.all(np.isfinite(p)) and np.all(np.isfinite(w)) and np.all(np.isfinite(y))):
        raise ModelInputError("table", "non-finite entries")
    levels = np.unique(p)
    ks, fs, rms = [], [], []
    for level in levels:
        sel = p == level
        ww, yy = w[sel], y[sel]
        if np.unique(ww).size < 2:
            raise ModelInputError("table", f"pressure {level:g} kPa needs at least two distinct loads")
        A = np.column_stack([np.ones_like(ww), ww])
        (a, b), *_ = np.linalg.lstsq(A, yy, rcond=None)
        if b >= 0:
            raise ModelInputError("table", f"extension does not decrease with load at {level:g} kPa")
        k = -1.0 / b
        ks.append(k)
        fs.append(a * k + mass_t * g)
        rms.append(float(np.sqrt(np.mean((A @ [a, b] - yy) ** 2))))
    return PerPressureFit(levels, np.array(ks), np.array(fs), np.array(rms))


def _line_fit(x: np.ndarray, y: np.ndarray) -> tuple[Line, float]:
    A = np.column_stack([x, np.ones_like(x)])
    (s, c), *_ = np.linalg.lstsq(A, y, rcond=None)
    sse = float(np.sum((A @ [s, c] - y) ** 2))
    return Line(float(s), float(c)), sse


def fit_piecewise(
    pressure_kpa: ArrayLike, values: ArrayLike, breakpoint: float | None = 60.0, piecewise: bool = True
) -> PiecewiseLinear:
    """Two lines split at `breakpoint` (kPa, lower line for P <= bp) or at the best data pressure."""
    x = np.asarray(pressure_kpa, dtype=float)
    v = np.asarray(values, dtype=float)
    if not piecewise:
        line, _ = _line_fit(x, v)
        return PiecewiseLinear(line)
    if breakpoint is not None:
        lo, hi = x <= breakpoint, x > breakpoint
        if np.unique(x[lo]).size < 2 or np.unique(x[hi]).size < 2:
            raise ModelInputError(
                "breakpoint", f"{breakpoint:g} kPa leaves fewer than two pressures on one side"
            )
        l1, _ = _line_fit(x[lo], v[lo])
        l2, _ = _line_fit(x[hi], v[hi])
        return PiecewiseLinear(l1, l2, float(breakpoint))
    levels = np.unique(x)
    best = None
    for bp in levels[1:-2]:
        lo, hi = x <= bp, x > bp
        if np.unique(x[lo]).size < 2 or np.unique(x[hi]).size < 2:
            continue
        l1, s1 = _line_fit(x[lo], v[lo])
        l2, s2 = _line_fit(x[hi], v[hi])
        if best is None or s1 + s2 < best[0] - 1e-12 * abs(best[0]):
            best = (s1 + s2, PiecewiseLinear(l1, l2, float(bp)))
    if best is None:
        raise ModelInputError("breakpoint", "need at least four pressure levels to fit a breakpoint")
    return best[1]


def identify(
    pressure_kpa: ArrayLike,
    load_n: ArrayLike,
    extension_mm: ArrayLike,
    mass_t: float = 0.0,
    g: float = G_STANDARD,
    breakpoint: float | None = 60.0,
    piecewise: bool = True,
) -> Identification:
    """The paper's two-step procedure; see the module docstring."""
    per = fit_per_pressure(pressure_kpa, load_n, extension_mm, mass_t, g)
    return Identification(
        per,
        fit_piecewise(per.pressure_kpa, per.k_p, breakpoint, piecewise),
        fit_piecewise(per.pressure_kpa, per.f_p, breakpoint, piecewise),
    )


def synthetic_table(
    actuator: EPSAParams,
    pressures_kpa: ArrayLike,
    loads_n: ArrayLike,
    repeats: int = 1,
    noise_mm: float = 0.0,
    seed: int = 0,
    g: float = G_STANDARD,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(P, W, y) rows from the model k_p y + m g + W = f_p, plus Gaussian noise on y."""
    rng = np.random.default_rng(seed)
    P, W = np.meshgrid(np.asarray(pressures_kpa, float), np.asarray(loads_n, float), indexing="ij")
    P = np.repeat(P.ravel(), repeats)
    W = np.repeat(W.ravel(), repeats)
    y = (actuator.f_p(P) - actuator.mass * g - W) / actuator.k_p(P)
    return P, W, y + noise_mm * rng.standard_normal(y.shape)


#: Largest identification table read (bytes): a test of 10 pressures x 3 loads is a few hundred
#: bytes; 50 MB is a million rows.
MAX_TABLE_BYTES = 50_000_000


def read_table(path: str | Path) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """CSV with header columns pressure_kpa, load_n, extension_mm (extra columns ignored)."""
    import csv

    try:
        if os.stat(path).st_size > MAX_TABLE_BYTES:
            raise ModelInputError("table", f"{path} is larger than {MAX_TABLE_BYTES} bytes")
        with open(path, newline="", encoding="utf-8") as fh:
            rows = list(csv.DictReader(fh))
    except OSError as exc:
        raise ModelInputError("table", f"cannot read {path}: {exc.strerror or exc}") from None
    except (UnicodeDecodeError, csv.Error) as exc:
        raise ModelInputError("table", f"{path} is not a CSV text file ({exc})") from None
    try:
        cols = [np.array([float(r[c]) for r in rows]) for c in ("pressure_kpa", "load_n", "extension_mm")]
    except (KeyError, ValueError, TypeError) as exc:
        raise ModelInputError(
            "table", f"{path}: need numeric columns pressure_kpa, load_n, extension_mm ({exc})"
        ) from None
    return tuple(cols)
