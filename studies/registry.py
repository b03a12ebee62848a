"""The study registry: every study of `softcrawl study`, declared once in its feature folder.

`STUDY_MODULES` lists the declaration modules, one line per feature; each holds a tuple
`STUDIES` of `studies.declaration.Study`. Adding a study is one declaration in its folder (and, for
a new folder, one line here). `register` adds one at run time (a plug-in, or a test's toy study).

Sweep evaluators are stored by registry name (``"epsa"``, ``"crawl"``, ...) in a study's
spec.json and handed to spawned workers by that name; `evaluator_reference` turns a name into its
``"module:function"``. Studies computed before the registry stored the function's import path;
`LEGACY_EVALUATORS` maps every path that a committed study used to its name, so that they resume,
and any other import path is refused with one line.
"""

from __future__ import annotations

import dataclasses
import importlib
from collections.abc import Callable

from softcrawl.studies.declaration import Study, StudyRequest, resolve
from softcrawl.studies.sweeps.spec import StudyError

#: The declaration modules, in the order of `softcrawl study --help` and of the design review.
STUDY_MODULES = (
    "softcrawl.studies.epsa.study",
    "softcrawl.studies.foot.study",
    "softcrawl.studies.skirt.study",
    "softcrawl.studies.robot_fe.study",
    "softcrawl.studies.crawl.study",
    "softcrawl.studies.material.study",
)

#: Evaluator import paths of studies computed before the registry -> their registry names.
LEGACY_EVALUATORS = {
    "studies.runner:evaluate_epsa": "epsa",
    "studies.catalogue.epsa_evaluator:evaluate_epsa": "epsa",
    "studies.catalogue.constrained_objective:evaluate_constrained": "epsa-constrained",
    "studies.catalogue.contact_studies:evaluate_groove": "groove",
    "studies.catalogue.contact_studies:evaluate_foot": "foot",
    "studies.catalogue.robot_studies:evaluate_robot": "robot",
    "studies.catalogue.crawl_study:evaluate_crawl": "crawl",
}

_added: dict[str, Study] = {}


class RegistryError(StudyError):
    """An unknown study or evaluator name; `parameter` names where it came from."""


def _declared() -> dict[str, Study]:
    out: dict[str, Study] = {}
    for module in STUDY_MODULES:
        for study in importlib.import_module(module).STUDIES:
            if study.name in out:
                raise ValueError(f"study {study.name!r} is declared twice ({module})")
            out[study.name] = study
    return out


def studies() -> tuple[Study, ...]:
    """Every study, declared ones in registry order, then those added by `register`."""
    return tuple((_declared() | _added).values())


def names() -> tuple[str, ...]:
    return tuple(s.name for s in studies())


def get(name: str) -> Study:
    for study in studies():
        if study.name == name:
            return study
    raise RegistryError("name", f"unknown study {name!r}; valid: {', '.join(names())}")


def register(study: Study) -> Study:
    """Add a study at run time (a plug-in or a test); a declared name cannot be replaced."""
    if study.name in _declared():
        raise ValueError(f"study {study.name!r} is already declared")
    _added[study.name] = study
    return study


def unregister(name: str) -> None:
    _added.pop(name, None)


def evaluators() -> dict[str, str]:
    """Every registry evaluator name -> its ``"module:function"``."""
    out: dict[str, str] = {}
    for study in studies():
        out |= dict(study.evaluators)
    return out


def evaluator_reference(name: str, parameter: str = "evaluator") -> str:
    """The ``"module:function"`` of an evaluator given by registry name or by a legacy import
    path; anything else is an input error naming `parameter`."""
    known = evaluators()
    name = LEGACY_EVALUATORS.get(name, name)
    if name in known:
        return known[name]
    raise RegistryError(
        parameter,
        f"unknown evaluator {name!r} (a study computed by another softcrawl version?); "
        f"known: {', '.join(sorted(known))}",
    )


def evaluator(name: str) -> Callable:
    return resolve(evaluator_reference(name))


def refuse_material(study: Study, material: object) -> None:
    """StudyError (parameter "material") when a material is given to a study that takes none
    (its `default_material` is None): it would be silently ignored."""
    if material is not None and study.default_material is None:
        raise StudyError(
            "material", f"--material does not apply to study {study.name}: it takes no material (see --help)"
        )


def run_study(name: str, out: str, **options: object) -> object:
    """Run (or resume) study `name` into `out`, as `softcrawl study NAME --out OUT` does, and
    return its `StudyOutcome`; `options` are `StudyRequest`'s fields (quick, material, workers,
    storage, ...). The material defaults to the study's own; a study that takes none refuses one
    (`refuse_material`)."""
    study = get(name)
    refuse_material(study, options.get("material"))
    request = StudyRequest(study=name, out=str(out), **options)  # type: ignore[arg-type]
    if request.material is None and study.default_material is not None:
        request = dataclasses.replace(request, material=study.default_material)
    if study.check is not None:
        resolve(study.check)(request)
    return resolve(study.run)(request)
