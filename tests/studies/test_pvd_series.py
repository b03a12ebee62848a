"""Every VTU series read as ParaView reads it, with pyvista's PVDReader at every time: times that
increase, every block present at every time, the load in the field data (decision 063).
The ePSA and the robot on their quickest settings; the crawl (one cycle, quick feet) is slow."""

from __future__ import annotations

import numpy as np
import pytest

pv = pytest.importorskip("pyvista")


def read_series(pvd, n_blocks: int) -> list[tuple[float, object]]:
    """(time, MultiBlock) at every time of the series; asserts the times increase and that every
    time holds `n_blocks` non-empty blocks."""
    reader = pv.PVDReader(str(pvd))
    times = list(reader.time_values)
    assert times and all(b > a for a, b in zip(times, times[1:])), times
    out = []
    for t in times:
        reader.set_active_time_value(t)
        data = reader.read()
        assert data.n_blocks == n_blocks, (t, data.n_blocks)
        for block in data:
            assert block is not None and block.n_points > 0, t
        out.append((t, data))
    return out


def test_epsa_series_runs_on_the_path_parameter(tmp_path):
    from softcrawl.fem.vtu import write_path
    from softcrawl.geometry.design import EPSADesign
    from softcrawl.studies.epsa.response import simulate_epsa

    solved = simulate_epsa(EPSADesign(length=40.0, fiber_turns=8), quick=True, pressures_kpa=(5.0, 10.0),
                           keep_model=True)  # fmt: skip
    write_path(tmp_path, solved.model, solved.path)
    for name in ("step.pvd", "winding.pvd"):
        series = read_series(tmp_path / name, 1)
        assert [t for t, _ in series] == pytest.approx([0.0, 5.0, 10.0])
        for t, data in series:
            fields = data[0].field_data
            assert fields["pressure_kPa"][0] == pytest.approx(t) and "load_factor" in fields
    winding = read_series(tmp_path / "winding.pvd", 1)[-1][1][0]
    assert {"fiber_tension_family1_N", "fiber_tension_family2_N"} <= set(winding.cell_data)


def test_robot_series_runs_on_the_path_parameter(tmp_path):
    from softcrawl.studies.cli import main

    code = main(["robot", "--pressures", "10,4,6", "--steps", "2", "--mesh", "quick", "--out", str(tmp_path)])
    assert code == 0
    series = read_series(tmp_path / "vtu" / "robot.pvd", 1)
    for t, data in series:
        fields = data[0].field_data
        assert fields["path_parameter"][0] == pytest.approx(t)
        assert len(fields["pressure_kPa"]) == 3 and "load_factor" in fields
    assert series[-1][1][0].field_data["pressure_kPa"] == pytest.approx([10.0, 4.0, 6.0])


@pytest.mark.slow
def test_crawl_series_has_the_pipe_and_the_feet_at_every_time(tmp_path):
    from softcrawl.studies.cli import main

    assert main(["crawl", "--quick", "--cycles", "1", "--out", str(tmp_path)]) == 0
    series = read_series(tmp_path / "vtu" / "crawl.pvd", 2)
    peak = 0.0
    for t, data in series:
        feet = data[0]
        for key in ("time_s", "pressure_kPa", "actuator_force_N", "rear_slip_share", "front_slip_share"):
            assert key in feet.field_data, (t, key)
        assert feet.field_data["time_s"][0] == pytest.approx(t, abs=1e-6)
        assert {"contact_pressure_MPa", "slip"} <= set(feet.point_data)
        assert feet.point_data["displacement_mm"].dtype == np.float32
        peak = max(peak, float(np.max(feet.field_data["pressure_kPa"])))
    assert peak > 0.0  # the pressures are the schedule's, not 0
