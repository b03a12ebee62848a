"""`softcrawl report`: one self-contained HTML design review built from the committed results/.

It computes no finite-element solution: it reads the study tables, figures, calibration, renders
and the verification table under results/, fits the shipped tensile data (a second), and writes
DIR/index.html (`studies.html` says how it stays self-contained). A section whose results
are missing says which command makes them.

The first section answers the reviewer's three questions from the tables alone:

- what limits the design: without the winding, a limit (burst) point of the chamber; with it, the
  largest principal stretch of the silicone against the stretch at which the shipped tensile test
  broke (uniaxial, so an indication, not a failure criterion for the multiaxial wall), and the
  bending over of the long actuator (the side-load probe);
- at what pressure: the limit pressures and the pressure the ramp reached;
- how sure: the spread between the two moduli (tensile 0.03 MPa, calibrated 0.0638 MPa), the mesh
  convergence of the default mesh, the calibration error, the verification cases.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

from softcrawl import __version__
from softcrawl.console import detail
from softcrawl.provenance import git_commit
from softcrawl.studies.crawl_fe.report import crawl_fe
from softcrawl.studies.html import page
from softcrawl.studies.review import headline as H
from softcrawl.studies.review import provenance as P
from softcrawl.studies.review import report_sections as S
from softcrawl.studies.robot_fe import report as R

#: The Table 1 actuator: r0 = 3 mm, N = 20 (the fiber-turns study's design of the paper).
TABLE1_TURNS = 20.0

SECTIONS = (
    ("answer", "The answer in detail: every material of the tables", S.answer),
    ("table1", "Table 1: the paper's values against rules and evidence", S.table1),
    ("renders", "The Table 1 actuator at 0, 50 and 100 kPa", S.renders),
    ("studies", "Studies: figures and tables", S.studies),
    ("robot", "The tied robot: Fig. 11 load and FE workspace", R.robot),
    ("crawl", "Crawling in a pipe: the gait in FE", R.crawl),
    ("crawl-fe", "The whole robot crawling in FE: straight, vertical and elbow pipes", crawl_fe),
    ("material", "Material: the tensile fit and the presets", S.material),
    ("calibration", "Calibration of the body's modulus to the prototype", S.calibration),
    ("verify", "Verification of the solver (softcrawl verify)", S.verify),
    ("benchmarks", "Solver benchmarks and mesh convergence", S.benchmarks),
    ("provenance", "Provenance: version, commit, commands and materials of every result", P.provenance),
)


def build_report(results, out, progress=print) -> Path:
    """Write OUT/index.html from the results folder `results`; returns its path."""
    results, out = Path(results), Path(out)
    sections = []
    for sid, heading, make in SECTIONS:
        progress(f"  {heading}")
        t0 = time.perf_counter()
        sections.append((sid, heading, make(results)))
        detail(f"    {time.perf_counter() - t0:.2f} s")

    preamble = (
        f"<p>softcrawl {__version__}, commit {git_commit(results)}, Python {sys.version.split()[0]}. "
        "Built by <code>softcrawl report</code> from the files under <code>results/</code>; every figure "
        "and number below comes from those files (section Provenance gives the command of each).</p>"
    )
    out.mkdir(parents=True, exist_ok=True)
    path = out / "index.html"
    title = "softcrawl design review: the Table 1 ePSA"
    path.write_text(page(title, sections, preamble, headline=H.headline(results)))
    return path
