"""The committed results/ hold no path of the machine that made them, and every JSON is strict."""

import csv
import json
from pathlib import Path

import pytest

RESULTS = Path(__file__).resolve().parents[1] / "results"
MACHINE_PREFIXES = ("/tmp/", "/work/", "/home/", "/root/", "/Users/", "C:\\")


def _strict(text: str):
    def refuse(constant):
        raise ValueError(f"bare {constant} is not JSON")

    return json.loads(text, parse_constant=refuse)


@pytest.mark.parametrize("path", sorted(RESULTS.rglob("*.json")), ids=lambda p: str(p.relative_to(RESULTS)))
def test_committed_json_is_strict(path):
    _strict(path.read_text())


def test_committed_tables_and_texts_hold_no_absolute_paths():
    files = [p for p in RESULTS.rglob("*") if p.suffix in (".csv", ".json", ".md", ".html", ".txt")]
    assert files
    for path in files:
        text = path.read_text(errors="replace")
        assert not any(prefix in text for prefix in MACHINE_PREFIXES), path


def test_study_vtu_column_is_relative_to_the_study_folder():
    for path in RESULTS.glob("*/*/curves.csv"):
        for row in csv.DictReader(open(path)):
            assert not row.get("vtu") or row["vtu"].startswith("vtu/"), (path, row["vtu"])


def test_every_results_file_the_readmes_link_exists():
    """A figure or table that README.md or a results/ README links (`](results/...)` or a relative
    link inside results/) is committed: a renamed study folder must not leave a broken link."""
    import re

    readmes = [RESULTS.parent / "README.md", *sorted(RESULTS.rglob("README.md"))]
    missing = []
    for readme in readmes:
        for target in re.findall(r"\]\(([^)#\s]+)\)", readme.read_text()):
            if "://" in target or not target.endswith((".png", ".gif", ".csv", ".json", ".md")):
                continue
            if not (readme.parent / target).exists():
                missing.append(f"{readme.relative_to(RESULTS.parent)} -> {target}")
    assert not missing, missing
