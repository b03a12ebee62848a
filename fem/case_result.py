"""The outcome of one verification case (`fem.verification`, `fem.law_verification`)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass(frozen=True)
class CaseResult:
    name: str
    error: float  # worst relative error against the analytic solution
    tolerance: float
    details: dict = field(default_factory=dict)

    @property
    def passed(self) -> bool:
        return bool(np.isfinite(self.error) and self.error <= self.tolerance)
