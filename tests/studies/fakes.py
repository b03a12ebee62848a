"""Fast fake ePSA simulators for the study tests (no FE solver). Importable by spawned workers as
``tests.studies.fakes:NAME``; behaviour is steered by environment variables so that worker
processes see it too."""

from __future__ import annotations

import errno
import os
import time
from dataclasses import dataclass
from pathlib import Path

from softcrawl.files import atomic_path
from softcrawl.geometry.design import DesignError
from softcrawl.studies.epsa.response import CurveRow


@dataclass(frozen=True)
class ActuatorCurve:
    """The fields of `studies.epsa.response.ActuatorCurve` that the runner reads (no mesh,
    no design)."""

    rows: tuple
    converged: bool
    limit_pressure_kpa: float | None
    message: str = ""
    wall_s: float = 0.0
    n_dofs: int = 0
    material: str = ""

    def to_dict(self):
        return {"rows": [r.__dict__ for r in self.rows], "converged": self.converged}


def _log(design):
    path = os.environ.get("SOFTCRAWL_FAKE_LOG")
    if path:
        with open(path, "a") as handle:
            handle.write(f"{design.chamber_radius:g},{design.fiber_turns},{os.getpid()}\n")


def _write_output(design):
    """Like the VTU of the real evaluator: a file per design in SOFTCRAWL_FAKE_OUTPUT (bytes:
    SOFTCRAWL_FAKE_OUTPUT_BYTES), written atomically. While the file named by
    SOFTCRAWL_FAKE_FULL_DISK exists, the write fails half-way with ENOSPC, as on a full disk (the
    injected fault; a real full disk does the same on a tiny filesystem)."""
    folder = os.environ.get("SOFTCRAWL_FAKE_OUTPUT")
    if not folder:
        return
    size = int(os.environ.get("SOFTCRAWL_FAKE_OUTPUT_BYTES", "65536"))
    full = os.environ.get("SOFTCRAWL_FAKE_FULL_DISK")
    with atomic_path(Path(folder) / f"r{design.chamber_radius:g}-n{design.fiber_turns}.bin") as temp:
        with open(temp, "wb") as handle:
            handle.write(b"\0" * (size // 2))
            if full and os.path.exists(full):
                raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(temp))
            handle.write(b"\0" * (size - size // 2))
            handle.flush()
            os.fsync(handle.fileno())


def _hog_memory(design):
    """While SOFTCRAWL_FAKE_HOG is "RADIUS:MB", the design of that chamber radius allocates MB
    megabytes gradually (25 MB a step, touched, every 0.05 s), as a growing FE model would;
    "RADIUS:MB:block": all at once in one C call, then holds them 30 s (no handler can interrupt
    the call: the memory watchdog's hard stop)."""
    hog = os.environ.get("SOFTCRAWL_FAKE_HOG")
    if not hog or float(hog.split(":")[0]) != design.chamber_radius:
        return
    import numpy as np

    if hog.endswith(":block"):
        held = np.ones(int(float(hog.split(":")[1]) * 2**20 // 8))
        time.sleep(30)
        del held
        return
    held = []
    for _ in range(int(float(hog.split(":")[1]) / 25)):
        held.append(np.ones(25 * 2**20 // 8))
        time.sleep(0.05)
    del held


def analytic_curve(design, pressures_kpa, *, material="fake", limit_kpa=None, wobble=0.0, stiff=1.0):
    """A smooth made-up response: extension grows with chamber radius, fibers cut radial growth."""
    seal = 3.0  # like the FE evaluator, the measured length includes the seal head
    rows = [CurveRow(0.0, design.length + seal, design.outer_radius, 1000.0, 1.0, 0.0, "reference")]
    n = design.fiber_turns
    for i, p in enumerate(pressures_kpa):
        if limit_kpa is not None and p > limit_kpa:
            rows.append(
                CurveRow(p, float("nan"), float("nan"), float("nan"), float("nan"), float("nan"), "failed")
            )
            continue
        a = design.chamber_radius / 3.0
        ext = 0.2 * p * a / stiff * (1 + 0.5 * n / (n + 10)) + wobble * (-1) ** i * p / 20
        rad = 0.02 * p * a**2 / stiff / (1 + n / 5)
        rows.append(
            CurveRow(
                p,
                design.length + seal + ext,
                design.outer_radius + rad,
                1000.0 + p,
                1.0 + p / 200,
                0.1 * n * p / 100,
                "converged",
            )
        )
    return ActuatorCurve(rows=tuple(rows), converged=True, limit_pressure_kpa=limit_kpa, material=material)


def fake_simulate(
    design,
    *,
    material="fake",
    pressures_kpa=(20, 40, 60, 80, 100),
    mesh_size=None,
    quick=False,
    progress=None,
):
    """Instant; sleeps SOFTCRAWL_FAKE_SLEEP s; chamber radius 5 "diverges"; 6 has a limit at 80."""
    _log(design)
    time.sleep(float(os.environ.get("SOFTCRAWL_FAKE_SLEEP", "0")))
    _hog_memory(design)
    _write_output(design)
    if design.chamber_radius == 5.0 and os.environ.get("SOFTCRAWL_FAKE_DIVERGE"):
        good = analytic_curve(design, [p for p in pressures_kpa if p <= 40], material=material)
        return ActuatorCurve(
            rows=good.rows,
            converged=False,
            limit_pressure_kpa=None,
            message="Newton diverged at 60 kPa",
            material=material,
        )
    if design.chamber_radius == 6.0 and os.environ.get("SOFTCRAWL_FAKE_DIVERGE"):
        return analytic_curve(design, pressures_kpa, material=material, limit_kpa=80.0)
    return analytic_curve(design, pressures_kpa, material=material)


def raising_simulate(design, **kwargs):
    """Raises a DesignError for chamber radius 4, otherwise like fake_simulate."""
    if design.chamber_radius == 4.0:
        raise DesignError("chamber_radius", "made-up invalid design for the test")
    return fake_simulate(design, **kwargs)


def paper_like_simulate(
    design,
    *,
    material="fake",
    pressures_kpa=(20, 40, 60, 80, 100),
    mesh_size=None,
    quick=False,
    progress=None,
):
    """Mimics the paper's Fig. 8-9 findings: r = 5, 6 reach a limit point at 80 kPa, the lengths
    of r = 2, 4 fluctuate; fibers stiffen the radial response (N = 20, 25, 50 differ little)."""
    r = design.chamber_radius
    if r in (5.0, 6.0):
        return analytic_curve(design, pressures_kpa, material=material, limit_kpa=80.0)
    wobble = 1.5 if (r in (2.0, 4.0) and design.fiber_turns == 0) else 0.0
    return analytic_curve(design, pressures_kpa, material=material, wobble=wobble)


def early_limit_simulate(
    design,
    *,
    material="fake",
    pressures_kpa=(20, 40, 60, 80, 100),
    mesh_size=None,
    quick=False,
    progress=None,
):
    """r = 6 bursts at 15 kPa, below the first target: only volume-controlled states."""
    if design.chamber_radius != 6.0:
        return fake_simulate(design, material=material, pressures_kpa=pressures_kpa)
    ref = analytic_curve(design, (), material=material).rows
    rows = ref + tuple(
        CurveRow(
            p, design.length + 3 + p / 5, design.outer_radius + p / 10, 1000 + p, 1.0, 0.0, "volume-control"
        )
        for p in (5.0, 10.0, 15.0)
    )
    return ActuatorCurve(
        rows=rows,
        converged=True,
        limit_pressure_kpa=15.0,
        message="limit point at P ~ 15 kPa",
        material=material,
    )


#: The law of `loaded_simulate` (N/mm, N against P in kPa): k_p = 0.05 + 2e-4 P, f_p = 0.04 P; at
#: 70 kPa and above the FE-like response "fails" for the heaviest weight when SOFTCRAWL_FAKE_FAIL_HEAVY
#: is set.
def fake_k_p(p):
    return 0.05 + 2e-4 * p


def fake_f_p(p):
    return 0.04 * p


def loaded_simulate(
    design,
    *,
    material="fake",
    pressures_kpa=(20, 40),
    mesh_size=None,
    quick=False,
    progress=None,
    end_load_n=None,
):
    """A weight W on the top: extension y = (f_p(P) - W) / k_p(P) exactly (eq. 3, m g = 0)."""
    w = 0.0 if end_load_n is None else float(end_load_n)
    fail_heavy = os.environ.get("SOFTCRAWL_FAKE_FAIL_HEAVY") and w >= 1.0
    rows = [
        CurveRow(0.0, design.length, design.outer_radius, 1000.0, 1.0, 0.0, "reference"),
        CurveRow(0.0, design.length - w / fake_k_p(0.0), design.outer_radius, 1000.0, 1.0, 0.0, "converged"),
    ]
    nan = float("nan")
    for p in pressures_kpa:
        if fail_heavy and p >= 70:
            rows.append(CurveRow(p, nan, nan, nan, nan, nan, "failed"))
            continue
        y = (fake_f_p(p) - w) / fake_k_p(p)
        rows.append(CurveRow(p, design.length + y, design.outer_radius, 1000.0 + p, 1.0, 0.0, "converged"))
    failed = any(r.status == "failed" for r in rows)
    return ActuatorCurve(
        rows=tuple(rows),
        converged=not failed,
        limit_pressure_kpa=None,
        material=material,
        message="diverged at 70 kPa" if failed else "",
    )


def limited_simulate(
    design,
    *,
    material="fake",
    pressures_kpa=(20, 40, 60, 80, 100),
    mesh_size=None,
    quick=False,
    progress=None,
):
    """Like fake_simulate, but chamber radii above 4 mm meet a limit point at 60 kPa."""
    limit = 60.0 if design.chamber_radius > 4.0 else None
    return analytic_curve(design, pressures_kpa, material=material, limit_kpa=limit)


def invalid_simulate(design, **kwargs):
    """Every design is invalid (an input error of the evaluation, for every point)."""
    raise DesignError("chamber_radius", "made-up invalid design for the test")


def fake_robot_cases(design, material, mesh, cases):
    """A stand-in for `studies.robot_fe.robot_studies.run_cases` (no FE): theta falls with the
    ring count and with d, splay falls with the ring count, as the rules expect."""
    n, d = design.n_rings, design.d
    rows = []
    for case in cases:
        theta = 0.0 if case == "equal" else 80.0 - 2.0 * n - 3.0 * (d - 14.0)
        rows.append(
            {
                "case": case,
                "step": 0,
                "P1_kpa": 100.0,
                "P2_kpa": 100.0 if case == "equal" else 40.0,
                "P3_kpa": 100.0 if case == "equal" else 60.0,
                "theta_deg": theta,
                "phi_deg": 100.0,
                "phi_cc_deg": 100.5,
                "d_eff_mm": d,
                "extension_mm": 50.0 - 0.1 * n,
                "splay_mm": 3.0 / n,
                "arc_rms_mm": 0.2,
            }  # fmt: skip
        )
    return {"rows": rows, "converged": True, "message": "fake", "wall_s": 0.0, "n_dofs": 0,
            "material": {"epsa": material}}  # fmt: skip


@dataclass(frozen=True)
class FakeDrag:
    """The fields of `studies.foot.model.DragCurve` that optimise-feet reads."""

    converged: bool
    peak: float
    limit_point: tuple | None = None
    message: str = ""


@dataclass(frozen=True)
class FakeFoot:
    """The fields of `studies.foot.model.FootResult` that optimise-feet reads."""

    normal_force: float
    forward: FakeDrag | None
    backward: FakeDrag | None
    message: str = ""
    wall_s: float = 0.0


def fake_foot(
    design, pipe_diameter, *, material, mu_smooth, mu_grooved, quick=False, max_wall_s=None, wedge=1
):
    """A foot without FE, `simulate_foot`'s call: a normal force that grows with the squeeze
    (78 - D), the skirt's thickness and the modulus, F_fwd = mu_smooth N, F_bwd = 2 mu_grooved N
    x angle / 120. While SOFTCRAWL_FAKE_FOOT_FAIL is set to an angle, a skirt narrower than it
    fails to insert in the smallest pipe; a 75 mm backward drag of a 3.5 mm skirt ends past a limit
    point (a lower bound)."""
    youngs = 3.0 * material.mu
    normal = youngs * design.skirt_thickness * (2.0 * design.tip_radius - pipe_diameter) / 2.0
    fail = os.environ.get("SOFTCRAWL_FAKE_FOOT_FAIL")
    if fail and design.angle < float(fail) and pipe_diameter < 56.0:
        return FakeFoot(float("nan"), None, None, "stage insert: Newton did not converge (fake)")
    f_bwd = 2.0 * mu_grooved * normal * design.angle / 120.0
    limit = design.skirt_thickness > 3.4 and pipe_diameter > 74.0
    backward = FakeDrag(False, f_bwd, (1.0, f_bwd), "limit point (fake)") if limit else FakeDrag(True, f_bwd)
    return FakeFoot(normal, FakeDrag(True, mu_smooth * normal), backward, wall_s=0.01)


def fake_feet_crawl(setup, schedule, folder, quick):
    """`study feet`'s per-point crawl, instant: a made-up speed rising with angle and hardness; the
    50A, 30 deg foot "diverges" in its second cycle. Each call appends "SHORE,ANGLE" to
    FOLDER/../calls.log (the tests count the evaluations)."""
    shore = float(setup.material.split("-")[1][:-1])
    angle = setup.foot.angle
    with open(Path(folder).parent / "calls.log", "a") as handle:
        handle.write(f"{shore:g},{angle:g}\n")
    stride = 20.0 + angle / 10.0 + (shore - 50.0) / 5.0
    strides = [stride + 1.0, stride][: setup.cycles]
    if shore == 50.0 and angle == 30.0:
        return {"converged": False, "message": "cycle 2: Newton diverged", "strides_mm": strides[:1]}
    return {"converged": True, "message": "done", "strides_mm": strides, "fe_friction_n": 5.0, "wall_s": 1.0}


def raising_feet_crawl(setup, schedule, folder, quick):
    """Like `fake_feet_crawl`, but the 50A, 60 deg point raises (as a mesh that cannot be built does)."""
    if setup.material == "rubber-50a" and setup.foot.angle == 60.0:
        raise RuntimeError("made-up: the contact faces cannot be built")
    return fake_feet_crawl(setup, schedule, folder, quick)
