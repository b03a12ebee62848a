r"""`softcrawl study skirt`: the squeezed skirt's stability against the mesh (`studies.skirt.model`).

For each mesh of the ladder (sectors around the axis x cells through the skirt) one point:
  1. the inserted state in the 60 mm pipe: directly (`model.insert`, the foot study's path) on
     source meshes (`model.source_sectors`) or those listed in `DIRECT`, else carried from the
     insertion on the source mesh with the same cells (`map_axisymmetric`) and settled by Newton;
     the carried, settled state is kept in DIR/.../states/ (not committed) so that a run stopped
     in step 2 resumes after the settle;
  2. its insertion force (N), unstable-mode count neg(K) - neg(K_pp), lowest eigenvalues and the
     lobe count of each unstable mode, and the closest approach of the skirt to itself. The count
     is taken on the whole tangent on the meshes of `FULL_COUNT` (the points committed before the
     cyclic counter existed), else one circumferential harmonic at a time (`fem.cyclic`, the same
     count: the state and the mesh are invariant under a sector rotation), which also gives the
     unstable count and the lowest eigenvalue per harmonic n = 0..N/2;
  3. on meshes in `SEEDED` with an unstable mode: the lowest mode seeded into the geometry
     (`SEED_MM`) and the insertion followed again: force, unstable count, the rim's wrinkle
     (half the spread of its deformed radius around a ring) and lobe count, and the gap.
Each point is written to DIR/skirt/MATERIAL[-quick]/points/S<sectors>-C<cells>.json when it is
done; a run again computes only the missing ones. skirt.csv gathers them (one row per mesh,
the seeded path's columns prefixed "seeded_"), with the wall time and the process's peak memory.
"""

from __future__ import annotations

import json
import resource
import time
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from softcrawl import jsonio
from softcrawl.analytic.pipe import Pipe
from softcrawl.fem.linsolve import release_factorisations
from softcrawl.fem.rigid_surfaces import CylinderWall
from softcrawl.geometry.design import FootDesign
from softcrawl.materials import get_material
from softcrawl.materials.fem_law import solid_law
from softcrawl.studies.declaration import StudyRequest
from softcrawl.studies.outcome import StudyOutcome
from softcrawl.studies.skirt import model as sm
from softcrawl.studies.sweeps.tables import write_csv

DEFAULT_MATERIAL = "rubber-70a"
PIPE_MM = 60.0
INSERT_STEPS = 8
#: (sectors, cells through the skirt): the foot study's default mesh first.
LADDER = ((48, 3), (24, 3), (96, 3), (96, 4), (128, 4), (96, 6), (128, 6))
QUICK_LADDER = ((24, 3), (48, 3))
#: Meshes inserted directly as well as the source ones: the default mesh, the check of the carried state.
DIRECT = ((48, 3),)
#: Meshes on which the lowest unstable mode is seeded and the insertion followed again.
SEEDED = ((48, 3),)
QUICK_SEEDED = ((48, 3),)
N_LOBES_REPORTED = 12  # unstable modes whose lobe count is listed
#: Meshes whose count is taken on the whole tangent (`fem.stability`); the others by harmonic.
FULL_COUNT = ((48, 3), (24, 3), (96, 3), (96, 4))


def _peak_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def point_name(sectors: int, cells: int) -> str:
    return f"S{sectors}-C{cells}"


def rim_wrinkle(model, x, reference) -> float:
    """Half the largest spread (mm) of the deformed radius around a ring of rim nodes; rings
    are those of `reference`, the perfect foot's nodes (a seeded foot's own are perturbed)."""
    nodes = model.boundary_nodes("rim")
    X = reference[:, nodes]
    xd = model.nodes[:, nodes] + model.displacement(x)[:, nodes]
    key = np.round(np.column_stack([np.hypot(X[0], X[1]), X[2]]) / sm.TOL_MATCH).astype(np.int64)
    _, ring = np.unique(key, axis=0, return_inverse=True)
    r = np.hypot(xd[0], xd[1])
    return float(max(0.5 * np.ptp(r[ring.reshape(-1) == k]) for k in np.unique(ring)))


def describe_state(model, x, design, reference=None, cyclic_sectors: int | None = None) -> dict:
    """Force, stability and gap of an equilibrium (the module docstring's item 2); lobes and
    rings are counted on `reference` (the perfect foot's nodes; default the model's own); the
    count by harmonic when `cyclic_sectors` is given (the mesh's sectors)."""
    reference = model.nodes if reference is None else reference
    t0 = time.perf_counter()
    release_factorisations()
    extra = {"counter": "whole tangent"}
    if cyclic_sectors:
        st, cs = sm.cyclic_state_stability(model, x, cyclic_sectors)
        extra = {
            "counter": "by harmonic",
            "circulant_error": cs.circulant_error,
            "unstable_by_harmonic": {str(h.n): h.n_unstable for h in cs.harmonics if h.n_unstable},
            "lowest_by_harmonic": [float(h.eigenvalues[0]) for h in cs.harmonics],
        }
    else:
        st = sm.state_stability(model, x)
    lobes = [int(np.argmax(sm.lobe_spectrum(reference, sm.mode_field(model, st.modes[:, i]))))
             for i in range(min(st.n_unstable, N_LOBES_REPORTED, st.modes.shape[1]))]  # fmt: skip
    lowest = sm.mode_field(model, st.modes[:, 0])
    where = int(np.argmax(np.linalg.norm(lowest, axis=0)))
    rho = float(np.hypot(*model.nodes[:2, where]))
    gap = sm.self_gap(model, x)
    return {
        "insertion_force_n": sm.normal_force(model, x),
        "n_unstable": st.n_unstable,
        "neg_tangent": st.tangent.negative,
        "neg_pressure_block": st.pressure_block.negative if st.pressure_block else 0,
        "perturbed_pivots": st.tangent.perturbed + (st.pressure_block.perturbed if st.pressure_block else 0),
        "lowest_eigenvalues": [float(v) for v in st.eigenvalues[: max(st.n_unstable + 2, 4)]],
        "lobes_lowest": lobes[0] if lobes else int(np.argmax(sm.lobe_spectrum(reference, lowest))),
        "lobes_unstable": lobes,
        "lowest_mode_rho_over_tip": rho / design.tip_radius,
        "lowest_mode_z_mm": float(model.nodes[2, where]),
        "rim_wrinkle_mm": rim_wrinkle(model, x, reference),
        "self_gap_mm": gap.gap,
        "self_gap_tags": "/".join(gap.tags),
        "gap_search_mm": sm.GAP_SEARCH_MM,
        "stability_s": time.perf_counter() - t0,
        "_mode": lowest,
    } | extra


def insert_source(cells: int, material, design, pipe, sources: dict, states=None):
    """The inserted state on the source mesh (`model.source_sectors`) with `cells` cells:
    (model, result), computed once per run (kept in `sources`) and, with `states`, kept on disk
    like the carried states (`carried_state`), so a later run starts from it."""
    if cells not in sources:
        sectors = sm.source_sectors(cells)
        model = sm.build_model(sm.foot_mesh(design, sectors, cells), material, design)
        if _is_kept(states, sectors, cells):
            sources[cells] = (model, _read_kept(kept_file(states, sectors, cells), model, pipe))
        else:
            t0 = time.perf_counter()
            res = sm.insert(model, design, pipe, INSERT_STEPS)
            out = Settled(bool(res.converged), res.message, int(res.newton_iterations), res.x)
            out = replace(out, wall_s=time.perf_counter() - t0, peak_rss_mb=_peak_mb())
            if states is not None and out.converged:
                keep_state(kept_file(states, sectors, cells), out, model)
            sources[cells] = (model, out)
    return sources[cells]


@dataclass(frozen=True)
class Settled:
    """A carried, settled state as `states/` keeps it (the fields of a StagedResult used here)."""

    converged: bool
    message: str
    newton_iterations: int
    x: np.ndarray | None
    wall_s: float = 0.0  # source insertion and settle (s)
    peak_rss_mb: float = 0.0  # of the process that settled it
    reused: bool = False  # read from states/, computed by an earlier run


def kept_file(states, sectors: int, cells: int) -> Path | None:
    """Where a carried, settled state is kept (None: states are not kept)."""
    return None if states is None else Path(states) / f"{point_name(sectors, cells)}.npz"


def _is_kept(states, sectors: int, cells: int) -> bool:
    file = kept_file(states, sectors, cells)
    return file is not None and file.exists()


def carried_state(sectors, cells, model, material, design, pipe, sources, states) -> Settled:
    """The inserted state of the source mesh carried to `model` and settled; read from
    `states`/S<sectors>-C<cells>.npz when an earlier run kept it, else computed and kept there.
    The contact terms are part of the state: the kept file holds their augmented-Lagrangian
    multipliers, and a state read back puts them and the pipe's wall into `model`'s contacts (a
    fresh model's wall is clear of the tip: no contact, no contact stiffness)."""
    file = kept_file(states, sectors, cells)
    if _is_kept(states, sectors, cells):
        return _read_kept(file, model, pipe)
    t0 = time.perf_counter()
    src_model, src = insert_source(cells, material, design, pipe, sources, states)
    if not src.converged:
        message = f"the {sm.source_sectors(cells)}-sector source did not converge: {src.message}"
        return Settled(False, message, 0, None)
    release_factorisations()
    res = sm.settle(model, pipe, sm.map_axisymmetric(src_model, src.x, model))
    wall = time.perf_counter() - t0
    out = Settled(bool(res.converged), res.message, int(res.newton_iterations), res.x, wall, _peak_mb())
    if file is not None and out.converged:
        keep_state(file, out, model)
    return out


def _read_kept(file, model, pipe) -> Settled:
    z = np.load(file)
    keys = ("converged", "message", "newton_iterations", "wall_s", "peak_rss_mb")
    for i, contact in enumerate(model.contacts):
        contact.set_surface(CylinderWall(pipe.radius))
        contact.multiplier = z[f"multiplier_{i}"]
    return Settled(**{k: z[k].item() for k in keys}, x=z["x"], reused=True)


def keep_state(file, state: Settled, model) -> None:
    """Write `state` and the multipliers of `model`'s contact terms to `file` (npz)."""
    Path(file).parent.mkdir(parents=True, exist_ok=True)
    keys = ("converged", "message", "newton_iterations", "x", "wall_s", "peak_rss_mb")
    multipliers = {f"multiplier_{i}": c.multiplier for i, c in enumerate(model.contacts)}
    np.savez(file, **{k: getattr(state, k) for k in keys}, **multipliers)


def run_point(
    sectors: int,
    cells: int,
    material,
    design,
    pipe,
    sources: dict,
    seeded: bool,
    direct: bool,
    progress=False,
    states=None,
) -> dict:
    t0 = time.perf_counter()
    if sectors == sm.source_sectors(cells):
        model, res = insert_source(cells, material, design, pipe, sources, states)
        mesh, path = model.mesh, "inserted"
    else:
        if not direct and not _is_kept(states, sectors, cells):
            insert_source(
                cells, material, design, pipe, sources, states
            )  # before the fine model: a lower peak
        mesh = sm.foot_mesh(design, sectors, cells)
        model = sm.build_model(mesh, material, design)
        if direct:
            res, path = sm.insert(model, design, pipe, INSERT_STEPS), "inserted"
        else:
            res = carried_state(sectors, cells, model, material, design, pipe, sources, states)
            path = f"carried from {sm.source_sectors(cells)} sectors, settled"
    row = {"sectors": sectors, "cells": cells, "n_dofs": int(model.n_dofs), "path": path}
    row |= {
        "converged": bool(res.converged),
        "message": res.message,
        "newton_iterations": res.newton_iterations,
    }
    if isinstance(res, Settled) and res.reused:
        row |= {
            "state_kept_from_earlier_run": True,
            "settle_wall_s": res.wall_s,
            "settle_peak_rss_mb": res.peak_rss_mb,
        }
    if not res.converged:
        return row | {"wall_s": time.perf_counter() - t0, "peak_rss_mb": _peak_mb()}
    x = res.x
    by_harmonic = (sectors, cells) not in FULL_COUNT
    info = describe_state(model, x, design, cyclic_sectors=sectors if by_harmonic else None)
    mode = info.pop("_mode")
    row |= info
    if progress:
        print(f"skirt: {point_name(sectors, cells)} inserted: {_line(row)}", flush=True)
    if seeded and row["n_unstable"] > 0:
        release_factorisations()
        imperfect = sm.build_model(sm.seeded_mesh(mesh, mode), material, design)
        path_rows = []

        def record(step):
            wall = design.tip_radius + 0.5 + step.s * (pipe.radius - design.tip_radius - 0.5)
            wrinkle = rim_wrinkle(imperfect, step.x, model.nodes)
            path_rows.append((float(wall), sm.normal_force(imperfect, step.x), wrinkle))

        res2 = sm.insert(imperfect, design, pipe, INSERT_STEPS, on_step=record)
        row |= {"seeded_converged": bool(res2.converged), "seeded_message": res2.message}
        row["seeded_wall_radius_path_mm"] = [r[0] for r in path_rows]
        row["seeded_force_path_n"] = [r[1] for r in path_rows]
        row["seeded_rim_wrinkle_path_mm"] = [r[2] for r in path_rows]
        if res2.converged:
            more = describe_state(imperfect, res2.x, design, model.nodes)
            more.pop("_mode")
            row |= {f"seeded_{k}": v for k, v in more.items()}
    return row | {"wall_s": time.perf_counter() - t0, "peak_rss_mb": _peak_mb()}


def run_skirt(out, *, material=None, quick: bool = False, ladder=None, progress: bool = True) -> StudyOutcome:
    material = material or DEFAULT_MATERIAL
    folder = Path(out) / "skirt" / (material + ("-quick" if quick else ""))
    (folder / "points").mkdir(parents=True, exist_ok=True)
    full = QUICK_LADDER if quick else LADDER
    ladder = tuple(ladder or full)  # a subset computes only those (two processes share a run)
    seeded = QUICK_SEEDED if quick else SEEDED
    spec = {"study": "skirt", "material": material, "pipe_mm": PIPE_MM, "ladder": [list(m) for m in full],
            "direct": [list(m) for m in DIRECT], "seeded": [list(m) for m in seeded], "seed_mm": sm.SEED_MM,
            "insert_steps": INSERT_STEPS}  # fmt: skip
    jsonio.write(folder / "spec.json", spec)
    design, pipe = FootDesign(), Pipe(diameter=PIPE_MM)
    law = solid_law(get_material(material), hyperelastic_only=True)
    sources: dict = {}
    for s, c in ladder:
        path = folder / "points" / f"{point_name(s, c)}.json"
        if path.exists():
            continue
        if progress:
            print(f"skirt: {s} sectors x {c} cells ...", flush=True)
        row = run_point(
            s, c, law, design, pipe, sources, (s, c) in seeded, (s, c) in DIRECT, progress, folder / "states"
        )
        jsonio.write(path, row)
        write_outputs(folder, full)
        if progress:
            print(f"skirt: {point_name(s, c)}: {_line(row)}", flush=True)
    return write_outputs(folder, full)


def _gap(value, radius=sm.GAP_SEARCH_MM) -> str:
    """A gap in mm; None (JSON's inf) is beyond the search radius."""
    return f"> {radius:g} mm" if value is None or value == float("inf") else f"{value:.3g} mm"


def _line(r: dict) -> str:
    if not r.get("converged"):
        return f"not converged: {r.get('message', '')}"
    if r.get("lowest_eigenvalues") is None:
        return f"{r['n_dofs']} dofs, force {r['insertion_force_n']:.2f} N (stability not computed)"
    text = (
        f"{r['n_dofs']} dofs, force {r['insertion_force_n']:.2f} N, {r['n_unstable']} unstable modes, "
        f"lowest {r['lowest_eigenvalues'][0]:.3g} N/mm with {r['lobes_lowest']} lobes, "
        f"gap {_gap(r['self_gap_mm'], r.get('gap_search_mm'))}"
    )
    if "seeded_converged" in r:
        text += f"; seeded: {'converged' if r['seeded_converged'] else 'stopped'}"
        if r["seeded_converged"]:
            text += (
                f", force {r['seeded_insertion_force_n']:.2f} N, {r['seeded_n_unstable']} unstable, "
                f"rim wrinkle {r.get('seeded_rim_wrinkle_mm', float('nan')):.3g} mm, "
                f"lobes {r.get('seeded_lobes_lowest', '-')}, "
                f"gap {_gap(r['seeded_self_gap_mm'], r.get('gap_search_mm'))}"
            )
    return text


def write_outputs(folder: Path, ladder) -> StudyOutcome:
    rows, lines = [], []
    for s, c in ladder:
        path = folder / "points" / f"{point_name(s, c)}.json"
        if not path.exists():
            lines.append(f"{point_name(s, c)}: not computed")
            continue
        r = json.loads(path.read_text())
        rows.append({k: (";".join(map(str, v)) if isinstance(v, list) else v) for k, v in r.items()})
        lines.append(f"{point_name(s, c)}: {_line(r)}")
    written = [write_csv(rows, folder / "skirt.csv")]
    failed = tuple(
        f"{r['sectors']} x {r['cells']}: {r.get('message', '')}" for r in rows if not r.get("converged")
    )
    missing = len(rows) < len(ladder)
    return StudyOutcome(tuple(lines), tuple(written), not failed and not missing, failed)


def run_request(request: StudyRequest) -> StudyOutcome:
    """`softcrawl study skirt` (the registry's entry point)."""
    return run_skirt(request.out, material=request.material, quick=request.quick, progress=request.progress)
