"""The crawl's GIF (`studies.crawl.animation`) on a tiny hand-made VTU series.

Two quadratic-tetra blocks ("rear" and "front" foot) in a pipe drawn by `crawl_files.write_pipe`,
listed in crawl.pvd by `crawl_files.write_pvd` as `softcrawl crawl` writes them; the front block
moves +6 mm along the axis over three states, the rear one stays. The GIF must hold one frame per
state, show no displaced (red) material in the first frame, and show the front block red and
further right (forward) in the last frame than any material was in the first frame.
"""

import meshio
import numpy as np
import pytest
from PIL import Image

from softcrawl.analytic.pipe import Pipe
from softcrawl.studies.crawl.files import write_pipe, write_pvd

pv = pytest.importorskip("pyvista")

VTK_TET10_EDGES = ((0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3))


@pytest.fixture(scope="module")
def offscreen():
    from softcrawl.studies.plots.render3d import pyvista_offscreen

    try:
        pvo = pyvista_offscreen()
        pl = pvo.Plotter(off_screen=True, window_size=(64, 48))
        pl.add_mesh(pvo.Sphere())
        image = pl.screenshot(return_img=True)
        pl.close()
    except Exception as exc:  # noqa: BLE001 - no EGL / OSMesa / X: nothing to test here
        pytest.skip(f"off-screen rendering unavailable: {exc}")
    if image is None or np.asarray(image).std() == 0:
        pytest.skip("off-screen rendering unavailable: blank screenshot")


def _tetra10_block(z0: float) -> tuple[np.ndarray, np.ndarray]:
    """A 16 x 16 x 10 mm block (x, y centred on the axis, z from z0) as quadratic tets."""
    grid = pv.ImageData(dimensions=(3, 3, 3), spacing=(8.0, 8.0, 5.0), origin=(-8.0, -8.0, z0))
    tets = grid.triangulate()
    corners = np.asarray(tets.points)
    cells = tets.cells_dict[pv.CellType.TETRA]
    points, out = [], []
    for cell in cells:
        p = corners[cell]
        mids = [(p[a] + p[b]) / 2 for a, b in VTK_TET10_EDGES]
        out.append(np.arange(len(points), len(points) + 10))
        points.extend(list(p) + mids)
    return np.array(points), np.array(out)


def _series(folder, shifts):
    rear, rear_cells = _tetra10_block(-20.0)
    front, front_cells = _tetra10_block(10.0)
    points = np.vstack([rear, front])
    cells = np.vstack([rear_cells, front_cells + len(rear)])
    is_front = np.arange(len(points)) >= len(rear)
    entries = []
    for k, shift in enumerate(shifts):
        u = np.zeros_like(points)
        u[is_front, 2] = shift
        name = f"crawl_{k:04d}.vtu"
        meshio.write(
            folder / name, meshio.Mesh(points, [("tetra10", cells)], point_data={"displacement_mm": u})
        )
        entries.append((0.5 * k, name))
    write_pipe(folder / "pipe.vtu", Pipe(diameter=28.0), -30.0, 40.0)
    write_pvd(folder, entries)


def _frames(path):
    with Image.open(path) as gif:
        frames = []
        for k in range(gif.n_frames):
            gif.seek(k)
            frames.append(np.asarray(gif.convert("RGB"), dtype=int))
    return frames


def _columns(frame, colour):
    """Columns of the red or blue pixels above the scalar bar (the picture's bottom fifth)."""
    frame = frame[: int(0.78 * frame.shape[0])]
    r, g, b = frame[..., 0], frame[..., 1], frame[..., 2]
    mask = (r - b > 60) & (r - g > 60) if colour == "red" else (b - r > 60) & (b - g > 40)
    return np.nonzero(mask)[1]


def test_the_gif_has_one_frame_per_state_and_shows_the_front_foot_moving_forward(tmp_path, offscreen):
    from softcrawl.studies.crawl.animation import write_crawl_gif

    vtu = tmp_path / "vtu"
    vtu.mkdir()
    _series(vtu, (0.0, 3.0, 6.0))
    path = write_crawl_gif(vtu, tmp_path / "crawl.gif")
    frames = _frames(path)
    assert len(frames) == 3
    first, last = frames[0], frames[-1]
    assert _columns(first, "red").size == 0  # nothing has moved yet: all at the low end (blue)
    blue0 = _columns(first, "blue")
    red = _columns(last, "red")
    assert blue0.size > 100 and red.size > 100
    # forward (+z) is to the right; the front block moved 6 mm of a ~70 mm wide view
    assert red.max() > blue0.max() + 20
    assert red.mean() > _columns(last, "blue").mean()  # the moved front foot is ahead of the rear


def test_a_series_without_states_is_a_clear_error(tmp_path, offscreen):
    from softcrawl.studies.crawl.animation import write_crawl_gif

    write_pvd(tmp_path, [])
    with pytest.raises(ValueError, match="lists no state"):
        write_crawl_gif(tmp_path, tmp_path / "crawl.gif")


def test_crawl_refuses_an_animation_that_is_not_a_gif_before_running(tmp_path, capsys):
    from softcrawl.studies.cli import main

    out = tmp_path / "crawl"
    assert main(["crawl", "--animation", str(tmp_path / "crawl.mp4"), "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "animation" in err[0] and ".gif" in err[0]
    assert not out.exists()  # refused before the mesh or any solve
