import os

import pytest

os.environ.setdefault("MPLBACKEND", "Agg")
os.environ.setdefault("PYVISTA_OFF_SCREEN", "true")

#: Time limit (s) of a test marked slow that sets none itself (pyproject.toml sets the default
#: limit of the fast tests): the slow set has fine meshes and full sweeps of up to ~15 minutes.
SLOW_TIMEOUT = 3600


def pytest_collection_modifyitems(config, items):
    for item in items:
        if item.get_closest_marker("slow") and not item.get_closest_marker("timeout"):
            item.add_marker(pytest.mark.timeout(SLOW_TIMEOUT))


@pytest.fixture(autouse=True)
def _run_in_a_temporary_folder(tmp_path, monkeypatch):
    """Every test runs with its own temporary folder as the working directory, so that a relative
    output path (`--out x`) can never write into the checkout (tests write only to tmp_path)."""
    monkeypatch.chdir(tmp_path)
