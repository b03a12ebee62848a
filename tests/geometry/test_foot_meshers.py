"""`geometry.foot_meshers`: the revolved foot is refined by sectors and layers, pytetwild's by the
edge length; a setting of the other mesher, or an unknown mesher, is an error that names it."""

import pytest

from softcrawl.geometry.design import DesignError, FootDesign
from softcrawl.geometry.foot_meshers import mesh_foot_with


def test_the_revolved_foot_refines_by_sectors_and_layers_and_keeps_its_volume():
    design = FootDesign()
    coarse = mesh_foot_with(design, "revolved", sectors=24)
    finer = mesh_foot_with(design, "revolved", sectors=48, thickness_layers=4)
    assert len(finer.tets) > 2 * len(coarse.tets)
    # chordal volumes sin(D)/D of the solid: 0.9886 at 24 sectors, 0.9971 at 48
    assert coarse.tet_volumes().sum() == pytest.approx(finer.tet_volumes().sum(), rel=0.01)


@pytest.mark.parametrize(
    "mesher, kwargs, name",
    [
        ("revolved", {"edge_length": 3.0}, "edge_length"),
        ("tetwild", {"sectors": 32}, "sectors"),
        ("tetwild", {"thickness_layers": 2}, "thickness_layers"),
        ("gmsh", {}, "mesher"),
    ],
)
def test_a_setting_of_the_other_mesher_is_an_error_naming_it(mesher, kwargs, name):
    with pytest.raises(DesignError) as err:
        mesh_foot_with(FootDesign(), mesher, **kwargs)
    assert err.value.parameter == name
