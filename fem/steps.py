"""The states of a path and what is shared by pressure and volume control.

A load is the vector L = (P..., f): one pressure per chamber as the targets give it (or one for
all) and the load factor. `LoadShape` converts between the user's pressures and L; `History`
keeps the last two converged states for the secant predictor; `Step` and `PathResult` are what a
path returns; `failed` is the result of a path that cannot advance, naming the last converged load.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from softcrawl.fem.errors import SolverInputError
from softcrawl.fem.model import SolidModel
from softcrawl.fem.newton import NewtonRecord, SolveStats
from softcrawl.units import mpa_to_kpa


@dataclass(frozen=True)
class Step:
    """One converged equilibrium state on the path."""

    pressure: float | tuple[float, ...]  # MPa: a float, or one per chamber as the targets gave it
    factor: float  # load factor (Dirichlet values, dead loads)
    volume: float  # cavity volume of the first (or the volume-controlled) chamber, mm^3
    x: np.ndarray = field(repr=False)  # state vector (u, and p for the mixed formulation)
    control: str  # "pressure", "volume" or "displacement"
    newton: NewtonRecord = field(repr=False)
    substeps: int = 1
    past_limit: bool = False  # a volume-controlled state after the limit point
    volumes: tuple[float, ...] = ()  # every chamber's volume, mm^3


@dataclass(frozen=True)
class PathResult:
    steps: tuple[Step, ...]
    converged: bool  # every requested target was reached (or passed on volume control)
    message: str
    limit_pressure: float | None  # MPa (of the driving chamber), None when no limit point was met
    events: tuple[str, ...]
    stats: SolveStats

    @property
    def pressures(self) -> np.ndarray:
        return np.array([s.pressure for s in self.steps])

    @property
    def volumes(self) -> np.ndarray:
        return np.array([s.volume for s in self.steps])


class LoadShape:
    """Converts between the user's pressure (a float or a sequence) and the load vector L."""

    def __init__(self, targets) -> None:
        pressures = [np.atleast_1d(np.asarray(P, dtype=float)) for P, _ in targets]
        sizes = {p.size for p in pressures}
        if len(sizes) != 1:
            raise SolverInputError("targets", "every target needs the same number of pressures")
        self.n = sizes.pop()
        self.scalar = all(np.ndim(P) == 0 for P, _ in targets)

    def vector(self, P, f: float) -> np.ndarray:
        return np.r_[np.atleast_1d(np.asarray(P, dtype=float)), float(f)]

    def pressure(self, L: np.ndarray):
        """The user-shaped pressure of a load vector: a float or a tuple."""
        return float(L[0]) if self.scalar else tuple(float(p) for p in L[:-1])


def describe_load(L: np.ndarray) -> str:
    """'P = 12.3 kPa, load factor 1' (or 'P = (10, 40, 60) kPa, ...') of a load vector."""
    P = mpa_to_kpa(L[:-1])  # the solver works in MPa; its messages are read in kPa
    text = f"{P[0]:.4g}" if P.size == 1 else "(" + ", ".join(f"{p:.4g}" for p in P) + ")"
    return f"P = {text} kPa, load factor {L[-1]:.4g}"


class History:
    """The last two converged states on the path, for the predictors of `fem.path`."""

    def __init__(self, x, load, volume=None) -> None:
        self.x, self.load, self.volume = x, load, volume
        self.x_prev, self.load_prev, self.volume_prev = None, None, None
        self.tangent = None  # (direction, dx/ds) at x, computed on demand by the path

    def accept(self, x, load, volume=None) -> None:
        self.x_prev, self.load_prev, self.volume_prev = self.x, self.load, self.volume
        self.x, self.load, self.volume = x, load, volume
        self.tangent = None

    def predict(self, load=None, volume=None) -> np.ndarray:
        """Linear extrapolation of the state to a new load (or volume) from the last two states."""
        if self.x_prev is None:
            return self.x
        if volume is not None:
            span, ahead = self.volume - self.volume_prev, volume - self.volume
        else:
            d = np.subtract(self.load, self.load_prev)
            span = float(np.linalg.norm(d))
            ahead = float(np.dot(np.subtract(load, self.load), d) / span) if span > 0 else 0.0
        if span == 0 or not np.isfinite(ahead / span) or ahead / span > 2.0:
            return self.x
        return self.x + (self.x - self.x_prev) * (ahead / span)

    def hermite(self, load, direction: np.ndarray, slope: np.ndarray) -> np.ndarray:
        """The state at `load` on the quadratic x(s) = x + s v + s^2 w through the last state
        with the slope v = dx/ds along the unit load `direction`, and through the previous state
        when it lies on the same load line behind (else the Euler step x + s v)."""
        s = float(np.dot(np.subtract(load, self.load), direction))
        if self.x_prev is not None:
            back = np.subtract(self.load_prev, self.load)
            s_prev = float(np.dot(back, direction))
            if s_prev < 0 and np.linalg.norm(back - s_prev * direction) <= 1e-9 * abs(s_prev):
                w = (self.x_prev - self.x - s_prev * slope) / (s_prev * s_prev)
                if s <= 2.0 * abs(s_prev):
                    return self.x + s * slope + s * s * w
        return self.x + s * slope


def make_step(
    model: SolidModel, shape: LoadShape, L, x, control, record, n_sub=1, past_limit=False, chamber: int = 0
) -> Step:
    """The `Step` of a converged state x at load vector L."""
    volumes = tuple(model.chamber_volume(x, i) for i in range(len(model.chambers)))
    volume = volumes[chamber] if volumes else 0.0
    return Step(shape.pressure(L), float(L[-1]), volume, x, control, record, n_sub, past_limit, volumes)


class ReportingList(list):
    """A list of steps that calls `on_step` for every appended step."""

    def __init__(self, on_step=None) -> None:
        super().__init__()
        self._on_step = on_step

    def append(self, step) -> None:
        super().append(step)
        if self._on_step is not None:
            self._on_step(step)


def failed(steps, events, solver, t0, load, reason, volume=None) -> PathResult:
    """The result of a path that could not advance from `load` (a load vector)."""
    where = describe_load(np.asarray(load, dtype=float))
    if volume is not None:
        where += f", chamber volume {volume:.6g} mm^3"
    msg = f"diverged after the last converged load ({where}): {reason}"
    events.append(msg)
    return PathResult(tuple(steps), False, msg, None, tuple(events), solver.stats(t0))
