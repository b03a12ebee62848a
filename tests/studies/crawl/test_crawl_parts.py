"""The crawl's parts that run fast: schedules, the axial law, the two-feet mesh and model."""

import numpy as np
import pytest

from softcrawl.analytic.pipe import Pipe
from softcrawl.paper import table2
from softcrawl.studies.crawl.mesh import attach_tag, two_feet
from softcrawl.studies.crawl.schedule import AxialLaw, ScheduleError, preset, read_csv


def test_presets_follow_the_stated_valve_timings():
    s = preset("inflate", 80.0, 3.0)
    assert s.cycle_s == 3.0 and np.allclose(s.pressures_kpa[1], 80.0) and np.allclose(s.pressures_kpa[-1], 0)
    g1 = preset("gait1")
    assert g1.cycle_s == pytest.approx(3.5)
    assert np.allclose(g1.pressures_kpa[1], 100.0)
    g2 = preset("gait2")  # ePSA 1 filled for 0.3 s of 1.5: 20 kPa; a 0.2 s release of 0.5 loses 40 kPa
    assert g2.cycle_s == pytest.approx(1.7)
    assert g2.pressures_kpa.max(axis=0) == pytest.approx([20.0, 100.0, 100.0])
    assert np.allclose(g2.pressures_kpa[0], g2.pressures_kpa[-1]) and np.allclose(
        g2.pressures_kpa[-1], [0, 60, 60]
    )
    g3 = preset("gait3")
    assert g3.cycle_s == pytest.approx(2.0) and np.allclose(g3.pressures_kpa[-1], 0.0)
    # linear between rows: at 1.6 s ePSA 2 and 3 have released 0.1 s x 200 kPa/s
    i = int(np.argmin(np.abs(g3.times - 1.6)))
    assert g3.pressures_kpa[i] == pytest.approx([0.0, 80.0, 80.0])


def test_axial_law_is_eq3_summed_over_three_actuators():
    from softcrawl.analytic.prototype import nominal_epsa

    a = nominal_epsa()
    law = AxialLaw()
    k, f0 = law.stiffness_preload((100.0, 40.0, 0.0))
    assert k == pytest.approx(float(a.k_p(100.0) + a.k_p(40.0) + a.k_p(0.0)))
    assert f0 == pytest.approx(float(a.f_p(100.0) + a.f_p(40.0) - 2 * a.f_p(0.0)))
    assert law.force((0, 0, 0), 0.0) == 0.0  # the robot as built is force-free
    # free extension at 100 kPa: f_p / k_p of one actuator
    assert law.force((100.0,) * 3, float((a.f_p(100.0) - a.f_p(0.0)) / a.k_p(100.0))) == pytest.approx(
        0, abs=1e-9
    )
    assert table2(70.0, "forward") == 18.3 and table2(72.0, "forward") is None


def test_chamber_volume_is_the_table1_chamber_lengthened_by_delta():
    """pi r0^2 (l_c + Delta): 3 mm radius, 90 mm chamber (100 mm body, two 5 mm end caps)."""
    law = AxialLaw()
    assert law.chamber_volume(0.0) == pytest.approx(np.pi * 3.0**2 * 90.0, rel=1e-12)
    assert law.chamber_volume(25.0) - law.chamber_volume(0.0) == pytest.approx(np.pi * 9.0 * 25.0, rel=1e-12)


def test_user_csv_schedule(tmp_path):
    good = tmp_path / "s.csv"
    good.write_text("time_s,P1_kpa,P2_kpa,P3_kpa\n0,0,0,0\n1,50,60,70\n2,0,0,0\n")
    s = read_csv(good)
    assert s.cycle_s == 2.0 and s.pressures_kpa[1].tolist() == [50, 60, 70]
    for text in (
        "time_s,P1_kpa,P2_kpa,P3_kpa\n0,0,0,0\n0,1,1,1\n",  # times not increasing
        "time_s,P1_kpa,P2_kpa,P3_kpa\n0,0,0,0\n1,200,0,0\n",  # over 100 kPa
        "t,a,b,c\n0,0,0,0\n1,1,1,1\n",  # header
        "time_s,P1_kpa,P2_kpa,P3_kpa\n0,0,0\n1,1,1,1\n",  # short row
    ):
        bad = tmp_path / "bad.csv"
        bad.write_text(text)
        with pytest.raises(ScheduleError, match="schedule"):
            read_csv(bad)


def _foot():
    """A stand-in foot: two tets stacked along z, with hub_top at z = 0 and a rim below."""
    from softcrawl.geometry.tagged_mesh import TaggedMesh

    p = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, -1.0], [1, 1, -1.0]])
    t = np.array([[0, 1, 2, 3], [1, 2, 3, 4]])
    vol = np.linalg.det(p[t[:, 1:]] - p[t[:, :1]])
    t[vol < 0] = t[vol < 0][:, [1, 0, 2, 3]]
    facets = {"hub_top": np.array([[0, 1, 2]]), "rim": np.array([[3, 4, 2]])}
    meta = {"curved_surfaces": {"rim": [[[1.0, -1.0], [1.0, 0.0], [0.0, 0.0]]]}}
    return TaggedMesh(p, t, np.ones(2, int), {1: "foot"}, facets, meta=meta)


@pytest.mark.parametrize("mirrored", [(False, False), (False, True), (True, True)])
def test_two_feet_keep_orientation_and_tags(mirrored):
    foot = _foot()
    both = two_feet(foot, 10.0, 1.0, mirrored)
    assert np.all(both.tet_volumes() > 0)
    assert set(both.facets) == {"rear:hub_top", "rear:rim", "front:hub_top", "front:rim"}
    for name, dz, m in zip(("rear", "front"), (0.0, 10.0), mirrored):
        top = both.points[both.facets[f"{name}:hub_top"]].mean(axis=(0, 1))
        # the hub top of a mirrored foot lands at -hub_thickness: the hub keeps its place
        assert top[2] == pytest.approx(dz - 1.0 if m else dz)
        tri = both.points[both.facets[f"{name}:hub_top"][0]]
        normal = np.cross(tri[1] - tri[0], tri[2] - tri[0])
        assert np.sign(normal[2]) == (-1 if m else 1)  # outward: +z, or -z when mirrored
        seg = both.meta["curved_surfaces"][f"{name}:rim"][0]
        assert seg[0][1] == pytest.approx((1.0 - 1.0 + dz) if m else (-1.0 + dz))
    assert attach_tag("rear", False) == "rear:hub_top" and attach_tag("front", False) == "front:hub_bottom"
    assert attach_tag("rear", True) == "rear:hub_bottom" and attach_tag("front", True) == "front:hub_top"


def test_study_tables_keep_every_point_with_its_status(tmp_path):
    """summary.csv from the stored point files: a completed, a failed (with its reason) and a
    missing point all appear; the outcome names the ones that did not complete."""
    import csv

    from softcrawl import jsonio
    from softcrawl.studies.crawl.crawl_study import GRID, point_stem, write_study_outputs
    from softcrawl.studies.sweeps.spec import SweepSpec

    spec = SweepSpec(name="crawl-test", grid=GRID, out_dir=str(tmp_path), evaluator="x:y")
    points = list(spec.points())
    ok, bad = points[0], points[1]
    base = {"strides_mm": "5.1", "steady_stride_mm": 5.1, "anchoring_slip_ratio": 0.04}
    jsonio.write(
        tmp_path / "points" / f"crawl-{point_stem(ok)}.json", {"params": ok, "converged": True} | base
    )
    flags = {
        f"{ph}_{f}_slid": str(ph + f in ("extendfront", "retractrear"))
        for ph in ("extend", "retract")
        for f in ("rear", "front")
    }
    (tmp_path / "points" / point_stem(ok) / "cycles.csv").parent.mkdir(parents=True)
    (tmp_path / "points" / point_stem(ok) / "cycles.csv").write_text(
        ",".join(flags) + "\n" + ",".join(flags.values()) + "\n"
    )
    failed = {"params": bad, "converged": False, "message": "stage 'cycle0-seg1' diverged"} | base
    failed |= {"steady_stride_mm": None, "anchoring_slip_ratio": None}  # NaN is stored as null
    jsonio.write(tmp_path / "points" / f"crawl-{point_stem(bad)}.json", failed)
    outcome = write_study_outputs(spec, tmp_path)
    rows = list(csv.DictReader(open(tmp_path / "summary.csv")))
    assert len(rows) == len(points)
    status = [r["status"] for r in rows]
    assert status[:2] == ["completed", "failed"] and set(status[2:]) == {"missing"}
    assert not outcome.ok and any("diverged" in p for p in outcome.problems)
    assert (rows[0]["extend_slid"], rows[0]["retract_slid"]) == ("front", "rear")  # from cycles.csv
    assert rows[1]["extend_slid"] == ""  # no cycle: nothing claimed
    table = (tmp_path / "summary.md").read_text()
    assert (
        "| front / rear |" in table and "diverged" in table and table.count("| missing |") == len(points) - 2
    )
    assert (tmp_path / "crawl-study.png").exists()


def test_the_wall_time_budget_stops_a_cycle_before_its_next_solve_attempt():
    """Every solve attempt of a cycle segment calls its stage's drive first (fem.contact_stages);
    past the deadline drive raises WallBudgetExceeded (run_crawl turns it into a failure that
    names max_wall_s and the last converged state), before it the pressures are set."""
    import time
    from types import SimpleNamespace

    from softcrawl.studies.crawl.model import WallBudgetExceeded, _cycle_stages

    loads = []
    actuator = SimpleNamespace(set_load=lambda k, f: loads.append((k, f)))
    cm = SimpleNamespace(terms={"actuator": actuator}, law=AxialLaw())
    schedule = preset("inflate", 100.0, 2.0)
    stages, spans = _cycle_stages(cm, schedule, 0, 4, deadline=np.inf)
    assert len(stages) == len(spans) == 2
    assert [s.duration for s in stages] == [1.0, 1.0]  # each segment's time (viscous slip reads it)
    stages[0].drive(0.5)
    assert loads == [AxialLaw().stiffness_preload((50.0, 50.0, 50.0))]
    late, _ = _cycle_stages(cm, schedule, 0, 4, deadline=time.perf_counter() - 1.0)
    with pytest.raises(WallBudgetExceeded):
        late[1].drive(0.25)
    assert len(loads) == 1  # nothing set after the deadline


def test_the_setup_stages_get_the_remaining_wall_time(monkeypatch):
    """The insertion, friction and start stages run under the same budget as the cycles
    (`run_stages(max_wall_s=...)`), so a stalled insertion ends as a recorded failure too."""
    import time
    from types import SimpleNamespace

    from softcrawl.fem.contact_stages import Stage
    from softcrawl.studies.crawl import model as crawl_model

    seen = []
    monkeypatch.setattr(crawl_model, "run_stages", lambda *a, **k: seen.append(k["max_wall_s"]))
    cm = SimpleNamespace(model=None)
    span = [(0.0, 0.0, np.zeros(3), np.zeros(3))]
    crawl_model._run(cm, [Stage("insert")], span, None, None, -1, time.perf_counter() + 100.0)
    crawl_model._run(cm, [Stage("insert")], span, None, None, -1)
    crawl_model._run(cm, [Stage("insert")], span, None, None, -1, time.perf_counter() - 1.0)
    assert 99.0 < seen[0] <= 100.0 and seen[1] is None and seen[2] == pytest.approx(1e-6)


def _contact_area(mirrored, sectors: int, tag: str) -> float:
    """Reference area of one contact face of the two revolved feet, through fem.contact.ContactTerm."""
    from softcrawl.fem.contact import ContactSpec, ContactTerm
    from softcrawl.fem.discretisation import Discretisation
    from softcrawl.fem.rigid_surfaces import CylinderWall
    from softcrawl.studies.crawl.mesh import crawl_mesh

    _, mesh = crawl_mesh(mirrored, mesher="revolved", sectors=sectors)
    term = ContactTerm(Discretisation(mesh), ContactSpec((tag,), CylinderWall(40.0), penalty=1.0))
    assert term.nodes.shape == (6, len(term.facets))
    return float(term.dA.sum())


def test_mirrored_revolved_feet_take_contact_on_every_face():
    """A mirrored foot's contact faces build (their P2 shape functions that vanish on a facet did
    so only to 1.2e-12 after the reflection, once above the old 1e-12 cut: `--symmetric` and
    `--backward` on the revolved feet failed with "expected six P2 nodes"), and the reflection
    keeps every face's area."""
    for face in ("back", "front", "rim"):
        plain = _contact_area((False, False), 24, f"front:{face}")
        assert _contact_area((False, True), 24, f"front:{face}") == pytest.approx(plain, rel=1e-10)


def test_contact_faces_too_coarse_to_map_are_an_input_error():
    """16 sectors: the inverse isoparametric map (fem.p2_mapping) does not converge on the skirt's
    faces; the error names the contact tags."""
    from softcrawl.fem.errors import SolverInputError

    with pytest.raises(SolverInputError, match="contact.tags.*refine the mesh"):
        _contact_area((False, False), 16, "rear:back")


def test_the_crawl_wall_is_the_pipe_of_its_setup():
    from softcrawl.errors import InputError
    from softcrawl.studies.crawl.model import CrawlSetup
    from softcrawl.studies.foot.model import insertion_wall

    pipe = CrawlSetup(pipe_diameter=65.0).pipe
    assert (pipe.kind, pipe.diameter, pipe.radius) == ("straight", 65.0, 32.5)
    wall_at = insertion_wall(pipe, 39.5)
    assert wall_at(0.0).radius == 39.5 and wall_at(1.0).radius == 32.5
    with pytest.raises(InputError):
        insertion_wall(Pipe(kind="elbow", diameter=65.0), 39.5)


class _TighteningSolver:
    """A scripted Newton solver (no FE) for a jam that tightens, as the 55 mm backward insertion
    did (docs/decisions/078-backward-stall.md: sub-steps of 1e-3, then 1e-4 mm of wall travel): a
    sub-step converges (in 8 iterations: no regrowth) only when it is at most `h_ok`, and each
    converged one halves `h_ok`, so the cut-backs in a row stay few while the sub-steps shrink."""

    def __init__(self, model, options):
        from types import SimpleNamespace

        self.h_ok, self.last, self.iterations, self.assembly_s = 0.05, 0.0, 0, 0.0
        self.linear = SimpleNamespace(seconds=0.0, factorizations=0)

    def load_step(self, x, P, f):
        from softcrawl.fem.newton import Diverged, NewtonRecord

        if f - self.last > self.h_ok * (1.0 + 1e-12):
            raise Diverged("residual stalls")
        self.last, self.h_ok = f, 0.5 * self.h_ok
        return np.array([f]), NewtonRecord((1.0,) * 8 + (1e-9,), True)


def _tightening_run(monkeypatch, cycle: int):
    from types import SimpleNamespace

    from softcrawl.fem import contact_stages
    from softcrawl.fem.contact_stages import Stage
    from softcrawl.studies.crawl import model as crawl_model

    monkeypatch.setattr(contact_stages, "NewtonSolver", _TighteningSolver)
    model = SimpleNamespace(contacts=[], chambers=[], commit=lambda x: None)
    model.initial_state = lambda: np.zeros(1)
    cm = SimpleNamespace(model=model)
    recorder = SimpleNamespace(record=lambda *a: None)
    span = [(0.0, 0.0, np.zeros(3), np.zeros(3))]
    stages = [Stage("insert" if cycle < 0 else "cycle0-seg0", factor=1.0, steps=4)]
    return crawl_model._run(cm, stages, span, np.zeros(1), recorder, cycle)


def test_a_setup_stage_that_grinds_stops_at_the_smallest_sub_step(monkeypatch):
    """The crawl's setup stages stop, as a recorded failure, once a sub-step falls below
    MIN_STEP_FRACTION (1e-3) of the stage's step (the foot study's guard); before, `run_crawl`
    passed no floor and the 55 mm backward insertion ground on in sub-steps of 1e-4 mm until it
    was killed (record 078). The cycles keep running without it (here down to the float
    resolution of the stage parameter, which stops them too)."""
    from softcrawl.studies.foot.model import MIN_STEP_FRACTION

    setup = _tightening_run(monkeypatch, -1)
    assert not setup.converged
    assert f"min_step_fraction = {MIN_STEP_FRACTION:g}" in setup.message and "'insert'" in setup.message
    # it stopped at the first sub-step below 1e-3 of the stage's step (0.25): the converged ones kept
    sizes = np.diff([0.0] + [s.factor for s in setup.steps])
    assert sizes.min() >= MIN_STEP_FRACTION * 0.25 and len(setup.steps) < 12
    cycle = _tightening_run(monkeypatch, 0)
    assert not cycle.converged and "min_step_fraction" not in cycle.message
    assert len(cycle.steps) > len(setup.steps)


def test_the_guard_is_passed_to_the_setup_stages_only(monkeypatch):
    from types import SimpleNamespace

    from softcrawl.fem.contact_stages import Stage
    from softcrawl.studies.crawl import model as crawl_model
    from softcrawl.studies.foot.model import MIN_STEP_FRACTION

    seen = []
    monkeypatch.setattr(crawl_model, "run_stages", lambda *a, **k: seen.append(k["min_step_fraction"]))
    cm = SimpleNamespace(model=None)
    span = [(0.0, 0.0, np.zeros(3), np.zeros(3))]
    for cycle in (-1, 0, 3):
        crawl_model._run(cm, [Stage("x")], span, None, None, cycle)
    assert seen == [MIN_STEP_FRACTION, None, None]
