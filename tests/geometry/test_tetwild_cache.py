"""Cache keys: design hash + mesh settings; default location from $SOFTCRAWL_CACHE."""

from pathlib import Path

from softcrawl.geometry.design import EPSADesign
from softcrawl.geometry.tetwild import _cache_path, default_cache_dir


def test_cache_key_depends_on_design_and_settings(tmp_path):
    h1, h2 = EPSADesign().short_hash(), EPSADesign(chamber_radius=4).short_hash()
    s = {"kind": "epsa", "edge_length": 5.0, "n_theta": 48, "epsilon": 1e-3}
    p = _cache_path(tmp_path, "epsa", h1, s)
    assert p.parent == tmp_path and h1 in p.name and p.suffix == ".npz"
    assert _cache_path(tmp_path, "epsa", h1, dict(s)) == p
    assert _cache_path(tmp_path, "epsa", h2, s) != p
    assert _cache_path(tmp_path, "epsa", h1, {**s, "edge_length": 4.0}) != p
    assert _cache_path(tmp_path, "epsa", h1, {**s, "n_theta": 64}) != p
    assert _cache_path(False, "epsa", h1, s) is None


def test_default_cache_dir(monkeypatch, tmp_path):
    monkeypatch.setenv("SOFTCRAWL_CACHE", str(tmp_path))
    assert default_cache_dir() == tmp_path
    monkeypatch.delenv("SOFTCRAWL_CACHE")
    assert default_cache_dir() == Path.home() / ".cache" / "softcrawl" / "meshes"
