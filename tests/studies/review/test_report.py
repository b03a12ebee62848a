"""`softcrawl report` on the committed results/: every section and image is in the page, a section
whose results are missing names its command, and a real headless browser renders it."""

import os
import re
import shutil
import subprocess
from pathlib import Path

import pytest

from softcrawl.studies.cli import main
from softcrawl.studies.review.report import SECTIONS

RESULTS = Path(__file__).resolve().parents[3] / "results"


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    out = tmp_path_factory.mktemp("report")
    assert main(["report", "--results", str(RESULTS), "--out", str(out)]) == 0
    return out / "index.html"


def test_every_section_and_image_is_in_the_page(report):
    text = report.read_text()
    for sid, _heading, _ in SECTIONS:
        assert f'<section id="{sid}">' in text, sid
    images = re.findall(r'<img alt="[^"]*" src="data:image/png;base64,', text)
    # the three renders, the study figures (2 + 2 + 4 + 1), the fit and the calibration
    assert len(images) >= 14
    assert "http://" not in text and "https://" not in text  # nothing to fetch
    assert "what limits" in text.lower() and "limit point at" in text
    assert 'class="missing"' not in text.split('id="provenance"')[0].split('id="benchmarks"')[0]


def test_missing_results_name_their_command(tmp_path):
    empty = tmp_path / "results"
    empty.mkdir()
    assert main(["report", "--results", str(empty), "--out", str(tmp_path / "r")]) == 0
    text = (tmp_path / "r" / "index.html").read_text()
    assert text.count('class="missing"') >= 6
    commands = ("softcrawl study fiber-turns", "softcrawl calibrate", "softcrawl verify", "--render")
    for command in (*commands, "softcrawl crawl", "softcrawl study workspace", "softcrawl robot"):
        assert command in text


def test_robot_and_crawl_sections_carry_the_committed_figures(report):
    text = report.read_text()
    robot = text.split('<section id="robot">')[1].split("</section>")[0]
    crawl = text.split('<section id="crawl">')[1].split("</section>")[0]
    assert "robot-table1/robot.png" in robot
    # the mu = 0.3 run of results/crawl on the revolved feet: two cycles, steady stride 7.78 mm at
    # 3.89 mm/s, Table 2 18.3; the same run on the pytetwild feet: 6.20 mm at 3.10 mm/s
    row = crawl.split("forward-70-mu0.3-2cycles</td>")[1].split("</tr>")[0]
    assert "7.78" in row and "3.89" in row and "18.3" in row and "revolved, 48 sectors" in row
    old = crawl.split("forward-70-mu0.3-2cycles-tetwild</td>")[1].split("</tr>")[0]
    assert "6.2" in old and "3.1" in old and "pytetwild" in old
    assert crawl.count("data:image/png;base64,") >= 5  # one figure per committed run


def test_report_of_a_folder_that_does_not_exist_is_an_input_error(tmp_path, capsys):
    assert main(["report", "--results", str(tmp_path / "nope"), "--out", str(tmp_path / "r")]) == 2
    assert "results" in capsys.readouterr().err


def _chromium():
    for name in ("chromium", "chromium-browser", "google-chrome"):
        if shutil.which(name):
            return shutil.which(name)
    return None


@pytest.mark.skipif(_chromium() is None, reason="no headless Chromium (Debian: apt-get install chromium)")
def test_headless_chromium_renders_every_section_and_image(report, tmp_path):
    flags = [
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-background-networking",
        "--no-first-run",
        f"--user-data-dir={tmp_path / 'profile'}",
    ]
    url = report.resolve().as_uri()
    env = dict(os.environ, HOME=str(tmp_path))
    dom = subprocess.run(
        [_chromium(), *flags, "--virtual-time-budget=10000", "--dump-dom", url],
        capture_output=True,
        text=True,
        timeout=180,
        env=env,
    ).stdout
    for sid, _, _ in SECTIONS:
        assert f'id="{sid}"' in dom, sid
    loaded = re.search(r'data-images-loaded="(\d+)/(\d+)"', dom)
    assert loaded, "the page's image check did not run"
    assert int(loaded.group(1)) == int(loaded.group(2)) >= 14  # every embedded image decoded
    # the answer on the first screen, the page short with every section collapsed, no script or
    # console error (the page's own script records them: studies.html.SCRIPT)
    assert 'id="headline"' in dom and "Design basis" in dom
    assert 0 < int(re.search(r'data-headline-bottom="(\d+)"', dom).group(1)) < 1500
    assert int(re.search(r'data-page-height="(\d+)"', dom).group(1)) < 20_000
    assert re.search(r'data-errors="(\d+)"', dom).group(1) == "0"
    shot = tmp_path / "report.png"
    subprocess.run(
        [_chromium(), *flags, "--window-size=1280,3000", f"--screenshot={shot}", url],
        capture_output=True,
        timeout=180,
        env=env,
    )
    assert shot.exists() and shot.stat().st_size > 50_000


def test_the_headline_states_the_basis_and_the_counts_from_the_files(report):
    import json

    text = report.read_text()
    head = text.split('id="headline"')[1].split("</div>")[0]
    cases = json.loads((RESULTS / "verify" / "verify.json").read_text())["cases"]
    assert f"solver verification {sum(c['passed'] for c in cases)} of {len(cases)} cases pass" in head
    assert "Design basis" in head and "mu = 0.0638 MPa" in head and "Robot:" in head and "Crawl:" in head
    answer = text.split('<section id="answer">')[1].split("</section>")[0]
    assert "none" not in re.findall(r"<td>([^<]*)</td>", answer)  # one spelling: "no limit point"
    assert "no limit point" in answer
    assert "<details" in text and text.count("<section id=") == len(SECTIONS)


def test_every_provenance_command_parses():
    """Each command of the provenance table parses with the CLI's own parser (parse only, no
    work), and a `softcrawl study` command passes the study's option check."""
    import shlex

    from softcrawl.studies import registry
    from softcrawl.studies.cli import build_parser
    from softcrawl.studies.commands.study import _applies
    from softcrawl.studies.review.provenance import provenance_rows

    rows = provenance_rows(RESULTS)
    assert len(rows) >= 30
    for row in rows:
        assert '"None"' not in row["command"], row
        args = build_parser().parse_args(shlex.split(row["command"])[1:])
        if args.command == "study":
            _applies(args, registry.get(args.name))
    materials = {row["result"].split("/")[0]: row["material"] for row in rows}
    assert materials["groove"] == materials["foot"] == "rubber-70a"  # not the silicone
    assert "@mu=" in materials["robot-rings"]  # the modulus it ran with


def test_the_optimise_feet_block_carries_its_confirm_crawls(report):
    """results/optimise-feet/rubber-wedge4: the command with its wedge, and confirm.md's table (the
    109 deg design crawls at 20.297 mm/s since fem.p2_mapping, docs/decisions/086-curved-facet-points.md)."""
    text = report.read_text()
    block = text.split("optimise-feet: rubber-wedge4</h3>")[1].split("<h3")[0]
    assert "--wedge 4" in block
    confirm = block.split("the best designs crawled at 70 mm")[1]
    row = confirm.split("<td>109.0 deg, 2.33 mm, rubber-50a</td>")[1].split("</tr>")[0]
    assert "43.2666;40.5935" in row and "20.297" in row
