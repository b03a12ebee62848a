"""Uniaxial tensile tests: the shipped Soft Robotics Materials Database files and the CSV reader.

`load_tensile` reads the tensile tests shipped in ``softcrawl/materials/data`` (Marechal et al., Soft
Robotics 8(3), 2021; ODbL 1.0 / DbCL 1.0, attribution in ``softcrawl/materials/data/README.md`` and in
`DATA_ATTRIBUTION`, which must travel with every derived table) or any CSV file of that format.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from softcrawl.materials.material import MaterialError

DATA_DIR = Path(__file__).resolve().parent / "data"
#: Largest tensile-test file read (bytes): the shipped tests are 17-33 kB; 50 MB is a
#: million-row test, and anything larger is not a tensile test.
MAX_TENSILE_FILE_BYTES = 50_000_000

#: Shipped tensile tests: data name -> CSV file in DATA_DIR.
TENSILE_FILES = {
    "ecoflex-00-50": "ecoflex-00-50-tensile.csv",
    "ecoflex-00-30": "ecoflex-00-30-tensile.csv",
    "dragon-skin-30": "dragon-skin-30-tensile.csv",
}

DATA_ATTRIBUTION = (
    "Tensile data: Soft Robotics Materials Database, L. Marechal, L. Lindenroth et al. "
    "(Marechal et al., 'Toward a Common Framework and Database of Materials for Soft Robotics', "
    "Soft Robotics 8(3), 2021), repository LucMarechal/Soft-Robotics-Materials-Database, "
    "commit 8ff66c3, folder Tensile-Tests-Data."
)
DATA_LICENSE = (
    "Database: Open Database License (ODbL 1.0); contents: Database Contents License (DbCL 1.0). "
    "Derived constants are shared under the same terms; keep this attribution with them."
)


@dataclass(frozen=True, kw_only=True, eq=False)
class TensileData:
    """One uniaxial tensile test: engineering strain [-] and nominal stress [MPa], loading branch.

    `metadata` holds the PARAMETER;INFO header lines (specimen, machine, material...).
    """

    name: str
    path: str
    strain: np.ndarray
    nominal_stress: np.ndarray
    metadata: tuple[tuple[str, str], ...] = ()
    attribution: str = ""

    @property
    def stretch(self) -> np.ndarray:
        """lam = 1 + engineering strain."""
        return 1.0 + self.strain


def load_tensile(name: str) -> TensileData:
    """Read a tensile test: a shipped data name (see `TENSILE_FILES`) or a path to a CSV file.

    The file format is the Soft Robotics Materials Database one: semicolon-separated
    ``PARAMETER;INFO`` metadata lines, then a header row naming the columns (found by name, in
    any order, case-insensitively: ``Engineering Strain`` and ``Engineering Stress (MPa)``), then
    data rows. Blank rows and rows with a non-numeric strain or stress are skipped; a decimal
    comma is accepted. Rows after the peak stress (specimen failure) are dropped, and the strain
    must then be strictly increasing.
    """
    path, shipped = _tensile_path(name)
    try:
        if path.stat().st_size > MAX_TENSILE_FILE_BYTES:
            raise MaterialError("data", f"{path} is larger than {MAX_TENSILE_FILE_BYTES} bytes")
        text = path.read_text(encoding="utf-8-sig")
    except OSError as exc:
        raise MaterialError("data", f"cannot read {path}: {exc.strerror or exc}") from None
    except UnicodeDecodeError:
        raise MaterialError("data", f"{path} is not a UTF-8 text (CSV) file") from None
    metadata, strain, stress = _parse_tensile_csv(text, str(path))
    peak = int(np.argmax(stress))
    strain, stress = strain[: peak + 1], stress[: peak + 1]
    if np.any(np.diff(strain) <= 0.0):
        raise MaterialError(
            "data", f"{path}: engineering strain is not strictly increasing on the loading branch"
        )
    return TensileData(
        name=name if shipped else path.stem,
        path=str(path),
        strain=strain,
        nominal_stress=stress,
        metadata=metadata,
        attribution=DATA_ATTRIBUTION if shipped else "",
    )


def _tensile_path(name: str) -> tuple[Path, bool]:
    if name in TENSILE_FILES:
        return DATA_DIR / TENSILE_FILES[name], True
    path = Path(str(name))
    if path.is_file():
        return path, False
    raise MaterialError(
        "data", f"{name!r} is neither a shipped data set ({', '.join(TENSILE_FILES)}) nor a file"
    )


def _parse_tensile_csv(text: str, label: str) -> tuple[tuple[tuple[str, str], ...], np.ndarray, np.ndarray]:
    lines = text.splitlines()
    header_index = None
    for index, line in enumerate(lines):
        cells = [cell.strip().lower() for cell in line.split(";")]
        if "engineering strain" in cells:
            header_index = index
            break
    if header_index is None:
        raise MaterialError("data", f"{label}: no header row with an 'Engineering Strain' column")
    columns = [cell.strip().lower() for cell in lines[header_index].split(";")]
    strain_col = columns.index("engineering strain")
    stress_col = next((i for i, c in enumerate(columns) if c.startswith("engineering stress")), None)
    if stress_col is None:
        raise MaterialError("data", f"{label}: no 'Engineering Stress (MPa)' column")
    metadata = tuple(
        _metadata_pair(line)
        for line in lines[:header_index]
        if line.strip(" ;") and not line.upper().startswith("PARAMETER;")
    )
    strain, stress = [], []
    for line in lines[header_index + 1 :]:
        cells = line.split(";")
        if len(cells) <= max(strain_col, stress_col):
            continue
        e, s = _number(cells[strain_col]), _number(cells[stress_col])
        if e is None or s is None:
            continue
        strain.append(e)
        stress.append(s)
    if len(strain) < 3:
        raise MaterialError("data", f"{label}: fewer than 3 numeric data rows")
    return metadata, np.array(strain), np.array(stress)


def _metadata_pair(line: str) -> tuple[str, str]:
    key, _, rest = line.partition(";")
    return key.strip(), rest.split(";")[0].strip()


def _number(cell: str) -> float | None:
    cell = cell.strip()
    if "," in cell and "." not in cell:
        cell = cell.replace(",", ".")
    try:
        value = float(cell)
    except ValueError:
        return None
    return value if math.isfinite(value) else None
