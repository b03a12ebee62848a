"""Every docs link and section reference resolves (pure text: nothing of the package is imported).

- Every relative Markdown link (and image) in README.md, CONTRIBUTING.md, docs/**/*.md and
  results/**/README.md points to an existing file or folder, and a `#anchor` to a heading of the
  target page (GitHub's slug rules).
- Every textual reference in the repository's .py and .md files of the forms `DESIGN.md section N`,
  `DESIGN.md N`, `DESIGN.md, section N`, `DESIGN.md sections N and M` names a numbered heading of
  docs/DESIGN.md; `DESIGN.md, "Heading"` and `DESIGN.md ("Heading")` name a heading of it; and
  `docs/decisions/NNN...` names an existing decision record.
"""

import os
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DESIGN = ROOT / "docs" / "DESIGN.md"
DECISIONS = ROOT / "docs" / "decisions"
#: Folders never scanned: tool and environment folders, build output.
SKIP_DIRS = {"build", "dist", "node_modules", "__pycache__", "venv"}


def _walk(suffix: str) -> list[Path]:
    out = []
    for folder, dirs, files in os.walk(ROOT):
        dirs[:] = sorted(
            d for d in dirs if not d.startswith(".") and d not in SKIP_DIRS and not d.endswith(".egg-info")
        )
        out += [Path(folder) / f for f in sorted(files) if f.endswith(suffix)]
    return out


def _doc_pages() -> list[Path]:
    pages = [ROOT / "README.md", ROOT / "CONTRIBUTING.md"]
    pages += sorted((ROOT / "docs").rglob("*.md"))
    pages += sorted((ROOT / "results").rglob("README.md"))
    return [p for p in pages if p.exists()]


def _without_code(text: str) -> str:
    """The text with fenced code blocks and inline code spans blanked (links there are not links)."""
    text = re.sub(r"^(```|~~~).*?^\1[^\n]*$", "", text, flags=re.S | re.M)
    return re.sub(r"`[^`\n]*`", "", text)


def slug(heading: str) -> str:
    """GitHub's anchor of a heading: lower case, punctuation other than '-' and '_' dropped,
    spaces to '-' (markup characters dropped with the punctuation)."""
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", heading.strip())  # a link's text only
    text = text.lower()
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def anchors(page: Path) -> set[str]:
    out: set[str] = set()
    seen: dict[str, int] = {}
    text = re.sub(r"^(```|~~~).*?^\1[^\n]*$", "", page.read_text(), flags=re.S | re.M)
    for match in re.finditer(r"^#{1,6}\s+(.*?)\s*#*\s*$", text, flags=re.M):
        base = slug(match.group(1))
        n = seen.get(base, 0)
        out.add(base if n == 0 else f"{base}-{n}")
        seen[base] = n + 1
    return out


def links(page: Path) -> list[str]:
    text = _without_code(page.read_text())
    found = re.findall(r"!?\[[^\]]*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)", text)
    found += re.findall(r"^\s*\[[^\]]+\]:\s*(\S+)", text, flags=re.M)  # reference definitions
    return [t for t in found if not re.match(r"^[a-z][a-z0-9+.-]*:", t, flags=re.I)]


PAGES = _doc_pages()


def test_there_are_pages_and_a_design_map():
    assert DESIGN.exists() and (DECISIONS / "README.md").exists()
    assert len(PAGES) >= 5


@pytest.mark.parametrize("page", PAGES, ids=[str(p.relative_to(ROOT)) for p in PAGES])
def test_every_relative_link_resolves(page):
    broken = []
    for target in links(page):
        path, _, anchor = target.partition("#")
        resolved = (page.parent / path).resolve() if path else page
        if not resolved.exists():
            broken.append(f"{target}: no such file")
        elif anchor and resolved.is_file() and resolved.suffix == ".md" and anchor not in anchors(resolved):
            broken.append(f"{target}: no heading #{anchor} in {resolved.relative_to(ROOT)}")
    assert not broken, "\n".join(broken)


def design_sections() -> set[str]:
    """The numbers of docs/DESIGN.md's numbered headings ("## 3.1 Title" -> "3.1")."""
    text = DESIGN.read_text()
    return set(re.findall(r"^#{1,6}\s+(\d+[a-z]?(?:\.\d+)*)\.?\s", text, flags=re.M))


def design_headings() -> set[str]:
    return {m.strip().lower() for m in re.findall(r"^#{1,6}\s+(.*)$", DESIGN.read_text(), flags=re.M)}


#: `DESIGN.md section 13`, `DESIGN.md 7.2`, `DESIGN.md, section 8`, `DESIGN.md sections 3.3 and 5.1`,
#: across a line break and a comment marker (`#`, `#:`) too.
SECTION_REF = re.compile(
    r"DESIGN\.md,?(?:\s*#:?)?\s+(?:sections?(?:\s*#:?)?\s+)?(\d+[a-z]?(?:\.\d+)?)(?:\s+and\s+(\d+[a-z]?(?:\.\d+)?))?\b"
)
HEADING_REF = re.compile(r"DESIGN\.md(?:,\s*|\s*\()\"([^\"]+)\"")
DECISION_REF = re.compile(r"docs/decisions/(\d{3}[\w.-]*)")


def _references(paths: list[Path]) -> list[str]:
    sections, headings = design_sections(), design_headings()
    records = {p.name for p in DECISIONS.glob("[0-9][0-9][0-9]-*.md")}
    bad = []
    for path in paths:
        if path.resolve() in (DESIGN, Path(__file__).resolve()):  # this file quotes the forms
            continue
        text = path.read_text(errors="replace")
        where = path.relative_to(ROOT)
        for m in SECTION_REF.finditer(text):
            for number in filter(None, m.groups()):
                if number not in sections:
                    bad.append(f"{where}: {m.group(0)!r}: docs/DESIGN.md has no section {number}")
        for m in HEADING_REF.finditer(text):
            if " ".join(m.group(1).split()).lower() not in headings:
                bad.append(f"{where}: {m.group(0)!r}: docs/DESIGN.md has no heading {m.group(1)!r}")
        for m in DECISION_REF.finditer(text):
            name = m.group(1).rstrip(".")
            if name not in records and not (name.endswith(".md") is False and f"{name}.md" in records):
                bad.append(f"{where}: {m.group(0)!r}: no such decision record")
    return bad


def test_section_and_decision_references_in_markdown_resolve():
    bad = _references(_walk(".md"))
    assert not bad, "\n".join(bad)


def test_section_and_decision_references_in_python_resolve():
    bad = _references(_walk(".py"))
    assert not bad, "\n".join(bad)
