r"""The solver's hyperelastic laws, one module each, and their one registry `LAWS`.

Every law is isochoric in I1, W = Psi(I1bar - 3) + K/2 (J - 1)^2 (`base`: the protocol, stress
and tangent from Psi' and Psi'', the uniaxial nominal stress P = 2 Psi'(x)(lam - lam^-2), the
generic fit). A law's module owns its energy and derivatives, its uniaxial stress, its validity
check, its label and its fit to a tensile test (docstrings state the math):

    neo_hookean   Psi = mu/2 x                              (the fast path of `fem.solid`)
    yeoh          Psi = C10 x + C20 x^2 + C30 x^3            (stable iff Psi' > 0 for x >= 0)
    gent          Psi = -mu Jm/2 ln(1 - x/Jm)                (locks at x = Jm)

The tensor algebra the laws share (and the Neo-Hookean kernel `fem.solid` calls directly for the
laws linear in I1) stays in `fem.neohooke`; only the laws moved here.

`LAWS` (name -> law class) drives everything that names a law: the materials' laws and records
(`materials.material`), the fits (`materials.fitting`) and the command line's `--model` choices.
A new law is a module with a `IsochoricI1Law` subclass plus one `register_law(NewLaw)` line;
`law_class(name)` looks a name up (an unknown name is a one-line input error).
"""

from __future__ import annotations

from softcrawl.fem.errors import SolverInputError
from softcrawl.fem.laws.base import DEFAULT_K_OVER_MU, IsochoricI1Law, with_mu
from softcrawl.fem.laws.gent import Gent, LockingStretch
from softcrawl.fem.laws.neo_hookean import NeoHookean
from softcrawl.fem.laws.yeoh import Yeoh

#: Registry name -> law class, in registration order (the order of the CLI's choices and tables).
LAWS: dict[str, type[IsochoricI1Law]] = {}


def register_law(cls: type[IsochoricI1Law]) -> type[IsochoricI1Law]:
    """Add `cls` to `LAWS` under `cls.NAME` (returns `cls`, so it also works as a decorator).

    The class must be an `IsochoricI1Law` that defines NAME, FIT_PARAMS, MODULI, `label` and
    `nearly_incompressible`; a name already taken by another class is an error."""
    if not (isinstance(cls, type) and issubclass(cls, IsochoricI1Law)):
        raise SolverInputError("law", f"{cls!r} is not an IsochoricI1Law subclass")
    missing = [a for a in ("NAME", "FIT_PARAMS", "MODULI", "nearly_incompressible") if not hasattr(cls, a)]
    if cls.label is IsochoricI1Law.label:
        missing.append("label")
    if missing:
        raise SolverInputError("law", f"{cls.__name__} does not define {', '.join(missing)}")
    if not isinstance(cls.NAME, str) or not cls.NAME or LAWS.get(cls.NAME, cls) is not cls:
        raise SolverInputError("law", f"{cls.__name__}: name {cls.NAME!r} is empty or taken")
    LAWS[cls.NAME] = cls
    return cls


def law_class(name: str, parameter: str = "model") -> type[IsochoricI1Law]:
    """The registered law called `name`; an unknown name is an input error naming `parameter`."""
    if not isinstance(name, str) or name not in LAWS:
        raise SolverInputError(parameter, f"unknown law {name!r:.40}; valid: {', '.join(LAWS)}")
    return LAWS[name]


for _law in (NeoHookean, Yeoh, Gent):
    register_law(_law)

__all__ = [
    "DEFAULT_K_OVER_MU",
    "LAWS",
    "Gent",
    "IsochoricI1Law",
    "LockingStretch",
    "NeoHookean",
    "Yeoh",
    "law_class",
    "register_law",
    "with_mu",
]
