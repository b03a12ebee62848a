"""Run one crawl and write its files (`softcrawl crawl`, `softcrawl study crawl`).

FOLDER/states.csv (one row per converged state, `studies.crawl.outputs`), cycles.csv (one
row per cycle), summary.json (strict JSON: setup, sources, the speeds beside Table 2 and the
analytic model, solver figures), crawl.png (foot positions and pressures against time),
vtu/crawl.pvd (one VTU per state, the time in s; the setup states at small negative times) with
the pipe wall in vtu/pipe.vtu as a second block of every time step (one file, referenced per step),
so that a reader shows pipe and feet together at every time. Each state's field data: time_s,
pressure_kPa (P1-P3), actuator_force_N, the feet's slip shares and friction forces; its point
data: the contact pressure and the slip state (`fem.vtu.contact_fields`). Float32 unless
``precision=64`` (decision 063).
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np

from softcrawl.fem.vtu import write_state
from softcrawl.materials import get_material
from softcrawl.materials.fem_law import solid_law
from softcrawl.paper import FRICTION_N, table2
from softcrawl.provenance import write_summary
from softcrawl.studies.crawl.insertion import insertion_cache_for
from softcrawl.studies.crawl.mesh import crawl_mesh
from softcrawl.studies.crawl.model import build, run_crawl
from softcrawl.studies.crawl.outputs import steady_stride
from softcrawl.studies.crawl.plot import plot_crawl
from softcrawl.studies.crawl.schedule import analytic_speed
from softcrawl.studies.sweeps.tables import write_csv

#: The feet's rubber by default (`CrawlSetup.material`).
MATERIAL = "rubber-70a"
MATERIAL_SOURCE = "Shore 70A rubber of the foot study (results/foot/README.md)"


def material_source(name: str) -> str:
    """Where the feet's rubber `name` comes from (summary.json's sources)."""
    return MATERIAL_SOURCE if name == MATERIAL else get_material(name).source


#: The friction's source when the caller gives the coefficients (the crawl study's grid, an option).
FRICTION_SOURCE = "given by the caller (dry rubber on a smooth pipe: 0.3-0.9); the paper gives no coefficient"


def write_pipe(path: Path, pipe, z0: float, z1: float, n: int = 96) -> Path:
    """The rigid wall of the straight `pipe` (`analytic.pipe.Pipe`) from z0 to z1 as a quad
    surface (meshio)."""
    import meshio

    radius = pipe.radius
    a = np.linspace(0.0, 2 * np.pi, n, endpoint=False)
    ring = np.column_stack([radius * np.cos(a), radius * np.sin(a)])
    pts = np.vstack([np.column_stack([ring, np.full(n, z)]) for z in (z0, z1)])
    k = np.arange(n)
    quads = np.column_stack([k, (k + 1) % n, n + (k + 1) % n, n + k])
    meshio.write(path, meshio.Mesh(pts, [("quad", quads)]))
    return path


#: State-row columns that go into each VTU's field data, under their VTU names.
ROW_FIELDS = {
    "time_s": "time_s",
    "actuator_force_n": "actuator_force_N",
    "rear_slip_share": "rear_slip_share",
    "front_slip_share": "front_slip_share",
    "rear_friction_n": "rear_friction_N",
    "front_friction_n": "front_friction_N",
}


class _VtuSeries:
    def __init__(self, folder: Path, rows=(), precision: int = 32) -> None:
        """The series in `folder`; `rows`: the states of a resumed run, whose VTU files are kept
        (a later one, written after the last checkpoint, is written again or removed)."""
        self.folder, self.precision = folder, precision
        self.entries = [(vtu_time(r), f"crawl_{r['index']:04d}.vtu") for r in rows]
        folder.mkdir(parents=True, exist_ok=True)
        for path in folder.glob("crawl_*.vtu"):
            if path.name not in {name for _, name in self.entries}:
                path.unlink(missing_ok=True)

    def __call__(self, index, model, x, time_s, row=None) -> None:
        fields = {}
        if row is not None:
            fields = {name: row[key] for key, name in ROW_FIELDS.items() if key in row}
            fields["pressure_kPa"] = [row.get(f"p{i}_kpa", 0.0) for i in (1, 2, 3)]
        fields["time_s"] = time_s  # the series time (setup states: small negative times)
        path = write_state(
            self.folder / f"crawl_{index:04d}.vtu",
            model,
            x,
            extra_field_data=fields,
            precision=self.precision,
        )
        self.entries.append((time_s, path.name))
        write_pvd(self.folder, self.entries)


def vtu_time(row: dict) -> float:
    """The time of a state in the series: the schedule's; the setup states (insertion, friction
    on) at small negative times, in order."""
    return row["time_s"] if row["cycle"] > 0 else (row["index"] - 1000) * 1e-3


def write_pvd(folder: Path, entries) -> Path:
    """folder/crawl.pvd: the states (time_s, VTU file name) in order, each time with the pipe as its
    part 1 (the same pipe.vtu at every time)."""
    from xml.sax.saxutils import quoteattr

    lines = ['<?xml version="1.0"?>', '<VTKFile type="Collection" version="0.1">', "<Collection>"]
    for t, f in entries:
        lines.append(f'<DataSet timestep="{t:.6g}" part="0" file={quoteattr(f)}/>')
        lines.append(f'<DataSet timestep="{t:.6g}" part="1" file="pipe.vtu"/>')
    lines += ["</Collection>", "</VTKFile>"]
    path = Path(folder) / "crawl.pvd"
    path.write_text("\n".join(lines) + "\n")
    return path


def compare(result, setup, schedule, pressure_kpa: float) -> dict:
    """Stride and speed beside Table 2 and the analytic model (with the paper's friction and with
    the FE's own: the largest axial friction force on a foot while the pressures rise)."""
    direction = "backward" if setup.feet == "backward" else "forward"
    stride = steady_stride(result)
    extend = [
        max(abs(s["rear_friction_n"]), abs(s["front_friction_n"]))
        for s in result.states
        if s["phase"] == "extend"
    ]
    fe_friction = max(extend, default=float("nan"))
    T = schedule.cycle_s
    return {
        "direction": direction,
        "stride_mm": stride,
        "speed_mm_s": stride / T,
        "cycle_s": T,
        "table2_mm_s": table2(setup.pipe_diameter, direction),
        "analytic_paper_friction_mm_s": analytic_speed(pressure_kpa, T, FRICTION_N[direction]),
        "paper_friction_n": FRICTION_N[direction],
        "fe_friction_n": fe_friction,
        "analytic_fe_friction_mm_s": analytic_speed(pressure_kpa, T, fe_friction)
        if np.isfinite(fe_friction)
        else float("nan"),
    }


def summary_text(result, setup, schedule, cmp: dict) -> str:
    lines = [
        f"crawl: {setup.pipe_diameter:g} mm pipe, {schedule.name} ({schedule.source}), feet {setup.feet}, "
        f"mu smooth {setup.mu_smooth:g} / grooved {setup.mu_grooved:g}, {result.n_dofs} DOFs"
        + (f" (a 1/{setup.copies} wedge of the feet, tied cyclically)" if setup.copies > 1 else "")
    ]
    for c in result.cycles:
        slid = ", ".join(
            f"{ph}: {'/'.join(f for f in ('rear', 'front') if c[f'{ph}_{f}_slid']) or 'none'} slid"
            for ph in ("extend", "retract")
        )
        lines.append(
            f"cycle {c['cycle']}: stride {c['stride_mm']:.3f} mm (rear {c['rear_advance_mm']:+.3f}, "
            f"front {c['front_advance_mm']:+.3f}), speed {c['speed_mm_s']:.3f} mm/s; {slid}"
        )
    if not result.cycles and result.states and result.states[-1]["cycle"] > 0:
        last = result.states[-1]
        moved = last["centre_u_mm"] - result.states[0]["centre_u_mm"]
        lines.append(
            f"no complete cycle: by the last converged state (t = {last['time_s']:.3f} s) the centre "
            f"advanced {moved:.3f} mm (rear {last['rear_u_mm']:+.3f}, front {last['front_u_mm']:+.3f} mm)"
        )
    t2 = cmp["table2_mm_s"]
    lines.append(
        f"speed {cmp['speed_mm_s']:.3f} mm/s ({cmp['direction']}, {cmp['cycle_s']:g} s cycles); Table 2: "
        f"{'n/a' if t2 is None else f'{t2:g} mm/s'}; analytic crawl_speed: "
        f"{cmp['analytic_paper_friction_mm_s']:.2f} mm/s with the paper's {cmp['paper_friction_n']:g} N, "
        f"{cmp['analytic_fe_friction_mm_s']:.2f} mm/s with the FE's {cmp['fe_friction_n']:.2f} N"
    )
    lines.append(
        f"ground springs at most {result.ground_max_n:.3g} N against {result.friction_max_n:.3g} N "
        f"of friction; "
        f"momentum balance at most {result.momentum_max_n:.3g} N"
    )
    lines.append(
        f"{result.message}; {result.increments} states, {result.newton_iterations} Newton iterations, "
        f"{result.wall_s:.0f} s"
    )
    return "\n".join(lines)


def progress_line(row: dict) -> str:
    return (
        f"  {row['stage']:>16s} t = {row['time_s']:6.3f} s: F = {row['actuator_force_n']:7.3f} N, "
        f"rear {row['rear_u_mm']:+8.3f} mm, front {row['front_u_mm']:+8.3f} mm, friction "
        f"{row['rear_friction_n']:+7.2f} / {row['front_friction_n']:+7.2f} N, slip "
        f"{row['rear_slip_share']:.2f} / {row['front_slip_share']:.2f}, {row['newton']} Newton"
    )


def run_and_write(
    setup,
    schedule,
    folder: Path,
    quick: bool = False,
    vtu: bool = True,
    progress=None,
    store=None,
    resumed=None,
    precision: int = 32,
    insertion_cache=False,
    friction_source: str = FRICTION_SOURCE,
):
    """Mesh, build, run and write (module docstring); returns (CrawlResult, summary dict).
    `progress(line)` is called with one line per converged state. `store` (`resume.CrawlStore`):
    each converged state is written to it, and it is cleared once the files are written;
    `resumed` (its `load()`): the run continues from that state; `precision`: the VTU floats;
    `insertion_cache`: True (the default folder) or a folder: the insertion is taken from
    (or written to) the cache of inserted states (`studies.crawl.insertion`); False: computed;
    `friction_source`: where the setup's mu come from, for summary.json."""
    folder.mkdir(parents=True, exist_ok=True)
    design, mesh = crawl_mesh(setup.mirrored, foot=setup.foot, **setup.mesh_options())
    law = solid_law(get_material(setup.material), hyperelastic_only=True)
    cm = build(mesh, law, design, setup)
    insertion = insertion_cache_for(insertion_cache, cm, mesh, design, law)
    series = None
    if vtu:
        series = _VtuSeries(folder / "vtu", resumed.rows if resumed is not None else (), precision)
        z = mesh.p[2]
        write_pipe(series.folder / "pipe.vtu", setup.pipe, float(z.min()) - 20, float(z.max()) + 80)

    def on_state(row, model, x):
        if series is not None:  # setup states (insertion, friction on) at negative times, in order
            series(row["index"], model, x, vtu_time(row), row)
        if progress is not None:
            progress(progress_line(row))

    result = run_crawl(cm, schedule, on_state=on_state, store=store, resumed=resumed, insertion=insertion)
    pressure = float(np.max(schedule.pressures_kpa))
    cmp = compare(result, setup, schedule, pressure)
    text = summary_text(result, setup, schedule, cmp)
    write_csv(list(result.states), folder / "states.csv")
    if result.cycles:
        write_csv(list(result.cycles), folder / "cycles.csv")
    fields = {k: v for k, v in dataclasses.asdict(result).items() if k not in ("states", "cycles")}
    summary = {
        "setup": dataclasses.asdict(setup),
        "quick": quick,
        "schedule": {"name": schedule.name, "source": schedule.source, "cycle_s": schedule.cycle_s},
        "sources": {
            "axial_law": cm.law.source,
            "material": material_source(setup.material),
            "friction": friction_source,
        },
        "comparison": cmp,
        "strides_mm": result.strides,
        "cycles": list(result.cycles),
        "text": text,
        "insertion_cached": bool(insertion is not None and insertion.hit),
    } | fields
    write_summary(folder / "summary.json", summary, indent=1)
    if result.states:
        plot_crawl(list(result.states), folder / "crawl.png", text.splitlines()[0])
    if store is not None:
        store.clear()
    return result, summary
