"""softcrawl: the public Python API, one import for scripts and notebooks (``import softcrawl as sc``).

Units at this edge: lengths in mm, forces in N, pressures in kPa (converted to the solver's MPa once,
inside the simulation functions), material constants in MPa.

=====================  ==================================================  ===========================
name                   what                                                lives in
=====================  ==================================================  ===========================
EPSADesign             the actuator's design (Table 1 defaults)            softcrawl.geometry.design
FootDesign             the grooved foot's design                           softcrawl.geometry.design
RingDesign             a connecting ring's design                          softcrawl.geometry.design
RobotDesign            the robot: ePSA, feet, rings, their layout          softcrawl.geometry.design
load_design            a design from a .json / .toml file                  softcrawl.geometry.design
Material               a validated material law (Neo-Hookean, Yeoh, ...)   softcrawl.materials.material
get_material           a preset by name, or ``NAME@mu=VALUE``              softcrawl.materials.presets
material_names         the preset names                                    softcrawl.materials.presets
load_tensile           a shipped tensile test                              softcrawl.materials.tensile
fit_tensile            fit a hyperelastic law to a tensile test            softcrawl.materials.fitting
TensileData            a tensile test (stretch, nominal stress)            softcrawl.materials.tensile
FitResult              a fitted law and its residuals                      softcrawl.materials.fitting
simulate_epsa          one ePSA under a pressure ramp -> ActuatorCurve     softcrawl.studies.epsa.response
simulate_robot         the robot under P1, P2, P3 -> RobotRun              softcrawl.studies.robot_fe.simulate
simulate_foot          a foot inserted and dragged -> FootResult           softcrawl.studies.foot.simulate
simulate_crawl         two feet crawling in a pipe -> CrawlResult          softcrawl.studies.crawl.simulate
ActuatorCurve          result of simulate_epsa (frozen)                    softcrawl.studies.epsa.response
RobotRun               result of simulate_robot (frozen)                   softcrawl.studies.robot_fe.response
FootResult             result of simulate_foot (frozen)                    softcrawl.studies.foot.model
CrawlResult            result of simulate_crawl (frozen)                   softcrawl.studies.crawl.outputs
prototype_epsa         the paper's identified ePSA 1-3 (statics, eq. 3)    softcrawl.analytic.prototype
nominal_epsa           the mean of the three prototypes                    softcrawl.analytic.prototype
forward_kinematics     lengths -> (kappa, theta, phi, l_c), eqs. 4-6       softcrawl.analytic.kinematics
inverse_kinematics     tip position -> ePSA lengths (exact IK)             softcrawl.analytic.kinematics
tip_position           lengths -> tip position, eq. 9                      softcrawl.analytic.kinematics
run_study              run a named study into a folder                     softcrawl.studies.registry
study_names            the study names                                     softcrawl.studies.registry
InputError             the error of every bad input (names the parameter)  softcrawl.errors
DesignError            a bad design (an InputError)                        softcrawl.geometry.errors
MaterialError          a bad material (an InputError)                      softcrawl.materials.material
=====================  ==================================================  ===========================

Every name is loaded on first use (PEP 562): ``import softcrawl`` imports only the standard library,
so the core modules (`softcrawl.errors`, `checks`, `files`, `jsonio`) that the whole code base imports
stay light, and so does the command line. The package layering is in docs/DESIGN.md ("Layout");
docs/api.md shows the API at work.
"""

from __future__ import annotations

import importlib
from importlib import metadata

try:
    __version__ = metadata.version("softcrawl")
except metadata.PackageNotFoundError:  # a source checkout on PYTHONPATH, not installed
    __version__ = "0+unknown"

#: Public name -> "module:attribute" it is loaded from on first use (the table above).
_LAZY = {
    # designs
    "EPSADesign": "softcrawl.geometry.design:EPSADesign",
    "FootDesign": "softcrawl.geometry.design:FootDesign",
    "RingDesign": "softcrawl.geometry.design:RingDesign",
    "RobotDesign": "softcrawl.geometry.design:RobotDesign",
    "load_design": "softcrawl.geometry.design:load_design",
    # materials and fitting
    "Material": "softcrawl.materials.material:Material",
    "get_material": "softcrawl.materials.presets:get_material",
    "material_names": "softcrawl.materials.presets:material_names",
    "load_tensile": "softcrawl.materials.tensile:load_tensile",
    "fit_tensile": "softcrawl.materials.fitting:fit_tensile",
    "TensileData": "softcrawl.materials.tensile:TensileData",
    "FitResult": "softcrawl.materials.fitting:FitResult",
    # simulations (pressures in kPa) and their frozen results
    "simulate_epsa": "softcrawl.studies.epsa.response:simulate_epsa",
    "simulate_robot": "softcrawl.studies.robot_fe.simulate:simulate_robot",
    "simulate_foot": "softcrawl.studies.foot.simulate:simulate_foot",
    "simulate_crawl": "softcrawl.studies.crawl.simulate:simulate_crawl",
    "ActuatorCurve": "softcrawl.studies.epsa.response:ActuatorCurve",
    "RobotRun": "softcrawl.studies.robot_fe.response:RobotRun",
    "FootResult": "softcrawl.studies.foot.model:FootResult",
    "CrawlResult": "softcrawl.studies.crawl.outputs:CrawlResult",
    # the paper's analytic models
    "prototype_epsa": "softcrawl.analytic.prototype:prototype_epsa",
    "nominal_epsa": "softcrawl.analytic.prototype:nominal_epsa",
    "forward_kinematics": "softcrawl.analytic.kinematics:forward",
    "inverse_kinematics": "softcrawl.analytic.kinematics:inverse",
    "tip_position": "softcrawl.analytic.kinematics:tip",
    # the studies of the command line
    "run_study": "softcrawl.studies.registry:run_study",
    "study_names": "softcrawl.studies.registry:names",
    # errors
    "InputError": "softcrawl.errors:InputError",
    "DesignError": "softcrawl.geometry.errors:DesignError",
    "MaterialError": "softcrawl.materials.material:MaterialError",
}

__all__ = ["__version__", *_LAZY]


def __getattr__(name: str) -> object:
    """Load a public name of `_LAZY` on first use and keep it in the module."""
    try:
        target = _LAZY[name]
    except KeyError:
        raise AttributeError(f"module 'softcrawl' has no attribute {name!r}") from None
    module, _, attribute = target.partition(":")
    value = getattr(importlib.import_module(module), attribute)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    """The module's own names and the lazy public ones."""
    return sorted(set(globals()) | set(_LAZY))
