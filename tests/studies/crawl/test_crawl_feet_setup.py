"""The crawl takes its feet's design and rubber from `CrawlSetup` (issue 29, step 6)."""

import dataclasses

import numpy as np
import pytest

from softcrawl.geometry.foot_design import FootDesign
from softcrawl.studies.crawl import files
from softcrawl.studies.crawl.insertion import mesh_hash
from softcrawl.studies.crawl.mesh import crawl_mesh, separation
from softcrawl.studies.crawl.model import CrawlSetup


def test_the_default_setup_is_the_papers_foot_in_70a_rubber():
    setup = CrawlSetup()
    assert setup.foot == FootDesign() and setup.foot.angle == 120.0
    assert setup.material == "rubber-70a" == files.MATERIAL


def test_a_60_degree_foot_builds_another_mesh_than_the_papers():
    setup = CrawlSetup(sectors=24)
    narrow = dataclasses.replace(setup, foot=FootDesign(angle=60.0))
    design, mesh = crawl_mesh(setup.mirrored, foot=setup.foot, **setup.mesh_options())
    design60, mesh60 = crawl_mesh(narrow.mirrored, foot=narrow.foot, **narrow.mesh_options())
    assert design.angle == 120.0 and design60.angle == 60.0
    assert mesh_hash(mesh60) != mesh_hash(mesh)
    # the 60 deg foot's hub is 6 mm (t / sin 30 deg), so the front hub sits 2 mm further forward
    assert separation(design60) - separation(design) == pytest.approx(2.0, abs=1e-9)
    assert np.ptp(mesh60.p[2]) > np.ptp(mesh.p[2])  # the narrower cone reaches further back
    # the default crawl mesh is the paper's foot's, bit for bit
    assert mesh_hash(crawl_mesh(setup.mirrored, **setup.mesh_options())[1]) == mesh_hash(mesh)


class _Reached(Exception):
    pass


def test_run_and_write_builds_the_setups_foot_and_rubber(tmp_path, monkeypatch):
    seen = {}

    def fake_mesh(mirrored, foot=None, **options):
        seen["foot"] = foot
        return foot, None

    def fake_law(material, hyperelastic_only):
        seen["material"] = material.name
        raise _Reached

    monkeypatch.setattr(files, "crawl_mesh", fake_mesh)
    monkeypatch.setattr(files, "solid_law", fake_law)
    setup = CrawlSetup(foot=FootDesign(angle=60.0), material="rubber-50a")
    with pytest.raises(_Reached):
        files.run_and_write(setup, None, tmp_path)
    assert seen == {"foot": FootDesign(angle=60.0), "material": "rubber-50a"}


def test_the_summary_names_the_rubbers_source():
    assert files.material_source("rubber-70a") == files.MATERIAL_SOURCE
    assert "50A" in files.material_source("rubber-50a")


@pytest.mark.parametrize(("angle", "sectors"), [(120.0, 24), (90.0, 34), (60.0, 42), (30.0, 47)])
def test_quick_crawls_take_the_least_sectors_each_angle_builds(angle, sectors):
    """`crawl --quick --foot-angle A` meshes at `quick_sectors` (record 066: 24 fails below 120 deg)."""
    from softcrawl.studies.cli import build_parser
    from softcrawl.studies.commands.crawl import mesh_settings

    args = build_parser().parse_args(["crawl", "--quick", "--foot-angle", f"{angle:g}", "--out", "x"])
    assert mesh_settings(args)["sectors"] == sectors
