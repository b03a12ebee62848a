"""Names in the user's terms for figure titles, legends and the report.

Internal names (`fiber_turns`, `ecoflex-00-50@mu=0.0638`) stay in files and tables; figures say
"fiber turns N" and "Ecoflex 00-50, mu = 0.0638 MPa". One table here, so every figure and the
report use the same words.
"""

from __future__ import annotations

from softcrawl.materials import get_material

#: Design or load parameter -> (symbol for legends, words for titles, unit with its leading space).
PARAMETERS = {
    "chamber_radius": ("r0", "chamber radius r0", " mm"),
    "fiber_turns": ("N", "fiber turns N", ""),
    "outer_radius": ("R0", "outer radius R0", " mm"),
    "length": ("L0", "length L0", " mm"),
    "end_load_n": ("W", "weight W on the guided top", " N"),
}

#: Study name -> (title, the paper's figure or section it repeats).
STUDIES = {
    "chamber-radius": ("Chamber radius study, no fibers", "paper Fig. 8"),
    "fiber-turns": ("Fiber turns study, r0 = 3 mm", "paper Fig. 9"),
    "identify": ("Static identification: the Table 1 ePSA under weights", "paper Section VII-A"),
    "optimise-actuator": ("Actuator optimiser (NSGA-II) at 100 kPa", "beyond the paper"),
    "groove": ("Groove segment pressed at 100 kPa and dragged on the wall", "paper Fig. 10(a)"),
    "foot": ("Whole foot inserted into pipes and dragged both ways", "paper Fig. 10(b), Fig. 4"),
    "robot-rings": ("Connecting rings of the tied robot", "paper Fig. 11(c)"),
    "robot-foot-radius": ("Foot radius d of the tied robot", "paper Section V-C"),
}


def parameter(name: str) -> tuple[str, str, str]:
    """(symbol, words, unit) of a parameter; unknown names are shown as they are."""
    return PARAMETERS.get(name, (name, name.replace("_", " "), ""))


def material_label(name: str | None) -> str:
    """'Ecoflex 00-50, mu = 0.03 MPa' for a `materials` preset name (NAME@mu=VALUE included);
    the name itself when it is not a known preset (a test's fake material)."""
    if not name:
        return "material not recorded"
    try:
        mu = get_material(name).mu
    except Exception:  # noqa: BLE001 - an unknown or fake material: show its name
        return str(name)
    base = str(name).partition("@")[0]
    words = {"ecoflex": "Ecoflex", "dragon": "Dragon", "skin": "Skin", "fit": "(tensile fit)"}
    text = " ".join(words.get(w, w) for w in base.split("-"))
    for a, b in (("Ecoflex 00 50", "Ecoflex 00-50"), ("Ecoflex 00 30", "Ecoflex 00-30")):
        text = text.replace(a, b)
    return f"{text}, mu = {mu:.3g} MPa"


def fixed_text(fixed: dict) -> str:
    """'fiber turns N = 0' for the fixed parameters of a study."""
    parts = []
    for key, value in fixed.items():
        _, words, unit = parameter(key)
        parts.append(f"{words} = {value:g}{unit}")
    return ", ".join(parts)


def study_title(name: str, material: str | None, quick: bool = False, fixed: dict | None = None) -> str:
    """The title of a study's figure: what was studied, in the paper's terms, with which silicone."""
    title, source = STUDIES.get(name, (name, ""))
    extra = fixed_text(fixed or {})
    if name == "chamber-radius" or name == "fiber-turns":
        extra = ""  # the title already says it
    parts = [title + (f" ({source})" if source else "")]
    if extra:
        parts.append(extra)
    parts.append(material_label(material) + (", coarse (quick) mesh" if quick else ""))
    return "; ".join(parts)
