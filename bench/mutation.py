"""Mutation testing (issue 32): run mutmut on a chosen set of modules, print the kill rate per module.

    python bench/mutation.py                          # every group below, one after the other
    python bench/mutation.py units rules              # chosen groups
    python bench/mutation.py --list                   # the groups, their modules and their tests
    python bench/mutation.py --report units           # the scores of the last run, no new run
    python bench/mutation.py rules --again --survivors  # re-run the survivors against the checkout's tests

Not part of the default CI run: it runs the group's tests once per mutant (3-20 minutes a group on
2 shared cores; an --again run 1-7 minutes). Needs mutmut 3 (`pip install -e '.[mutation]'`).
Each group runs its modules' targeted fast tests only (`GROUPS`); solves of more than a few
seconds are deselected there.

The report prints each module's kill rate as measured and without the named equivalent survivors of
bench/mutation-equivalents.toml (mutmut name -> why the mutant changes nothing observable); with
--survivors it lists every survivor with its reason, and names an equivalent that is now killed as
stale. `--again` keeps the stage's mutants and results, copies the checkout's tests in and re-runs
only the mutants not killed (mutmut forgets the other results of a named run: they are put back).

Why a staged copy: mutmut 3 copies the source into ``mutants/`` and names every mutant after its
file's path (``fem/contact.py`` -> ``fem.contact.x_...``); the trampoline it plants only switches a
mutant on when that name matches the module the tests import. This project's setup.py maps the
folders fem/, geometry/ and studies/ to ``softcrawl.fem``, ``softcrawl.geometry`` and
``softcrawl.studies``, so in the checkout the names never match (and the editable install would
import the unmutated folders). The script therefore builds, per group, ``$SOFTCRAWL_MUTATION_DIR/<group>/``
(default /tmp/softcrawl-mutation, outside the checkout)
with the installed layout written out (``softcrawl/``, ``softcrawl/fem/``, ``softcrawl/geometry/``,
``softcrawl/studies/``) plus tests/, results/, docs/, examples/ and pyproject.toml, adds the
group's modules (``only_mutate``) and tests (``pytest_add_cli_args_test_selection``) to the
``[tool.mutmut]`` table of pyproject.toml, and runs ``mutmut run --max-children N`` there. The
mutated package in ``mutants/`` comes first on sys.path, ahead of the editable install's finder
(appended to sys.meta_path), so the tests import the mutants.
mutants/ is gitignored in case mutmut is run in the checkout.

Kill rate = (killed + timeout) / (every mutant checked); "no tests" and "survived" count against.
Survivors are listed with `--survivors` (then `cd /tmp/softcrawl-mutation/<group> && mutmut show NAME`).
"""

from __future__ import annotations

import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
import tomllib
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
#: Outside the checkout: the project's tests scan every file under it (tests/test_docs.py).
STAGE = Path(os.environ.get("SOFTCRAWL_MUTATION_DIR", Path(tempfile.gettempdir()) / "softcrawl-mutation"))
#: folder in the checkout -> folder in the installed package (setup.py's MAPPED).
LAYOUT = {
    "softcrawl": "softcrawl",
    "fem": "softcrawl/fem",
    "geometry": "softcrawl/geometry",
    "studies": "softcrawl/studies",
}
EQUIVALENTS = ROOT / "bench" / "mutation-equivalents.toml"
ALSO = ("tests", "results", "docs", "examples", "README.md", "pyproject.toml")

#: group -> (modules as checkout paths, tests that guard them).
GROUPS = {
    "units": (["softcrawl/units.py"], ["tests/test_units.py", "tests/test_identities.py"]),
    "post": (
        ["studies/crawl/outputs.py", "studies/foot/outputs.py", "studies/sweeps/tables.py", "fem/post.py"],
        [
            "tests/fem/test_post.py",
            "tests/fem/test_post_state.py",
            "tests/studies/foot/test_foot_outputs.py",
            "tests/studies/crawl/test_crawl_outputs.py",
            "tests/studies/sweeps/test_sweep_records.py",
            "tests/studies/foot/test_contact_runs.py",
            "tests/test_identities.py",
        ],
    ),
    "rules": (
        [
            "studies/robot_fe/rules.py",
            "studies/epsa/rules.py",
            "studies/epsa/linearity.py",
            "studies/foot/groove_rule.py",
            "studies/table1_row.py",
        ],
        [
            "tests/studies/robot_fe/test_rules_flip.py",
            "tests/studies/epsa/test_linearity_flip.py",
            "tests/studies/robot_fe/test_robot_rules.py",
            "tests/studies/epsa/test_rules.py",
            "tests/studies/foot/test_groove_study.py",
            "tests/studies/foot/test_groove_rule_rows.py",
            # a 20 s groove solve: per mutant too slow; the rule's own tests take its outputs as given
            "--deselect",
            "tests/studies/foot/test_groove_study.py::test_groove_drag_normal_force_and_plateau",
        ],
    ),
    "fem": (
        ["fem/axial_link.py", "fem/chamber.py"],
        [
            "tests/fem/test_chamber_state.py",
            "tests/fem/test_axial_link_state.py",
            "tests/fem/test_axial_link.py::test_link_tangent_matches_finite_differences",
            "tests/fem/test_axial_link.py::test_bad_links_name_the_parameter",
            "tests/fem/test_chambers.py",
            # the solves of test_axial_link.py (contact, 1-5 s each) and a 12 s path through a limit
            # point are per mutant too slow on a shared machine; the prescribed-state tests guard the lines
            "--deselect",
            "tests/fem/test_chambers.py::test_volume_control_along_a_two_chamber_load_direction_passes_one_limit_point",
        ],
    ),
    "contact": (
        ["fem/contact.py", "fem/contact_law.py"],
        [
            "tests/fem/test_contact_report.py",
            "tests/fem/test_contact_term_state.py",
            "tests/fem/test_contact_law_state.py",
            "tests/fem/test_contact.py",
            # the verification cases are solves (1-6 s each, 956 mutants: hours on a shared machine);
            # the pointwise law, the term's arrays and the report are checked at prescribed states
            "-k",
            "not verification_case and not hertz",
        ],
    ),
    "stages": (
        ["fem/contact_stages.py"],
        [
            "tests/fem/test_contact_stages_driver.py",
            "tests/fem/test_contact_stages_cursor.py",
            "tests/fem/test_contact_stages.py",
            "tests/fem/test_contact_stages_resume.py",
            # two resumed block solves (4 s and 1 s, 8-40 s per mutant on the loaded machine: the first
            # run checked 206 of 387 mutants in 15 min); the scripted-solver tests guard the same lines
            "--deselect",
            "tests/fem/test_contact_stages_resume.py::test_a_run_resumed_after_any_sub_step_ends_where_the_uninterrupted_run_ends",
            "--deselect",
            "tests/fem/test_contact_stages_resume.py::test_setting_friction_again_on_the_resumed_stage_would_change_the_result",
        ],
    ),
    "verification": (
        ["fem/contact_verification.py"],
        [
            "tests/fem/test_contact_verification_results.py",
            "tests/fem/test_contact_verification_setup.py",
            "tests/fem/test_contact_hertz_parts.py",
            "tests/fem/test_contact_report.py",
            "tests/fem/test_contact_term_state.py",
            "tests/fem/test_contact.py",
            # the verification cases themselves, 0.1-3 s each; the two Hertz solves (10-30 s each) are
            # per mutant too slow on a shared machine: test_contact_hertz_parts.py guards their lines
            "--deselect",
            "tests/fem/test_contact.py::test_hertz_line_contact",
            "--deselect",
            "tests/fem/test_contact.py::test_verification_cases_hold_with_a_smoothed_normal_law[hertz-0.001]",
        ],
    ),
}


#: Per group, [tool.mutmut] settings that replace the project's: a mutant of the stage loop's step
#: control (h not halved, t not advanced) loops until mutmut's CPU limit, (tests' time + constant) x
#: multiplier x 2 s; with the defaults (10 s, 5) that is 2-3 minutes per such mutant.
SETTINGS = {"stages": {"timeout_constant": 1.0, "timeout_multiplier": 2.0}}


def staged(path: str) -> str:
    """A checkout path (fem/contact.py) as a path in the installed layout (softcrawl/fem/contact.py)."""
    head, _, rest = path.partition("/")
    return f"{LAYOUT[head]}/{rest}" if head in LAYOUT else path


def stage(group: str, modules: list[str], tests: list[str]) -> Path:
    where = STAGE / group
    if where.exists():
        shutil.rmtree(where)
    ignore = shutil.ignore_patterns("__pycache__", "*.egg-info", "mesh", "*.vtu")
    for src, dst in LAYOUT.items():
        shutil.copytree(ROOT / src, where / dst, ignore=ignore, dirs_exist_ok=True)
    for name in ALSO:
        src = ROOT / name
        if src.is_dir():
            shutil.copytree(src, where / name, ignore=ignore)
        elif src.exists():
            shutil.copy2(src, where / name)
    configure(where, modules, tests, SETTINGS.get(group))
    return where


def configure(where: Path, modules: list[str], tests: list[str], settings: dict | None = None) -> None:
    """The checkout's pyproject.toml with the group's modules and tests added to [tool.mutmut], and
    the group's `SETTINGS` in place of the project's."""
    text = (ROOT / "pyproject.toml").read_text()
    for key, value in (settings or {}).items():
        text, n = re.subn(rf"^{key} = .*$", f"{key} = {json.dumps(value)}", text, count=1, flags=re.M)
        if n != 1:
            raise SystemExit(f"pyproject.toml [tool.mutmut] has no {key}")
    extra = f"only_mutate = {json.dumps([staged(m) for m in modules])}\n"
    extra += f"pytest_add_cli_args_test_selection = {json.dumps(tests)}\n"
    if "[tool.mutmut]\n" not in text:
        raise SystemExit("pyproject.toml has no [tool.mutmut] table")
    (where / "pyproject.toml").write_text(text.replace("[tool.mutmut]\n", "[tool.mutmut]\n" + extra, 1))


def restage_tests(group: str, modules: list[str], tests: list[str]) -> Path:
    """`--again`: the checkout's tests and the group's test selection copied into the last run's
    stage, whose mutants and results are kept."""
    where = STAGE / group
    if not (where / "mutants").exists():
        raise SystemExit(f"{group}: no earlier run in {where}; run it without --again first")
    shutil.rmtree(where / "tests")
    shutil.copytree(ROOT / "tests", where / "tests", ignore=shutil.ignore_patterns("__pycache__"))
    configure(where, modules, tests, SETTINGS.get(group))
    return where


def statuses(where: Path, modules: list[str]) -> dict[str, dict[str, int | None]]:
    """Module -> {mutant name: exit code} from mutmut's .meta files."""
    out = {}
    for m in modules:
        meta = where / "mutants" / (staged(m) + ".meta")
        out[m] = json.loads(meta.read_text())["exit_code_by_key"] if meta.exists() else {}
    return out


def keep_results(where: Path, before: dict[str, dict[str, int | None]]) -> None:
    """Put back the earlier exit codes that a run of named mutants reset to None."""
    for m, old in before.items():
        meta = where / "mutants" / (staged(m) + ".meta")
        data = json.loads(meta.read_text())
        codes = data["exit_code_by_key"]
        for k, c in old.items():
            if codes.get(k) is None and c is not None:
                codes[k] = c
        meta.write_text(json.dumps(data, indent=4))


KILLED = {1, 3, 36, 24, -24, 152, 255, 37}  # killed, pytest internal error, timeouts, type check


def equivalents() -> dict[str, str]:
    """Named equivalent mutants (bench/mutation-equivalents.toml): mutmut name -> reason."""
    return tomllib.loads(EQUIVALENTS.read_text())["equivalent"] if EQUIVALENTS.exists() else {}


def report(group: str, modules: list[str], survivors: bool) -> list[tuple[str, int, int]]:
    """Per module: the kill rate as measured, and without the named equivalent survivors."""
    where = STAGE / group
    same = equivalents()
    rows = []
    for m, codes in statuses(where, modules).items():
        checked = {k: c for k, c in codes.items() if c is not None and c != 34}
        killed = sum(c in KILLED for c in checked.values())
        rows.append((m, killed, len(checked)))
        rate = f"{100 * killed / len(checked):5.1f} %" if checked else "  n/a  "
        named = sum(k in same for k, c in checked.items() if c not in KILLED)
        left = len(checked) - named
        net = f"{100 * killed / left:5.1f} %" if left else "  n/a  "
        kinds = Counter(
            "killed" if c in KILLED else {0: "survived", 5: "no tests", 33: "no tests"}.get(c, str(c))
            for c in checked.values()
        )
        print(
            f"{group:8s} {m:34s} {rate}  {killed:4d}/{len(checked):<4d}  "
            f"without {named} named equivalents {net}  {dict(kinds)}"
        )
        if survivors:
            for k, c in sorted(checked.items()):
                if c not in KILLED:
                    print(f"    {k}  (exit {c}){'  equivalent: ' + same[k] if k in same else ''}")
        stale = [
            k for k in same if k.startswith(staged(m)[:-3].replace("/", ".") + ".") and codes.get(k) in KILLED
        ]
        for k in stale:
            print(f"    stale equivalent (now killed): {k}")
    return rows


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("groups", nargs="*", help=f"groups to run (default all: {', '.join(GROUPS)})")
    ap.add_argument("--max-children", type=int, default=1, help="mutmut workers (default 1)")
    ap.add_argument("--list", action="store_true", help="print the groups and exit")
    ap.add_argument("--report", action="store_true", help="only print the scores of the last run")
    ap.add_argument("--survivors", action="store_true", help="list the surviving mutants")
    ap.add_argument(
        "--again",
        action="store_true",
        help="keep the last run's mutants and results, copy the checkout's tests in, "
        "re-run the mutants not killed",
    )
    args = ap.parse_args(argv)
    groups = args.groups or list(GROUPS)
    if args.list:
        for g in groups:
            print(g, "modules:", *GROUPS[g][0], "tests:", *GROUPS[g][1])
        return 0
    for g in groups:
        modules, tests = GROUPS[g]
        if not args.report:
            cmd = ["mutmut", "run", "--max-children", str(args.max_children)]
            if args.again:
                where = restage_tests(g, modules, tests)
                left = [
                    k
                    for codes in statuses(where, modules).values()
                    for k, c in codes.items()
                    if c not in KILLED
                ]
                if not left:
                    report(g, modules, args.survivors)
                    continue
                cmd += left
            else:
                where = stage(g, modules, tests)
            before = statuses(where, modules) if args.again else {}
            t0 = time.perf_counter()
            with open(where / "mutmut.log", "w") as log:
                done = subprocess.run(cmd, cwd=where, stdout=log, stderr=subprocess.STDOUT)
            if args.again:  # mutmut forgets the results of the mutants it was not asked to run
                keep_results(where, before)
            print(f"{g}: mutmut run exit {done.returncode} in {time.perf_counter() - t0:.0f} s")
            if done.returncode != 0:
                print((where / "mutmut.log").read_text()[-3000:], file=sys.stderr)
        report(g, modules, args.survivors)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
