"""Tetrahedral meshing with pytetwild, tagging after meshing, and a disk cache.

``mesh_epsa``, ``mesh_seal_head``, ``mesh_foot`` and ``mesh_ring`` return a
:class:`geometry.tagged_mesh.TaggedMesh`.

Pipeline per part: closed surface (``geometry.epsa_shape``/``foot``/``ring``) -> pytetwild at the target edge
length -> tets reoriented positively, unused nodes dropped -> boundary facets classified against the
part's exact surfaces (``geometry.tagging``) with tolerance ``tol = 2 eps diag + sagitta`` (fTetWild
keeps the boundary within eps * diag of the input surface, eps = 1e-3, diag = bounding box diagonal;
the input polygon lies within the sagitta R (1 - cos(pi / n_theta)) of the exact one) -> tagged vertices
projected onto the exact surfaces.

Default edge length: 5 % of the part's bounding-box diagonal (pytetwild's default; 5.2 mm for the
Table 1 ePSA: about 14k tets). fTetWild refines the surface further to stay within its envelope.

Cache. pytetwild is not reproducible (the tet count changes between identical calls), so every mesh
is stored as npz under ``cache_dir`` (default ``$SOFTCRAWL_CACHE`` or ``~/.cache/softcrawl/meshes``)
keyed by the part kind, the design hash and the mesh settings; a cached mesh is returned as is.
"""

from __future__ import annotations

import hashlib
import json
import logging
import os
import time
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Literal

import numpy as np

from softcrawl.geometry.design import DesignError, EPSADesign, FootDesign, RingDesign
from softcrawl.geometry.epsa_shape import (
    DEFAULT_N_THETA,
    epsa_segments,
    epsa_surface,
    fiber_helices,
    seal_head_segments,
    seal_head_surface,
)
from softcrawl.geometry.foot import FOOT_N_THETA, foot_segments, foot_surface
from softcrawl.geometry.ring import ring_segments, ring_surface
from softcrawl.geometry.tagged_mesh import TaggedMesh
from softcrawl.geometry.tagging import (
    RevolvedSegment,
    boundary_facets,
    classify_facets,
    curved_surface_meta,
    snap_to_surfaces,
    tet_volumes,
)

if TYPE_CHECKING:
    import pyvista as pv

#: Where meshes are cached: a folder, None for `default_cache_dir()`, False for no cache.
CacheDir = str | Path | Literal[False] | None

log = logging.getLogger(__name__)

#: Bumped whenever the meshing pipeline changes what it produces (invalidates the cache).
MESH_VERSION = 1
#: fTetWild envelope, relative to the bounding-box diagonal.
EPSILON = 1e-3
#: Default target edge length as a fraction of the bounding-box diagonal.
EDGE_LENGTH_FAC = 0.05
#: Range of the target edge length (mm): from the smallest design feature (0.01 mm) to the largest
#: part size. Which edge lengths are affordable depends on the part: see MAX_TETWILD_TETS.
MIN_EDGE_LENGTH, MAX_EDGE_LENGTH = 0.01, 1000.0
#: Most tetrahedra a pytetwild mesh may have, estimated before meshing as the part volume over the
#: volume of a regular tet of the target edge, 6 sqrt(2) V / a^3 (fTetWild adds more where the
#: surface is curved, up to ~10x at coarse sizes). 1e6 tets is ~5M P2 unknowns, beyond what the
#: solver can factorise on a laptop; --edge-length 1e-6 asked for ~1e23 and ran without end.
MAX_TETWILD_TETS = 1_000_000


def default_cache_dir() -> Path:
    env = os.environ.get("SOFTCRAWL_CACHE")
    return Path(env) if env else Path.home() / ".cache" / "softcrawl" / "meshes"


def _cache_path(cache_dir: CacheDir, kind: str, design_hash: str, settings: dict) -> Path | None:
    if cache_dir is False:
        return None
    cache_dir = Path(cache_dir) if cache_dir is not None else default_cache_dir()
    key = hashlib.sha256(json.dumps({"v": MESH_VERSION, **settings}, sort_keys=True).encode()).hexdigest()[
        :10
    ]
    return cache_dir / f"{kind}-{design_hash}-{key}.npz"


def _diag(surface: pv.PolyData) -> float:
    b = np.asarray(surface.bounds, dtype=float).reshape(3, 2)
    return float(np.linalg.norm(b[:, 1] - b[:, 0]))


def tetrahedralize(
    surface: pv.PolyData, edge_length: float, epsilon: float = EPSILON
) -> tuple[np.ndarray, np.ndarray]:
    """pytetwild on a closed surface -> (points, positively oriented tets), unused points removed."""
    import pytetwild

    started = time.time()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        grid = pytetwild.tetrahedralize_pv(
            surface.triangulate(), edge_length_abs=float(edge_length), epsilon=epsilon, quiet=True
        )
    # fTetWild leaves its tracked surface "__tracked_surface.stl" in the working directory: remove ours
    stray = Path.cwd() / "__tracked_surface.stl"
    if stray.exists() and stray.stat().st_mtime >= started - 1:
        stray.unlink(missing_ok=True)
    tets = np.array(grid.cells.reshape(-1, 5)[:, 1:], dtype=np.int64)
    points = np.array(grid.points, dtype=float)
    vol = tet_volumes(points, tets)
    flip = vol < 0
    tets[flip] = tets[flip][:, [0, 2, 1, 3]]
    tets = tets[np.abs(vol) > 0]
    used, inverse = np.unique(tets, return_inverse=True)
    return points[used], inverse.reshape(tets.shape).astype(np.int64)


def tag_boundary(
    points: np.ndarray,
    tets: np.ndarray,
    segments: list[RevolvedSegment],
    tol: float,
    snap: bool = True,
    tris: np.ndarray | None = None,
) -> tuple[np.ndarray, dict[str, np.ndarray], int]:
    """Tag the boundary facets (or `tris`, some of them); returns (points, facets by tag, number of
    untagged facets).

    Untagged facets (none expected) are given the tag of the nearest surface regardless of the normal
    and counted, so that a test can insist on zero.
    """
    if tris is None:
        tris, _ = boundary_facets(tets)
    idx = classify_facets(points, tris, segments, tol)
    n_untagged = int(np.count_nonzero(idx < 0))
    if n_untagged:
        rest = np.nonzero(idx < 0)[0]
        dists = np.array(
            [np.max([s.closest(points[tris[rest, k]])[1] for k in range(3)], axis=0) for s in segments]
        )
        idx[rest] = np.argmin(dists, axis=0)
        log.warning("%d boundary facets matched no surface within tol %.3g; nearest used", n_untagged, tol)
    facets: dict[str, np.ndarray] = {}
    by_tag: dict[str, list[RevolvedSegment]] = {}
    for _i, seg in enumerate(segments):
        by_tag.setdefault(seg.tag, []).append(seg)
    for tag in by_tag:
        members = [i for i, s in enumerate(segments) if s.tag == tag]
        facets[tag] = tris[np.isin(idx, members)].astype(np.int64)
    if snap:
        points, _ = snap_to_surfaces(points, tets, facets, by_tag, max_move=tol)
    return points, facets, n_untagged


def mesh_part(
    kind: str,
    surface_fn: Callable[[], pv.PolyData],
    segments: list[RevolvedSegment],
    design_hash: str,
    region_name: str,
    edge_length: float | None,
    cache_dir: CacheDir,
    n_theta: int,
    sagitta: float,
    fibers: tuple = (),
) -> TaggedMesh:
    """Mesh one part (surface built lazily by ``surface_fn()``), tag it and cache it."""
    surface = None
    if edge_length is None:
        surface = surface_fn()
        edge_length = round(EDGE_LENGTH_FAC * _diag(surface), 6)
    settings = {"kind": kind, "edge_length": float(edge_length), "n_theta": n_theta, "epsilon": EPSILON}
    path = _cache_path(cache_dir, kind, design_hash, settings)
    if path is not None and path.exists():
        return TaggedMesh.load_npz(path)
    if surface is None:
        surface = surface_fn()
    estimate = 6 * 2**0.5 * abs(float(surface.volume)) / float(edge_length) ** 3
    if not estimate <= MAX_TETWILD_TETS:
        raise DesignError(
            "edge_length",
            f"{edge_length:g} mm on the {kind} ({abs(surface.volume):.4g} mm^3) gives ~{estimate:.3g} "
            f"tetrahedra; at most {MAX_TETWILD_TETS}: use a larger edge length",
        )
    log.info(
        "meshing the %s with pytetwild: edge %.3g mm, ~%.3g tetrahedra (up to a minute)",
        kind,
        float(edge_length),
        estimate,
    )
    tol = 2 * EPSILON * _diag(surface) + sagitta
    t0 = time.perf_counter()
    points, tets = tetrahedralize(surface, edge_length)
    t_mesh = time.perf_counter() - t0
    points, facets, n_untagged = tag_boundary(points, tets, segments, tol)
    mesh = TaggedMesh(
        points,
        tets,
        np.ones(len(tets), dtype=int),
        {1: region_name},
        facets,
        tuple(fibers),
        design_hash,
        float(edge_length),
        {
            "kind": kind,
            "tag_tolerance_mm": tol,
            "n_untagged_facets": n_untagged,
            "mesh_seconds": round(t_mesh, 2),
            "n_theta": n_theta,
            "curved_surfaces": curved_surface_meta(segments),
        },
    )
    if path is not None:
        path.parent.mkdir(parents=True, exist_ok=True)
        mesh.save_npz(path)
    return mesh


def mesh_epsa(
    design: EPSADesign | None = None,
    edge_length: float | None = None,
    cache_dir: CacheDir = None,
    n_theta: int = DEFAULT_N_THETA,
) -> TaggedMesh:
    """Tetrahedral mesh of the ePSA body (region ``epsa``) with its five tags and the two fibers."""
    design = design or EPSADesign()
    sagitta = design.outer_radius * (1 - np.cos(np.pi / n_theta))
    return mesh_part(
        "epsa",
        lambda: epsa_surface(design, n_theta),
        epsa_segments(design),
        design.short_hash(),
        "epsa",
        edge_length,
        cache_dir,
        n_theta,
        sagitta,
        fiber_helices(design),
    )


def mesh_seal_head(
    design: EPSADesign | None = None,
    edge_length: float | None = None,
    cache_dir: CacheDir = None,
    n_theta: int = DEFAULT_N_THETA,
) -> TaggedMesh:
    """The ABS seal head disk of an ePSA, z in [L, L + t_s] (region ``seal_head``)."""

    design = design or EPSADesign()
    sagitta = design.outer_radius * (1 - np.cos(np.pi / n_theta))
    return mesh_part(
        "seal_head",
        lambda: seal_head_surface(design, n_theta),
        seal_head_segments(design),
        design.short_hash(),
        "seal_head",
        edge_length,
        cache_dir,
        n_theta,
        sagitta,
    )


def mesh_foot(
    design: FootDesign | None = None,
    edge_length: float | None = None,
    cache_dir: CacheDir = None,
    n_theta: int | None = None,
) -> TaggedMesh:
    """The grooved flexible foot (region ``foot``), hub top face at z = 0, see ``geometry.foot``."""
    design = design or FootDesign()
    n_theta = n_theta or FOOT_N_THETA
    sagitta = design.tip_radius * (1 - np.cos(np.pi / n_theta))
    return mesh_part(
        "foot",
        lambda: foot_surface(design, n_theta),
        foot_segments(design),
        design.short_hash(),
        "foot",
        edge_length,
        cache_dir,
        n_theta,
        sagitta,
    )


def mesh_ring(
    design: RingDesign | None = None, edge_length: float | None = None, cache_dir: CacheDir = None
) -> TaggedMesh:
    """The connecting ring (region ``ring``), z in [-t/2, t/2], see ``geometry.ring``."""
    design = design or RingDesign()
    surface = ring_surface(design)
    # input polygon sagitta on the largest circle for the chosen spacing
    spacing = float(np.max(np.linalg.norm(np.diff(np.asarray(surface.points)[:8, :2], axis=0), axis=1)))
    sagitta = spacing**2 / (8 * design.hole_radius)
    return mesh_part(
        "ring",
        lambda: surface,
        ring_segments(design),
        design.short_hash(),
        "ring",
        edge_length,
        cache_dir,
        0,
        sagitta,
    )
