"""`softcrawl epsa` and `softcrawl verify` end to end on tiny problems; the swept ePSA mesh."""

import csv
import json

import numpy as np
import pytest

from softcrawl.geometry.design import EPSADesign
from softcrawl.geometry.swept import mesh_epsa_swept
from softcrawl.studies.cli import main


def test_swept_mesh_volume_tags_and_orientation():
    d = EPSADesign()
    m = mesh_epsa_swept(d)
    assert set(m.facets) == {"chamber_wall", "chamber_ends", "outer", "end_bottom", "end_top"}
    assert all(len(f) for f in m.facets.values())
    v = m.points[m.tets]
    det = np.einsum("ij,ij->i", np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0]), v[:, 3] - v[:, 0])
    assert det.min() > 0
    import skfem

    m2 = m.to_skfem(order=2)
    exact = skfem.Basis(m2, skfem.ElementTetP2()).dx.sum()  # curved P2 geometry
    assert exact == pytest.approx(d.body_volume, rel=1e-3)
    assert m.area("chamber_wall") == pytest.approx(d.chamber_wall_area, rel=0.02)
    with_head = mesh_epsa_swept(d, seal_head=True)
    assert set(with_head.region_names.values()) == {"epsa", "seal_head"}
    assert with_head.volume("seal_head") == pytest.approx(np.pi * 81 * d.seal_head_thickness, rel=0.03)


def test_epsa_command_writes_curve_summary_vtu_and_plot(tmp_path, capsys):
    out = tmp_path / "run"
    code = main(
        [
            "epsa",
            "--length",
            "40",
            "--fiber-turns",
            "8",
            "--quick",
            "--pressures",
            "0:10:5",
            "--out",
            str(out),
        ]
    )
    assert code == 0
    rows = list(csv.DictReader(open(out / "curve.csv")))
    assert [r["status"] for r in rows] == ["reference", "converged", "converged"]
    assert [float(r["pressure_kPa"]) for r in rows] == [0.0, 5.0, 10.0]
    lengths = [float(r["length_mm"]) for r in rows]
    assert lengths[0] == pytest.approx(40.0) and lengths[2] > lengths[1] > lengths[0]
    summary = json.loads((out / "summary.json").read_text())
    assert summary["converged"] and summary["material"] == "ecoflex-00-50"
    assert (out / "vtu" / "step.pvd").exists() and (out / "epsa.png").stat().st_size > 10_000
    assert "P =   10.00 kPa" in capsys.readouterr().out


def test_epsa_blocked_force_grows_with_pressure(tmp_path):
    out = tmp_path / "blocked"
    assert (
        main(
            [
                "epsa",
                "--length",
                "40",
                "--fiber-turns",
                "8",
                "--quick",
                "--blocked",
                "--no-vtu",
                "--pressures",
                "5,10",
                "--out",
                str(out),
            ]
        )
        == 0
    )
    rows = list(csv.DictReader(open(out / "curve.csv")))
    force = [float(r["blocked_force_N"]) for r in rows]
    assert force[0] == pytest.approx(0.0, abs=1e-9)
    # at least the pressure on the chamber's end cap, P * pi r0^2, and growing
    assert force[2] > force[1] > 0.010 * np.pi * 9.0
    assert [float(r["length_mm"]) for r in rows] == pytest.approx([40.0] * 3, abs=1e-9)


@pytest.mark.parametrize(
    "argv, parameter",
    [
        (["epsa", "--chamber-radius", "9.5", "--out", "x-never-written"], "chamber_radius"),
        (["epsa", "--fiber-turns", "-1", "--out", "x-never-written"], "fiber_turns"),
        (["epsa", "--pressures", "100:0:20", "--out", "x-never-written"], "pressures"),
        (["epsa", "--material", "unobtainium", "--out", "x-never-written"], "material"),
        (["epsa", "--material", "abs", "--out", "x-never-written"], "material"),
    ],
)
def test_epsa_bad_input_is_one_line_and_exit_2(argv, parameter, capsys, tmp_path):
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and parameter in err[0]
    assert not (tmp_path / "x-never-written").exists()  # bad input writes nothing


def test_verify_command_writes_json(tmp_path):
    path = tmp_path / "verify.json"
    assert main(["verify", "--case", "patch", "--json", str(path)]) == 0
    data = json.loads(path.read_text())
    assert data["all_passed"] and data["cases"][0]["case"] == "patch"


def test_mesh_presets_are_points_of_the_size_family():
    """The convergence study over sizes contains the presets: quick = h 10 mm, default = h 5 mm."""
    from softcrawl.geometry.design import EPSADesign
    from softcrawl.studies.epsa.model import MESH_PRESETS, MeshSettings

    d = EPSADesign()
    assert MeshSettings.from_size(10.0, d) == MESH_PRESETS["quick"]
    assert MeshSettings.from_size(5.0, d) == MESH_PRESETS["default"]
    finer = MeshSettings.from_size(2.5, d)
    assert finer.n_around > 16 and finer.n_radial > 2 and finer.fiber_points_per_turn >= 2 * finer.n_around


def test_sway_of_the_free_end_is_reported():
    from softcrawl.studies.epsa.response import CurveRow, _sway_events

    def row(p, length, sway, status="converged"):
        return CurveRow(p, length, 9.0, 1.0, 1.0, 0.0, status, float("nan"), sway)

    calm = [row(0, 100, 0.0, "reference"), row(20, 110, 0.4), row(40, 140, 2.0)]
    assert _sway_events(calm) == ()
    bent = calm + [row(60, 190, 35.0)]
    (event,) = _sway_events(bent)
    assert "35 mm at P = 60 kPa" in event and "--guided" in event


def test_guided_top_stays_on_the_axis():
    from softcrawl.geometry.design import EPSADesign
    from softcrawl.studies.epsa.response import simulate_epsa

    free = simulate_epsa(EPSADesign(), quick=True, pressures_kpa=(20.0,), fibers="lines")
    guided = simulate_epsa(EPSADesign(), quick=True, pressures_kpa=(20.0,), guided=True, fibers="lines")
    assert free.converged and guided.converged
    assert free.rows[-1].tip_lateral_mm > 0.05  # the helix ends are not symmetric
    # the seal head's top is held; the body's top, 3 mm below it, only follows its small tilt
    assert guided.rows[-1].tip_lateral_mm < 0.05 * free.rows[-1].tip_lateral_mm
    # the guide holds the top sideways only: the extension barely changes at 20 kPa
    ext = [c.rows[-1].length_mm - c.rows[0].length_mm for c in (free, guided)]
    assert abs(ext[0] - ext[1]) < 0.02 * ext[0]


def test_side_load_probe_moves_the_free_top_and_is_checked():
    """The smeared winding is symmetric: without a probe the top stays near the axis (the swept
    mesh's triangulation leaves 0.007 mm at 20 kPa), with a small sideways force it moves, in
    proportion at low pressure."""
    import pytest

    from softcrawl.geometry.design import DesignError, EPSADesign
    from softcrawl.studies.epsa.response import simulate_epsa

    sway = [
        simulate_epsa(EPSADesign(), quick=True, pressures_kpa=(20.0,), side_load_n=f).rows[-1].tip_lateral_mm
        for f in (None, 1e-4, 2e-4)
    ]
    assert sway[0] < 0.2 * sway[1]
    assert sway[2] == pytest.approx(2 * sway[1], rel=0.1)  # the baseline adds a little
    for bad, name in (
        (dict(side_load_n=-1.0), "side_load"),
        (dict(side_load_n=1e-4, guided=True), "side_load"),
        (dict(fibers="braid"), "fibers"),
    ):
        with pytest.raises(DesignError) as err:
            simulate_epsa(EPSADesign(), quick=True, pressures_kpa=(20.0,), **bad)
        assert err.value.parameter == name
