"""The squeezed skirt's stability against the mesh (issue 29, step 2), declared for the registry
(`studies.registry`): the foot inserted into the 60 mm pipe on refined revolved meshes."""

from softcrawl.studies.declaration import Study

STUDIES = (
    Study(
        name="skirt",
        summary="the foot squeezed into a 60 mm pipe: force, unstable modes and lobes against the mesh",
        run="softcrawl.studies.skirt.runs:run_request",
        default_material="rubber-70a",
        tables=("skirt.csv",),
        help="skirt: the whole foot inserted into the 60 mm pipe on revolved meshes of 24-128 sectors "
        "and 3-6 cells through the skirt; per mesh the insertion force, the number of unstable modes "
        "(negative eigenvalues of the tangent, pressure block discounted), the lobe count of the "
        "lowest mode, and on two meshes the insertion followed again with that mode seeded; see "
        "studies/skirt/runs.py. --quick: 24 and 48 sectors.",
    ),
)
