"""Exit codes of a signal: 128 + the signal (130 Ctrl-C, 143 SIGTERM) in a single command, as in
`softcrawl study` (tests/studies/sweeps/test_faults.py); and the README and docs/DESIGN.md say so."""

from __future__ import annotations

import re
import signal
from pathlib import Path

import pytest

from softcrawl.studies.cli import EXIT_INTERRUPTED, EXIT_TERMINATED
from tests.studies.sweeps.cli_runs import ROOT, start


@pytest.mark.parametrize(
    "sig, code, line",
    [
        (signal.SIGTERM, 143, "softcrawl epsa: interrupted (SIGTERM)"),
        (signal.SIGINT, 130, "softcrawl epsa: interrupted"),
    ],
)
def test_a_signal_during_a_single_command_is_one_line_and_128_plus_the_signal(tmp_path, sig, code, line):
    proc = start(["epsa", "--quick", "--pressures", "0:100:2", "--out", str(tmp_path / "e")])
    first = proc.stdout.readline()  # the command runs (its header line is printed)
    assert first.startswith("ePSA "), first
    proc.send_signal(sig)
    out, err = proc.communicate(timeout=120)
    assert proc.returncode == code == 128 + sig
    assert err.splitlines() == [line], err


def test_the_docs_state_the_exit_codes_the_code_uses():
    assert (EXIT_INTERRUPTED, EXIT_TERMINATED) == (130, 143)
    for doc in ("README.md", "docs/DESIGN.md"):
        text = " ".join((ROOT / doc).read_text().split())
        section = text[text.index("## Errors and exit codes") :]
        assert re.search(r"128 \+ the signal when interrupted \(130 Ctrl-C, 143 SIGTERM[;,)]", section), doc
    assert "143 for SIGTERM" in " ".join(Path(ROOT / "studies/cli.py").read_text().split())
