"""Every summary.json records the softcrawl version and git commit (`softcrawl.provenance`)."""

import json
import re
from pathlib import Path

from softcrawl import __version__
from softcrawl.provenance import git_commit, write_summary

ROOT = Path(__file__).resolve().parents[1]


def test_write_summary_adds_version_and_commit(tmp_path):
    path = write_summary(tmp_path / "summary.json", {"x": 1.0})
    data = json.loads(path.read_text())
    assert data["x"] == 1.0
    assert data["provenance"]["softcrawl"] == __version__
    commit = data["provenance"]["commit"]
    assert commit == "unknown" or re.match(r"^[0-9a-f]{40}( \+ local changes)?$", commit)


def test_outside_a_checkout_the_commit_is_unknown(tmp_path):
    git_commit.cache_clear()
    try:
        assert git_commit(tmp_path) == "unknown"
    finally:
        git_commit.cache_clear()


def test_no_module_writes_a_summary_json_another_way():
    """A writer of summary.json goes through write_summary (so that it carries its provenance)."""
    offenders = []
    for folder in ("softcrawl", "fem", "geometry", "studies"):
        for path in (ROOT / folder).rglob("*.py"):
            for line in path.read_text().splitlines():
                if "summary.json" in line and re.search(r"jsonio\.write\(|json\.dump\(|write_text\(", line):
                    offenders.append(f"{path.relative_to(ROOT)}: {line.strip()}")
    assert not offenders, offenders


def test_a_command_pins_the_commit_it_started_from(monkeypatch):
    """A long run writes its summary hours after it started, from code loaded at the start: the
    commit is read as the command starts (the 60 and 40 mm elbow runs of record 087 ran for two
    hours while the checkout moved on, and recorded the later commit)."""
    from softcrawl.studies import cli

    seen = []

    class Args:
        command = "x"

        @staticmethod
        def func(args):
            seen.append(git_commit.cache_info().currsize)

    git_commit.cache_clear()
    monkeypatch.setattr(cli, "_parse", lambda argv: Args())
    try:
        assert cli.main(["x"]) == 0
        assert seen == [1]  # the commit was read before the command's work began
    finally:
        git_commit.cache_clear()
