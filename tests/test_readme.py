"""The documented example commands run as written, and print what their comments say.

The pages are README.md and the docs pages that took over its examples (`DOCS`: docs/results.md,
docs/sweeps.md). Every `softcrawl ...` line of a ```bash block (outside the results-regeneration
loop, which takes
35 minutes and is documented as such) is run in a temporary folder (the autouse fixture of
conftest.py makes it the working directory, so `--out out/...` writes there). A decimal number with
a unit in the line's comment ("2.505 kg", "118.032 mm"; whole numbers are mostly inputs, figures
in parentheses context) must appear in what the command prints. Commands that take minutes are
marked slow (`SLOW`)."""

import re
import shlex
from pathlib import Path

import pytest

from softcrawl.studies.cli import main

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
#: The pages whose ```bash examples are run: the README and the docs pages its examples moved to.
DOCS = (README, ROOT / "docs" / "results.md", ROOT / "docs" / "sweeps.md")
#: Commands of the documented examples that take minutes (run with -m slow).
SLOW = ("--search bfs", "identify-feet", "crawl --quick")


def _examples(page: Path = README) -> list[tuple[str, str]]:
    text = page.read_text()
    out = []
    for block in re.findall(r"```bash\n(.*?)```", text, flags=re.S):
        if "\\\n" in block:  # the multi-line results-regeneration loop
            continue
        for line in block.splitlines():
            command, _, comment = line.partition("#")
            for part in command.split("&&"):
                part = part.strip()
                if part.startswith("softcrawl "):
                    out.append((part, comment.strip()))
    return out


EXAMPLES = [example for page in DOCS for example in _examples(page)]


def test_the_readme_has_examples():
    assert len(_examples(README)) >= 8


def test_every_documented_page_exists():
    for page in DOCS:
        assert page.exists(), page


@pytest.mark.parametrize(
    "command, comment",
    [pytest.param(c, m, marks=[pytest.mark.slow] if any(s in c for s in SLOW) else []) for c, m in EXAMPLES],
    ids=[c[:60] for c, _ in EXAMPLES],
)
def test_readme_example_runs_and_prints_what_its_comment_says(command, comment, capsys):
    code = main(shlex.split(command)[1:])
    printed = capsys.readouterr().out
    assert code in (0, 1), printed  # 1: a plan that does not pass the pipe (a result, reported)
    said = re.sub(r"\([^)]*\)", "", comment)  # figures in parentheses are context, not output
    for figure in re.findall(r"\d+\.\d+ (?:kg|mm|N)\b", said):  # decimals: outputs, not inputs
        assert figure in printed, f"the docs say {figure!r}; the command printed:\n{printed}"


def test_the_quick_start_writes_what_the_readme_lists():
    assert main(["epsa", "--quick", "--pressures", "0:40:10", "--out", "out/epsa"]) == 0
    out = Path("out/epsa")
    for name in ("curve.csv", "summary.json", "epsa.png", "vtu/step.pvd", "vtu/winding.pvd"):
        assert (out / name).exists(), name
    assert len(list((out / "vtu").glob("step_*.vtu"))) == 5  # 0 kPa reference + 4 pressures
