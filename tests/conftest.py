import os

import pytest

os.environ.setdefault("MPLBACKEND", "Agg")
os.environ.setdefault("PYVISTA_OFF_SCREEN", "true")


@pytest.fixture(autouse=True)
def _run_in_a_temporary_folder(tmp_path, monkeypatch):
    """Every test runs with its own temporary folder as the working directory, so that a relative
    output path (`--out x`) can never write into the checkout (tests write only to tmp_path)."""
    monkeypatch.chdir(tmp_path)
