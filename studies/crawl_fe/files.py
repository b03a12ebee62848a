r"""Run the FE-body crawl and write its files (`softcrawl crawl --body fe`).

    build_body (gravity by the pipe: `pipe.PIPES`) -> into_pipe (insert, friction, weight)
      -> crawl_cycles (the schedule, each chamber its own pressure) -> OUT/

OUT/states.csv     one row per state: the setup phases (insert, friction, load) at cycle 0,
                   then every schedule segment's end (`cycle.BodyState`): time, the three
                   pressures (kPa) and chamber volumes (mm^3), each foot's axial displacement and
                   centreline position (mm), the lateral drift, the body's bend and heading (deg),
                   each foot's wall normal force and axial friction (N), the holds' largest force;
OUT/cycles.csv     one row per cycle: the advance along the centreline (stride, mm), speed
                   = stride / cycle time (mm/s), the turn (deg), the wall time it took (s;
                   `cycle.CycleLog`, blank where a resumed checkpoint did not hold it);
OUT/summary.json   the setup (pipe, gravity, mesh, friction and its source, the silicone and
                   its modulus), the body's mass per part against the prototype's 70.2 g, the
                   strides and speeds beside the paper's (Table 2 in a straight pipe, Section
                   VII-D-2's 12.9 / 19.1 mm/s vertically) and the solver's figures (DOFs, Newton
                   iterations, assembly and linear seconds, wall time, peak memory; the wall
                   time per cycle, `cycle_wall_s`);
OUT/crawl.png      each foot's centreline position and the pressures against the state;
OUT/vtu/crawl.pvd  one VTU of the body per state (`fem.vtu.write_state`, float32 unless
                   precision 64), the states in order (the setup phases at negative times); a
                   wedge (`--wedge 3`) turned into the whole body;
                   vtu/pipe.vtu the pipe's wall (open both in ParaView).

A stage that does not converge ends the run: the files then hold the states up to the last
converged one and summary.json says where it stopped (`converged`: false, the solver's message).
"""

from __future__ import annotations

import math
import resource
import time
from pathlib import Path

import meshio
import numpy as np

from softcrawl.fem.errors import SolverInputError
from softcrawl.fem.linsolve import default_solver
from softcrawl.fem.vtu import write_pvd, write_state
from softcrawl.provenance import write_summary
from softcrawl.studies.crawl.files import material_source
from softcrawl.studies.crawl.resume import Totals
from softcrawl.studies.crawl.schedule import Schedule
from softcrawl.studies.crawl_fe.cycle import FootProbe, crawl_cycles
from softcrawl.studies.crawl_fe.mass import TONNE_TO_G, mass_summary
from softcrawl.studies.crawl_fe.model import FEET, build_body
from softcrawl.studies.crawl_fe.pipe import PIPES, PLAN_TURN_DEG, into_pipe, pipe_wall
from softcrawl.studies.crawl_fe.summary import paper_speed, summary_mesh, summary_text
from softcrawl.studies.epsa.model import solid_material
from softcrawl.studies.plots.style import pyplot, save
from softcrawl.studies.sweeps.tables import write_csv
from softcrawl.units import kpa_to_mpa

#: Sub-steps of the ramp of the body's weight after friction is on (vertical pipes).
LOAD_STEPS = 2


def left(budget: float | None, t0: float) -> float | None:
    """What is left of a wall-time budget started at t0 (at least 1 us, so that it stops at once)."""
    return None if budget is None else max(budget - (time.perf_counter() - t0), 1e-6)


def ended(message: str, max_wall_s: float | None) -> str:
    """How the run ended; a stop at the time limit says so with the user's limit first (the
    solver's own message quotes the budget left to the stage that stopped)."""
    if max_wall_s is not None and "wall-time budget" in message:
        return f"time limit of {max_wall_s:g} s reached (checked before each solve attempt): {message}"
    return message


def state_rows(run, crawl, probe) -> list[dict]:
    """The rows of states.csv (module docstring); `probe`: the run's `cycle.FootProbe`."""
    rows = []
    for st in run.states:
        arc = probe.arc(st.x)
        rows.append(
            {"phase": st.phase, "cycle": 0, "time_s": float("nan")}
            | {f"{f}_z_mm": v for f, v in probe.z(st.x).items()}
            | {f"{f}_arc_mm": arc[f] for f in FEET}
            | {f"{f}_normal_n": st.normal[f] for f in FEET}
            | {f"{f}_friction_z_n": float(st.friction[f][2]) for f in FEET}
            | {"holds_max_n": max(abs(v) for v in st.holds.values())}
        )
    for st in crawl.states if crawl is not None else ():
        rows.append(
            {"phase": "cycle", "cycle": st.cycle, "time_s": st.t}
            | {f"P{i + 1}_kpa": p for i, p in enumerate(st.pressures_kpa)}
            | {f"V{i + 1}_mm3": v for i, v in enumerate(st.volumes)}
            | {f"{f}_z_mm": st.z[f] for f in FEET}
            | {f"{f}_arc_mm": st.arc[f] for f in FEET}
            | {"drift_x_mm": st.drift[0], "drift_y_mm": st.drift[1]}
            | {"bend_deg": st.bend_deg, "heading_deg": st.heading_deg}
            | {f"{f}_normal_n": st.normal[f] for f in FEET}
            | {f"{f}_friction_z_n": st.friction_z[f] for f in FEET}
            | {"holds_max_n": st.holds_max, "newton": st.newton}
        )
    return rows


def run_time(cycle: int, t: float, cycle_s: float) -> float:
    """A state's time on the run's clock: `t` in cycle `cycle` (0: the ramp to the first row, at 0)."""
    return t + (cycle - 1) * cycle_s if cycle else 0.0


def write_vtu(folder: Path, bm, run, crawl, factor: float, cycle_s: float, precision: int) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    entries = []
    for k, st in enumerate(run.states):
        t = (k - len(run.states)) * 1e-3  # the setup before the schedule's t = 0
        f = factor if st.phase == "load" else 0.0
        path = write_state(folder / f"setup{k}.vtu", bm.model, st.x, factor=f, time=t, precision=precision,
                           copies=bm.copies)  # fmt: skip
        entries.append((path, t))
    for k, st in enumerate(crawl.states if crawl is not None else ()):
        t = run_time(st.cycle, st.t, cycle_s)
        P = [kpa_to_mpa(p) for p in bm.pressures(st.pressures_kpa)]
        path = write_state(folder / f"state{k:04d}.vtu", bm.model, st.x, pressure_mpa=P, factor=factor,
                           time=t, precision=precision, copies=bm.copies)  # fmt: skip
        entries.append((path, t))
    return write_pvd(folder / "crawl.pvd", [p.name for p, _ in entries], [t for _, t in entries])


def write_wall(path: Path, wall, s0: float, s1: float, around: int = 48, along: int = 60) -> Path:
    """The pipe's wall (a `CylinderWall`, an `ElbowPipe` or a `CorrugatedPipe`) between centreline
    arc lengths s0 and s1 as a quad surface (meshio), for ParaView beside vtu/crawl.pvd; a bellows'
    corrugations get at least 8 rings per pitch."""
    corrugated = hasattr(wall, "amplitude")
    if corrugated:
        along = max(along, int(np.ceil(8 * (s1 - s0) / wall.pitch)) + 1)
    s = np.linspace(s0, s1, along)
    radius = wall.profile(s)[0] if corrugated else np.full(along, wall.radius)
    if hasattr(wall, "frame"):
        c, w, u = wall.frame(s)
    else:
        a = np.asarray(wall.axis)
        c = np.asarray(wall.centre) + s[:, None] * a
        w = np.broadcast_to(a, c.shape)
        u = np.broadcast_to(np.cross(a, [0.0, 1.0, 0.0] if abs(a[1]) < 0.9 else [1.0, 0.0, 0.0]), c.shape)
        u = u / np.linalg.norm(u, axis=1)[:, None]
    v = np.cross(w, u)
    angle = np.linspace(0.0, 2 * np.pi, around, endpoint=False)
    ring = np.cos(angle)[None, :, None] * u[:, None] + np.sin(angle)[None, :, None] * v[:, None]
    points = (c[:, None] + radius[:, None, None] * ring).reshape(-1, 3)
    i, k = np.meshgrid(np.arange(along - 1), np.arange(around), indexing="ij")
    a0, a1 = i * around + k, i * around + (k + 1) % around
    quads = np.stack([a0, a1, a1 + around, a0 + around], axis=-1).reshape(-1, 4)
    meshio.write(path, meshio.Mesh(points, [("quad", quads)]))
    return path


def value(row: dict, key: str) -> float:
    """A number of a states.csv row (as written or as read back), NaN where it has none."""
    v = row.get(key)
    return float("nan") if v in (None, "") else float(v)


def plot_body(rows: list[dict], rest: dict, cycle_s: float, path: Path, title: str) -> Path:
    """Top: each foot's advance along the centreline from where it sat in the undeformed body
    (`rest`: foot -> arc length, mm) against time (the inserted state at t = 0, when states.csv has
    it); middle: the body's bend and heading (deg); bottom: the three pressures (kPa)."""
    plt = pyplot()
    start = [r for r in rows if r["phase"] != "cycle" and np.isfinite(value(r, "rear_arc_mm"))]
    cyc = [r for r in rows if r["phase"] == "cycle"]
    drawn = start[-1:] + cyc
    t = [
        0.0 if r["phase"] != "cycle" else run_time(int(r["cycle"]), value(r, "time_s"), cycle_s)
        for r in drawn
    ]
    fig, (top, middle, bottom) = plt.subplots(3, 1, figsize=(7, 8), sharex=True)
    for f in FEET:
        top.plot(t, [value(r, f"{f}_arc_mm") - rest[f] for r in drawn], marker="o", label=f"{f} foot")
    top.set_ylabel("advance along the centreline (mm)")
    top.legend()
    tc = t[len(drawn) - len(cyc) :]
    middle.plot(tc, [value(r, "bend_deg") for r in cyc], marker=".", label="bend")
    middle.plot(tc, [value(r, "heading_deg") for r in cyc], marker=".", label="heading")
    middle.set_ylabel("angle (deg)")
    middle.legend()
    for i in (1, 2, 3):
        bottom.plot(tc, [value(r, f"P{i}_kpa") for r in cyc], marker=".", label=f"chamber {i}")
    bottom.set_ylabel("pressure (kPa)")
    bottom.set_xlabel("time (s)")
    bottom.legend()
    top.set_title(title)
    return save(fig, path)


def run_and_write(
    setup,
    schedule,
    out: Path,
    *,
    pipe: str = "straight",
    bend_radius: float | None = None,
    mesh="quick",
    design=None,
    silicone=None,
    precision: int = 32,
    progress=print,
    friction_source: str = "given by the caller",
    max_wall_s: float | None = None,
    store=None,
    resumed=None,
    inertia: bool = False,
    corrugation: tuple[float, float] | None = None,
) -> tuple:
    """One FE-body crawl of `setup.cycles` cycles of `schedule` (or of a gait plan: a sequence of
    schedules, one per cycle, `studies.crawl_fe.gait_plan`) in `pipe`, its files in `out`
    (module docstring); returns (converged, summary). `max_wall_s`: the run's wall-time budget
    (s; None: none): past it the run stops where it stands and writes what it has. `mesh`:
    "quick", "default" or a `BodyMeshSettings`; `design`: the robot (None: Table 1's; `build_body`).
    `store` (`resume.BodyStore`): the inserted state and every converged sub-step of the cycles
    are written to it; it is cleared once the files are written, unless the run stopped at its
    time limit (then it is kept to be resumed); `resumed` (its `load()`): continue from there.
    `inertia`: the body's lumped mass over the schedule's time (`build_body`); `corrugation`: a
    bellows' (depth, pitch) in mm (`pipe.pipe_wall`)."""
    t0 = time.perf_counter()
    plan = not isinstance(schedule, Schedule)
    if setup.copies > 1 and (pipe in ("elbow", "bellows") or plan):
        why = "a gait plan" if plan else f"a {pipe}"
        raise SolverInputError(
            "wedge", f"{why} breaks the body's three-fold symmetry (docs/decisions/096-body-wedge.md)"
        )
    cycles = len(schedule) if plan else setup.cycles
    first = schedule[0] if plan else schedule
    gravity = PIPES[pipe]
    kwargs = {} if silicone is None else {"silicone": silicone}
    bm = build_body(setup, mesh, gravity=gravity, design=design, inertia=inertia, **kwargs)
    front_tip = float(np.asarray(bm.model.nodes)[2].max())
    turn_deg = PLAN_TURN_DEG if plan else 0.0  # a plan's bends are in ePSA 1's plane (`PLAN_TURN_DEG`)
    wall = pipe_wall(pipe, setup.pipe.radius, front_tip=front_tip, bend_radius=bend_radius, turn_deg=turn_deg,
                     corrugation=corrugation)  # fmt: skip
    built, solver = time.perf_counter() - t0, default_solver()
    progress(f"body: {bm.n_dofs} DOFs on the {summary_mesh(mesh)} mesh; built in {built:.0f} s; "
             f"linear solver {solver}")  # fmt: skip

    def step_line(step) -> None:
        # with inertia, the kinetic energy shows a snap (docs/decisions/089-inertia.md)
        energy = None if bm.inertia is None else bm.copies * bm.inertia.kinetic_energy()  # the whole body's
        moving = "" if energy is None else f", kinetic energy {energy:.3g} mJ"
        progress(f"  {step.stage} s={step.s:.4g}: {sum(step.iterations)} Newton iterations, "
                 f"{time.perf_counter() - t0:.0f} s{moving}")  # fmt: skip

    if resumed is not None:
        store.restore(bm, wall, resumed)
        run = resumed.run
        progress(f"resumed from {resumed.describe()}")
    else:
        run = into_pipe(bm, insert_steps=setup.insert_steps, load_steps=LOAD_STEPS if gravity else 0,
                        wall=wall, on_step=step_line, max_wall_s=max_wall_s)  # fmt: skip
        if store is not None and run.converged:
            store.save_inserted(bm, run)
    factor = 1.0 if gravity else 0.0
    before = resumed.crawl if resumed is not None else Totals()  # the cycles' effort in earlier processes
    crawl, t_crawl = None, time.perf_counter()

    def saving(cursor, log) -> None:
        c, wall_s = cursor, time.perf_counter() - t_crawl
        work = Totals(c.newton_iterations, c.assembly_s, c.solve_s, wall_s, c.factorizations)
        store.save_cycle(bm, run, cursor, log, before.plus(work))

    if run.converged:
        crawl = crawl_cycles(bm, run.states[-1].x, schedule, cycles=cycles, steps=setup.steps,
                             factor=factor, wall=wall, on_step=step_line, max_wall_s=left(max_wall_s, t0),
                             log=getattr(resumed, "log", None), start=getattr(resumed, "cursor", None),
                             on_cursor=saving if store is not None else None)  # fmt: skip
    converged = run.converged and crawl.converged
    spent = before.plus(crawl) if crawl is not None else before
    earlier = run.wall_s + before.wall_s if resumed is not None else 0.0  # earlier processes' wall time
    contact_s = sum(c.seconds for c in bm.model.contacts)
    probe = FootProbe(bm.model.space, wall, bm.copies)
    rest = probe.arc(np.zeros(bm.n_dofs))
    rows = state_rows(run, crawl, probe)
    out.mkdir(parents=True, exist_ok=True)
    write_csv(rows, out / "states.csv")
    T = first.cycle_s
    paper, paper_source = paper_speed(pipe, setup.pipe_diameter)
    strides = crawl.strides if crawl is not None else ()
    turns = crawl.turns if crawl is not None else ()
    # each cycle's wall time (`cycle.CycleLog`); None where a resumed checkpoint did not hold it
    cycle_s = [None if t is None or not math.isfinite(t) else t for t in crawl.cycle_s] if crawl else []
    cycle_rows = [
        {"cycle": k + 1, "stride_mm": s, "speed_mm_s": s / T, "turn_deg": a, "wall_s": "" if t is None else t}
        for k, (s, a, t) in enumerate(zip(strides, turns, cycle_s))
    ]
    empty = {"cycle": "", "stride_mm": "", "speed_mm_s": "", "turn_deg": "", "wall_s": ""}
    write_csv(cycle_rows or [empty], out / "cycles.csv")
    mass = mass_summary(bm.design, bm.model.mesh, bm.materials, bm.copies)
    silicone_law = solid_material(bm.materials["epsa"])[1]
    dynamics = None
    if bm.inertia is not None:
        scheme = "backward Euler, HRZ-lumped mass (fem.inertia)"
        dynamics = {"scheme": scheme, "mass_g": bm.copies * bm.inertia.total_mass * TONNE_TO_G}
    summary = {
        "model": "fe-body",
        "converged": converged,
        "message": ended(run.message if crawl is None else crawl.message, max_wall_s),
        "pipe": {
            "kind": pipe,
            "diameter_mm": setup.pipe_diameter,
            "bend_radius_mm": bend_radius,
            "gravity_g": list(gravity) if gravity else None,
            "bend_start_mm": getattr(wall, "entry", None),
            "bend_turn_deg": turn_deg if pipe == "elbow" else None,  # azimuth from +x
            "corrugation_mm": [2 * wall.amplitude, wall.pitch] if pipe == "bellows" else None,  # depth, pitch
        },  # fmt: skip
        "mesh": summary_mesh(mesh),
        "wedge": bm.copies,  # 3: one wedge of 120 deg, tied by the three-fold symmetry (`wedge`)
        "schedule": {"name": first.name, "source": first.source, "cycle_s": T, "gait_plan": plan},
        "cycles": cycles,
        "steps": setup.steps,
        "friction": {
            "mu_smooth": setup.mu_smooth,
            "mu_grooved": setup.mu_grooved,
            "source": friction_source,
            "slip_viscosity_mpa_s_mm": setup.slip_viscosity,
        },  # fmt: skip
        "inertia": dynamics,
        "materials": bm.materials,
        "silicone_shear_modulus_mpa": float(silicone_law.mu),
        "feet_material_source": material_source(setup.material),
        "mass": mass,
        "rest_arc_mm": rest,
        "strides_mm": list(strides),
        "speeds_mm_s": [s / T for s in strides],
        "turns_deg": list(turns),
        "cycle_wall_s": cycle_s,
        "paper_speed_mm_s": paper,
        "paper_source": paper_source,
        "solver": {
            "dofs": bm.n_dofs,
            "newton_iterations": run.newton_iterations + spent.newton_iterations,
            "assembly_s": run.assembly_s + spent.assembly_s,
            "linear_s": run.solve_s + spent.solve_s,
            "wall_s": earlier + time.perf_counter() - t0,
            "factorizations": run.factorizations + spent.factorizations,
            # SuperLU where MKL's PARDISO cannot load: several times slower and larger on this body
            "linear_solver": solver,
            # this process's: the contact terms' assembly time and its share of the wall time
            "contact_s": contact_s,
            "contact_share": contact_s / (time.perf_counter() - t0),
            "resumed": resumed is not None,
            "peak_rss_gb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024**2,
        },
    }
    summary["text"] = summary_text(summary)
    write_summary(out / "summary.json", summary)
    if crawl is not None and crawl.states:
        plot_body(
            rows,
            rest,
            T,
            out / "crawl.png",
            f"FE body, {pipe} {setup.pipe_diameter:g} mm pipe, {first.source if plan else first.name}",
        )
    write_vtu(out / "vtu", bm, run, crawl, factor, T, precision)
    z = np.asarray(bm.model.nodes)[2]
    end = getattr(wall, "entry", 0.0) + getattr(wall, "bend_radius", 0.0) * getattr(wall, "bend_angle", 0.0)
    write_wall(out / "vtu" / "pipe.vtu", wall, float(z.min()) - 20.0, max(float(z.max()), end) + 100.0)
    if store is not None and not stopped(summary["message"]):
        store.clear()
    return converged, summary


def stopped(message: str) -> bool:
    """The run stopped at its time limit (`ended`): its checkpoints are kept to resume it."""
    return message.startswith("time limit of")
