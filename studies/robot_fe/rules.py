r"""Table 1 rules of the robot-level studies: the number of connecting rings and the foot radius d.

Each rule encodes the paper's stated reason (Sections II-B and V-C) with named thresholds, takes
the summary rows of its study (one per design) and returns a `RobotDecision`: the value, the
reason in words and the evidence (the quantities each candidate was judged on).

Connecting rings (`ring_rule`). Paper: "If the number of connecting rings is too small, the
successful combination of the three ePSAs into a flexible and adaptable soft robot cannot be
achieved. On the contrary, if the number is too large, the coupling between the three ePSAs will
be tight" and the robot "has optimal extension and bending property when the number of
connecting rings is 3". Encoded:

1. combined: the bundle bends as one body when (a) no actuator leaves the bundle between the
   rings, splay <= SPLAY_MAX_FRACTION_OF_D x d0 (`studies.robot_fe.response`: the largest
   change of an actuator's distance from the robot's centre), and (b) the robot's centreline is
   one arc, arc-fit RMS <= ARC_RMS_MAX_FRACTION_OF_L x L0 (the kinematics of eqs. 4-9 assume it),
   both at the asymmetric load (P1 = 100, P2 = 40, P3 = 60 kPa) and at the equal load;
2. among the combined counts, the best performance: the largest bending angle theta at the
   asymmetric load, each count's theta and equal-pressure extension counted as lost when more
   than COUPLING_LOSS_TOLERANCE below the best of the combined counts; ties (no loss) go to the
   fewest rings (weight, fabrication).

Foot radius d (`foot_radius_rule`). Paper: 12 and 14 mm bend best (an earlier 2D study), and 14
is chosen "considering the size of the endoscope camera". Encoded: the candidates are the d at
which the actuators do not intersect (d > 2 R0 / sqrt(3), with the ring's ligament) and the
central channel between them, of radius d - R0, holds an endoscope camera of diameter
ENDOSCOPE_DIAMETER_MM with CHANNEL_CLEARANCE_MM around it; among them, the d with the largest
bending angle at the asymmetric load (ties within BENDING_TIE_TOLERANCE go to the smaller d:
a slimmer robot).

Integration with `studies.review.table1` (for its owner): call `ring_rule(rows)` and
`foot_radius_rule(rows, R0)` with the rows of `results/robot-rings/.../summary.csv` and
`results/robot-foot-radius/.../summary.csv` (columns named in `RING_COLUMNS`,
`FOOT_COLUMNS`), and fill the rows "connecting rings" and "foot radius d" with `decision.value`,
`decision.reason` and `decision.evidence`; `decision_from_json` reads the `decision.json` that
the study writes beside its summary.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass
from pathlib import Path

from softcrawl import jsonio

#: (1a) an actuator's distance from the robot centre may change by at most this fraction of d0.
SPLAY_MAX_FRACTION_OF_D = 0.10
#: (1b) the centreline's RMS distance from one circle arc, as a fraction of the ePSA length.
ARC_RMS_MAX_FRACTION_OF_L = 0.01
#: (2) a count loses when its bending or extension is more than this fraction below the best.
COUPLING_LOSS_TOLERANCE = 0.02
#: The endoscope camera the central channel must pass: 8 mm, the common head diameter of small
#: USB inspection endoscopes (5.5 and 7 mm heads exist; the decision for them is reported).
ENDOSCOPE_DIAMETER_MM = 8.0
#: Free space around the camera in the channel (the design's minimum ligament).
CHANNEL_CLEARANCE_MM = 0.5
#: Bending angles closer than this fraction count as equal.
BENDING_TIE_TOLERANCE = 0.01

RING_COLUMNS = ("n_rings", "theta_asym_deg", "extension_equal_mm", "splay_max_mm", "arc_rms_max_mm")
FOOT_COLUMNS = ("d", "theta_asym_deg")


@dataclass(frozen=True)
class RobotDecision:
    parameter: str
    value: float | int | None
    reason: str
    evidence: tuple[dict, ...]

    def to_json(self) -> str:
        return jsonio.dumps(asdict(self), indent=2)


def decision_from_json(path) -> RobotDecision:
    data = json.loads(Path(path).read_text())
    return RobotDecision(data["parameter"], data["value"], data["reason"], tuple(data["evidence"]))


def _number(row: Mapping, key: str) -> float:
    try:
        return float(row[key])
    except (KeyError, TypeError, ValueError):
        return math.nan


def ring_rule(rows: Sequence[Mapping], d0: float = 14.0, length: float = 100.0) -> RobotDecision:
    """The ring count of the module docstring from one summary row per count."""
    splay_max, arc_max = SPLAY_MAX_FRACTION_OF_D * d0, ARC_RMS_MAX_FRACTION_OF_L * length
    evidence = []
    for row in sorted(rows, key=lambda r: _number(r, "n_rings")):
        n = int(_number(row, "n_rings"))
        theta, ext = _number(row, "theta_asym_deg"), _number(row, "extension_equal_mm")
        splay, arc = _number(row, "splay_max_mm"), _number(row, "arc_rms_max_mm")
        computed = all(map(math.isfinite, (theta, ext, splay, arc)))
        combined = computed and splay <= splay_max and arc <= arc_max
        evidence.append(
            dict(
                n_rings=n,
                theta_asym_deg=theta,
                extension_equal_mm=ext,
                splay_max_mm=splay,
                arc_rms_max_mm=arc,
                computed=computed,
                combined=combined,
            )  # fmt: skip
        )
    ok = [e for e in evidence if e["combined"]]
    if not ok:
        return RobotDecision(
            "connecting rings",
            None,
            f"no ring count combines the actuators (splay <= {splay_max:.2f} mm and arc-fit RMS <= "
            f"{arc_max:.2f} mm at both loads)",
            tuple(evidence),
        )
    best_theta = max(e["theta_asym_deg"] for e in ok)
    best_ext = max(e["extension_equal_mm"] for e in ok)
    for e in evidence:
        e["bending_loss"] = 1.0 - e["theta_asym_deg"] / best_theta if e["computed"] else math.nan
        e["extension_loss"] = 1.0 - e["extension_equal_mm"] / best_ext if e["computed"] else math.nan
    no_loss = [
        e for e in ok
        if e["bending_loss"] <= COUPLING_LOSS_TOLERANCE and e["extension_loss"] <= COUPLING_LOSS_TOLERANCE
    ]  # fmt: skip
    pick = min(no_loss, key=lambda e: e["n_rings"]) if no_loss else max(ok, key=lambda e: e["theta_asym_deg"])
    too_few = [e["n_rings"] for e in evidence if e["computed"] and not e["combined"]]
    lossy = [e["n_rings"] for e in ok if e not in no_loss]
    reason = (
        f"{pick['n_rings']} rings: the fewest that combine the actuators into one arc (splay "
        f"{pick['splay_max_mm']:.2f} <= {splay_max:.2f} mm, arc RMS {pick['arc_rms_max_mm']:.2f} <= "
        f"{arc_max:.2f} mm) with no more than {100 * COUPLING_LOSS_TOLERANCE:g} % loss of bending and "
        f"extension against the best combined count; not combined: {too_few or 'none'}; "
        f"coupling losses: {lossy or 'none'}"
    )
    return RobotDecision("connecting rings", pick["n_rings"], reason, tuple(evidence))


def channel_admits_camera(d: float, R0: float) -> bool:
    """The central channel (radius d - R0) holds the camera with its clearance."""
    return d - R0 >= ENDOSCOPE_DIAMETER_MM / 2 + CHANNEL_CLEARANCE_MM - 1e-9


def foot_radius_rule(rows: Sequence[Mapping], R0: float = 9.0) -> RobotDecision:
    """The foot radius d of the module docstring from one summary row per d."""
    evidence = []
    for row in sorted(rows, key=lambda r: _number(r, "d")):
        d, theta = _number(row, "d"), _number(row, "theta_asym_deg")
        evidence.append(
            dict(
                d=d,
                theta_asym_deg=theta,
                channel_diameter_mm=2 * (d - R0),
                camera_fits=channel_admits_camera(d, R0),
                computed=math.isfinite(theta),
            )  # fmt: skip
        )
    ok = [e for e in evidence if e["camera_fits"] and e["computed"]]
    if not ok:
        return RobotDecision(
            "foot radius d",
            None,
            f"no computed d leaves a channel for a {ENDOSCOPE_DIAMETER_MM:g} mm camera",
            tuple(evidence),
        )
    best = max(e["theta_asym_deg"] for e in ok)
    pick = min(
        (e for e in ok if e["theta_asym_deg"] >= (1 - BENDING_TIE_TOLERANCE) * best), key=lambda e: e["d"]
    )
    overall = max((e for e in evidence if e["computed"]), key=lambda e: e["theta_asym_deg"])
    reason = (
        f"d = {pick['d']:g} mm: the best bending ({pick['theta_asym_deg']:.1f} deg at P = (100, 40, 60) "
        f"kPa) among the d whose channel (2 (d - R0) = {pick['channel_diameter_mm']:g} mm) holds a "
        f"{ENDOSCOPE_DIAMETER_MM:g} mm camera with {CHANNEL_CLEARANCE_MM:g} mm clearance; the best "
        f"bending overall is d = {overall['d']:g} mm ({overall['theta_asym_deg']:.1f} deg)"
    )
    return RobotDecision("foot radius d", pick["d"], reason, tuple(evidence))
