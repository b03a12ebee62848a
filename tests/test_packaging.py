"""Installing softcrawl adds one import name, `softcrawl`, to site-packages (setup.py maps the
top-level folders fem/, geometry/ and studies/ into it), so it lives beside Robot Framework's
`robot` or PyPI's `fem` and `geometry` without shadowing them."""

import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.timeout(600)
def test_the_wheel_holds_only_the_softcrawl_package(tmp_path):
    source = tmp_path / "src"
    files = subprocess.run(
        ["git", "-C", str(ROOT), "ls-files", "--cached", "--others", "--exclude-standard"],
        capture_output=True,
        text=True,
        check=True,
    ).stdout.split()
    for name in files:
        if name.startswith(("results/", "docs/")) or not (ROOT / name).is_file():
            continue
        (source / name).parent.mkdir(parents=True, exist_ok=True)
        (source / name).write_bytes((ROOT / name).read_bytes())
    built = subprocess.run(
        [sys.executable, "-m", "pip", "wheel", "-q", "--no-deps", "-w", str(tmp_path / "dist"), str(source)],
        capture_output=True,
        text=True,
    )
    assert built.returncode == 0, built.stderr[-2000:]
    (wheel,) = (tmp_path / "dist").glob("softcrawl-*.whl")
    names = zipfile.ZipFile(wheel).namelist()
    assert {n.split("/")[0] for n in names} == {"softcrawl", wheel.name.split("-py")[0] + ".dist-info"}
    expected = (
        "softcrawl/fem/newton.py",
        "softcrawl/geometry/design.py",
        "softcrawl/studies/cli.py",
        "softcrawl/analytic/statics.py",
        "softcrawl/materials/presets.py",
        "softcrawl/materials/data/ecoflex-00-50-tensile.csv",
        "softcrawl/__main__.py",
    )
    for module in expected:
        assert module in names, module
    entry_points = zipfile.ZipFile(wheel).read(next(n for n in names if n.endswith("entry_points.txt")))
    assert b"softcrawl = softcrawl.studies.cli:main" in entry_points


def test_the_editable_install_maps_only_softcrawl_names():
    """The installed finder (an editable install) or the installed package serves every module
    under `softcrawl`; no bare `fem`, `geometry`, `studies`, `robot` or `materials` is importable
    from outside the checkout."""
    code = (
        "import importlib.util, sys; sys.path = [p for p in sys.path if p not in ('', '.')];"
        "print([n for n in ('fem', 'geometry', 'studies', 'materials') if importlib.util.find_spec(n)]);"
        "import softcrawl.fem.newton, softcrawl.studies.cli; print('ok')"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd="/", check=True)
    assert out.stdout.split("\n")[:2] == ["[]", "ok"], out.stdout + out.stderr
