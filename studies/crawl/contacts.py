r"""The feet's contact terms, shared by both crawl models: the reduced crawl (`studies.crawl.model`)
and the one FE body (`studies.crawl_fe.model`) take their contacts from here, so that the two
differ only in how the body is modelled.

Per foot two faces against the pipe wall: "smooth" (the skirt's front face and rim, mu_smooth) and
"grooved" (its back face, mu_grooved), named "<foot>:<face>"; the friction coefficients are set
when a stage switches friction on. Penalty eps_N = 10 E / h (E the rubber law's small-strain
modulus, h the feet's median edge), the foot study's smoothing and rounded cone
(`studies.foot.model`), and viscous slip when the setup asks for it (`fem.contact_law`,
docs/decisions/088-viscous-slip.md).
"""

from __future__ import annotations

from softcrawl.fem.contact import ContactSpec
from softcrawl.fem.rigid_surfaces import CylinderWall
from softcrawl.studies.crawl.mesh import FEET
from softcrawl.studies.foot.model import SLIP_BAND, SMOOTHING, small_strain_youngs

FACES = (("smooth", ("front", "rim")), ("grooved", ("back",)))


def feet_contacts(rubber, edge: float, tip_radius: float, viscosity: float = 0.0) -> list[ContactSpec]:
    """Each foot's two faces (`FACES`) against the straight pipe wall, clear of the tips by 0.5 mm
    (the insertion closes it), on a rubber law and the feet's median edge (module docstring);
    `viscosity`: eta of viscous slip (MPa s/mm; 0: Coulomb)."""
    eps = 10.0 * small_strain_youngs(rubber) / edge
    wall = CylinderWall(tip_radius + 0.5)
    return [
        ContactSpec(
            tuple(f"{foot}:{t}" for t in tags),
            wall,
            penalty=eps,
            name=f"{foot}:{face}",
            smoothing=SMOOTHING,
            slip_band=SLIP_BAND,
            slip_viscosity=viscosity,
        )
        for foot in FEET
        for face, tags in FACES
    ]
