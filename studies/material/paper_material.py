r"""Which material reproduces the paper's own FE observations (Section V-A, Figs. 8 and 9)?

`softcrawl study paper-material --out DIR` writes DIR/paper-material/: windows.csv (every law
and shape scanned, the shear-modulus interval of each observation and of their intersection),
paper-material.json (the verdicts, the window centres the other studies run at, and the
observations no constant reproduces, with the reason) and paper-material.md.

Observations (each a constant below with the paper's sentence):

- r = 2, 3, 4 mm withstand 100 kPa (Fig. 8(b) shows them to 100 kPa; r = 3 is selected);
- r = 5 and 6 mm "cannot withstand a pressure of more than 80 kPa": they reach 80 kPa and fail
  before 100 kPa (a limit point in [80, 100) kPa);
- r = 2 and 4 mm "fluctuate", r = 3 does not;
- N = 20, 25 and 50 "differ little" (rule `studies.epsa.rules.SIMILAR_EXTENSION_REL`).

Model. Without fibers the ePSA is a thick tube (A = r, B = 9 mm) closed by its seal heads. Its
limit pressure is the closed-end tube's (`fem.tube_theory`), which the FE ePSA reproduces within
0.7 % for Neo-Hookean (default mesh, mu = 0.03 MPa: 33.8/24.7/18.3/13.3/9.18 kPa against
33.6/24.6/18.2/13.2/9.12 kPa for r = 2..6), so the scan needs no FE. Every law here is
mu f(I1; shape): Neo-Hookean (no shape), Yeoh with shape (C20/C10, C30/C10), Gent with shape Jm.
At a fixed shape, stresses scale with mu, so P_lim = k_r(shape) mu, and each observation is an
interval of mu: withstands 100 kPa -> mu >= 100 kPa / k_r (any mu without a limit point);
fails in [80, 100) -> mu in [80/k_r, 100/k_r). Across shapes the limit pressures are not
proportional to mu (a stiffening law removes the limit points of the thick-walled small
chambers first), which is why the shapes are scanned.

The fibered observation (N) needs the FE fiber-turns study; `fiber_observation` reads it at the
window centre. "Fluctuating" lengths cannot be reproduced by any law W(I1) with W' > 0: the
closed-end tube's length grows monotonically with pressure on its stable branch (lz grows with
the inner stretch, which grows with pressure); `length_curve` shows it at the centre.
"""

from __future__ import annotations

import json
import math
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from softcrawl.fem.laws import Gent, NeoHookean, Yeoh
from softcrawl.fem.tube_theory import closed_end_limit, closed_end_pressure
from softcrawl.materials import get_material
from softcrawl.materials.fem_law import solid_law
from softcrawl.studies.declaration import StudyRequest
from softcrawl.studies.epsa import rules
from softcrawl.studies.outcome import StudyOutcome
from softcrawl.studies.sweeps.tables import read_csv, write_csv
from softcrawl.units import kpa_to_mpa, mpa_to_kpa

#: "the ePSA with an air chamber radius of r = 6 mm or r = 5 mm ... cannot withstand a pressure of
#: more than 80 kPa" (Section V-A): these radii reach FAIL_WINDOW_KPA[0] and fail below [1].
FAIL_RADII = (5.0, 6.0)
FAIL_WINDOW_KPA = (80.0, 100.0)
#: The other radii of Fig. 8 run to 100 kPa ("when the input air pressure changes from 0 to
#: 100kPa"; r = 2 and 4 are discussed as fluctuating, r = 3 is selected).
WITHSTAND_RADII = (2.0, 3.0, 4.0)
TARGET_KPA = 100.0
#: "The ePSA length with an air chamber radius of r = 4 mm or r = 2 mm fluctuates."
FLUCTUATING_RADII = (2.0, 4.0)
#: "when the number is N = 50, N = 25, or N = 20, the reinforcing effect ... is not much different"
CLOSE_TURNS = (20.0, 25.0, 50.0)
OUTER_RADIUS = 9.0
#: Shapes scanned (the fitted shapes of `materials.presets` are added): Yeoh C20/C10 with C30 = 0,
#: Gent Jm.
YEOH_SHAPES = tuple(np.round(np.linspace(0.0, 0.04, 21), 4))
GENT_JM = tuple(float(v) for v in np.round(np.geomspace(12.0, 2000.0, 24), 2))
#: Largest inner stretch searched for a limit point (the FE actuators burst below 3.5).
LA_MAX = 12.0


@dataclass(frozen=True)
class ShapeWindow:
    """One law and shape: k_r = P_lim / mu (None: no limit point) and the mu intervals (MPa)."""

    law: str
    shape: str  #: e.g. "C20/C10=0.01", "Jm=40", "-"
    k: dict  #: radius -> P_lim / mu or None
    withstand_mu: tuple[float, float]  #: all WITHSTAND_RADII withstand 100 kPa
    fail_mu: dict  #: radius -> [lo, hi) for a limit in the fail window, or None (impossible)
    window_all: tuple[float, float] | None  #: every Fig. 8 limit-pressure observation
    window_r5: tuple[float, float] | None  #: all but "r = 6 reaches 80 kPa"

    @property
    def centre(self) -> float | None:
        w = self.window_all or self.window_r5
        return None if w is None else 0.5 * (w[0] + w[1])


def _interval(*parts):
    lo = max([p[0] for p in parts], default=0.0)
    hi = min([p[1] for p in parts], default=math.inf)
    return (lo, hi) if lo < hi else None


def shape_window(law_name: str, shape: str, unit_law) -> ShapeWindow:
    """The mu window of one shape; `unit_law` is the law at mu = 1 MPa (limit pressures in MPa)."""
    k = {}
    for r in WITHSTAND_RADII + FAIL_RADII:
        lim = closed_end_limit(unit_law, r, OUTER_RADIUS, la_max=LA_MAX)
        k[r] = None if lim is None else lim[1]
    target = kpa_to_mpa(TARGET_KPA)
    withstand = (max([target / k[r] for r in WITHSTAND_RADII if k[r] is not None], default=0.0), math.inf)
    lo, hi = (kpa_to_mpa(v) for v in FAIL_WINDOW_KPA)
    fail = {r: None if k[r] is None else (lo / k[r], hi / k[r]) for r in FAIL_RADII}
    window_all = None if None in fail.values() else _interval(withstand, *fail.values())
    r5 = fail[FAIL_RADII[0]]
    r6_fails = (0.0, target / k[FAIL_RADII[1]]) if k[FAIL_RADII[1]] is not None else None
    window_r5 = None if r5 is None or r6_fails is None else _interval(withstand, r5, r6_fails)
    return ShapeWindow(law_name, shape, k, withstand, fail, window_all, window_r5)


def scan(yeoh_shapes=YEOH_SHAPES, gent_jm=GENT_JM) -> list[ShapeWindow]:
    fit_yeoh, fit_gent = get_material("ecoflex-00-50-yeoh").law, get_material("ecoflex-00-50-gent").law
    c10, c20, c30 = fit_yeoh.c10, fit_yeoh.c20, fit_yeoh.c30
    out = [shape_window(NeoHookean.NAME, "-", NeoHookean(mu=1.0, bulk=1000.0))]
    shapes = sorted({*yeoh_shapes, round(c20 / c10, 6)})
    for a in shapes:
        c3 = c30 / c10 if math.isclose(a, c20 / c10, rel_tol=1e-6) else 0.0
        out.append(
            shape_window(Yeoh.NAME, f"C20/C10={a:g}", Yeoh(c10=0.5, c20=0.5 * a, c30=0.5 * c3, bulk=1000.0))
        )
    for jm in sorted({*gent_jm, round(fit_gent.jm, 2)}):
        out.append(shape_window(Gent.NAME, f"Jm={jm:g}", Gent(mu=1.0, jm=jm, bulk=1000.0)))
    return out


def length_curve(unit_law, mu: float, radius: float, pressures_kpa=(20, 40, 60, 80, 100)):
    """Closed-end tube lengths (mm, L0 = 100) at the pressures on the stable branch (up to the
    limit point), for the fluctuation rule (`studies.epsa.rules.fluctuation`)."""
    from scipy.optimize import brentq

    lim = closed_end_limit(unit_law, radius, OUTER_RADIUS, la_max=LA_MAX)
    la_top = lim[0] if lim is not None else LA_MAX
    lengths = []
    for p in pressures_kpa:
        target = kpa_to_mpa(p) / mu
        if closed_end_pressure(unit_law, la_top, radius, OUTER_RADIUS)[0] < target:
            break
        la = brentq(
            lambda x, t=target: closed_end_pressure(unit_law, x, radius, OUTER_RADIUS)[0] - t, 1.0, la_top
        )
        lengths.append(100.0 * closed_end_pressure(unit_law, la, radius, OUTER_RADIUS)[1])
    return lengths


def fiber_observation(results: Path, material: str) -> dict | None:
    """N = 20, 25 vs N = 50 at 100 kPa from RESULTS/fiber-turns/MATERIAL/curves.csv, if present."""
    path = Path(results) / "fiber-turns" / material / "curves.csv"
    if not path.exists():
        return None
    sel = rules.select_fiber_turns(read_csv(path))
    return {"material": material, "selected_N": sel.value, "evidence": list(sel.evidence)}


#: Presets whose shape is scanned and whose window centre the other studies run at (`NAME@mu=`).
CENTRE_PRESETS = {"neo-hookean": "ecoflex-00-50", "yeoh": "ecoflex-00-50-yeoh", "gent": "ecoflex-00-50-gent"}
NAME = "paper-material"


def _fmt(w):
    return "" if w is None else f"{w[0]:.4g}" if math.isinf(w[1]) else f"{w[0]:.4g}-{w[1]:.4g}"


def centres(windows: list[ShapeWindow]) -> dict[str, dict]:
    """The window centre of each preset's own shape (Neo-Hookean; the full-range Yeoh and Gent
    fits), as a material name `PRESET@mu=CENTRE` for the studies."""
    shape_of = {  # the shape labels of `scan`, per law scanned
        NeoHookean: lambda law: "-",
        Yeoh: lambda law: f"C20/C10={round(law.c20 / law.c10, 6):g}",
        Gent: lambda law: f"Jm={round(law.jm, 2):g}",
    }
    out = {}
    for law, preset in CENTRE_PRESETS.items():
        m = get_material(preset)
        shape = shape_of[type(m.law)](m.law)
        w = next(x for x in windows if x.law == law and x.shape == shape)
        if w.centre is not None:
            out[law] = {"shape": shape, "window_mu": w.window_all or w.window_r5, "centre_mu": w.centre}
            out[law]["material"] = f"{preset}@mu={w.centre:.3g}"
    return out


def run_paper_material(out, results=None) -> tuple[list[str], list[Path]]:
    """Scan, write windows.csv, paper-material.json and .md; returns (lines, written)."""
    folder = Path(out) / NAME
    folder.mkdir(parents=True, exist_ok=True)
    windows = scan()
    write_csv(
        [
            {"law": w.law, "shape": w.shape}
            | {f"plim_over_mu_r{r:g}": "" if v is None else round(v, 6) for r, v in w.k.items()}
            | {"withstand_mu": _fmt(w.withstand_mu)}
            | {f"fail_80_100_mu_r{r:g}": _fmt(v) for r, v in w.fail_mu.items()}
            | {"window_all_mu": _fmt(w.window_all), "window_without_r6_at_80_mu": _fmt(w.window_r5)}
            for w in windows
        ],
        folder / "windows.csv",
    )
    chosen = centres(windows)
    nh = chosen.get("neo-hookean")
    fluct = {}
    if nh is not None:
        for r in WITHSTAND_RADII:
            lengths = length_curve(NeoHookean(mu=1.0, bulk=1000.0), nh["centre_mu"], r)
            curve = rules.DesignCurve(
                r,
                "completed",
                "",
                None,
                100.0,
                9.0,
                [20.0 * (i + 1) for i in range(len(lengths))],
                lengths,
                [9.0] * len(lengths),
            )
            fluct[r] = {
                "lengths_mm": [round(x, 3) for x in lengths],
                "fluctuating": rules.fluctuation(curve)[0],
            }
    record = {
        "observations": {
            "withstand_100kpa": list(WITHSTAND_RADII),
            "fail_between_kpa": {"radii": list(FAIL_RADII), "window": list(FAIL_WINDOW_KPA)},
            "fluctuating": list(FLUCTUATING_RADII),
            "close_turns": list(CLOSE_TURNS),
        },
        "all_fig8_limit_observations_reproduced_by": [f"{w.law} {w.shape}" for w in windows if w.window_all],
        "why_not_all": why_not_all(windows),
        "centres": chosen,
        "fluctuation_at_neo_hookean_centre": fluct,
        "fiber_observation": {
            law: fiber_observation(Path(results or out), c["material"]) for law, c in chosen.items()
        },
        "mesh": "none: closed-end thick-tube theory (fem.tube_theory); FE check by the chamber-radius "
        "studies (default mesh) in fe_check",
        "fe_check": fe_check(
            Path(results or out),
            ["ecoflex-00-50", "ecoflex-00-50-yeoh", "ecoflex-00-50-gent"]
            + [c["material"] for c in chosen.values()],
        ),
    }
    (folder / "paper-material.json").write_text(json.dumps(record, indent=2, default=str) + "\n")
    lines = [f"{NAME}: {len(windows)} law shapes scanned -> {folder}"]
    lines += [
        f"  {law}: window mu {_fmt(c['window_mu'])} MPa, centre {c['material']}" for law, c in chosen.items()
    ]
    n_all = len(record["all_fig8_limit_observations_reproduced_by"])
    lines.append(f"  shapes reproducing every Fig. 8 limit-pressure observation: {n_all}")
    return lines, [folder / "windows.csv", folder / "paper-material.json"]


def fe_check(results, materials) -> dict:
    """FE limit pressures of the chamber-radius studies under `results` against the closed-end
    tube theory with the same law (kPa), for every material that has such a study."""
    import csv

    out = {}
    for m in materials:
        path = Path(results) / "chamber-radius" / m / "summary.csv"
        if not path.exists():
            continue
        law = solid_law(get_material(m))
        rows = {}
        with open(path) as fh:
            for row in csv.DictReader(fh):
                r = float(row["chamber_radius"])
                fe = float(row["limit_pressure_kpa"]) if row["limit_pressure_kpa"] else None
                lim = closed_end_limit(law, r, OUTER_RADIUS, la_max=LA_MAX)
                theory = None if lim is None else mpa_to_kpa(lim[1])
                rows[f"{r:g}"] = {
                    "fe_limit_kpa": fe,
                    "theory_limit_kpa": theory,
                    "relative_difference": None if None in (fe, theory) else fe / theory - 1.0,
                }
        out[m] = rows
    return out


def to_dict(w: ShapeWindow) -> dict:
    return asdict(w)


def why_not_all(windows: list[ShapeWindow]) -> str:
    """Why r = 5 and r = 6 cannot both fail in [80, 100) kPa: P_lim(5) / P_lim(6) must be at most
    100/80 = 1.25, and no scanned shape brings it below its minimum here."""
    ratios = [w.k[5.0] / w.k[6.0] for w in windows if w.k[5.0] is not None and w.k[6.0] is not None]
    bound = FAIL_WINDOW_KPA[1] / FAIL_WINDOW_KPA[0]
    no_r5 = [f"{w.law} {w.shape}" for w in windows if w.k[5.0] is None]
    return (
        f"both need P_lim(r=5)/P_lim(r=6) <= {bound:g}; over the {len(ratios)} shapes where both have a "
        f"limit point it is {min(ratios):.3f}-{max(ratios):.3f} (the thinner r = 6 wall bursts at "
        f"~{1 / max(ratios):.2f}-{1 / min(ratios):.2f} of the r = 5 pressure whatever the law); "
        f"stiffer shapes remove the r = 5 limit point altogether ({len(no_r5)} shapes) before the ratio drops"
    )


def run_request(request: StudyRequest) -> StudyOutcome:
    """`softcrawl study paper-material` (no FE: the closed-end tube theory)."""
    lines, written = run_paper_material(request.out)
    return StudyOutcome(tuple(lines), tuple(written))
