"""Building blocks of the self-contained HTML design review (`studies.review.report`).

Self-contained: every image is a base64 `data:` URI (PNG, downscaled to `MAX_WIDTH` pixels and
reduced to a 256-colour palette, which keeps plots and renders sharp at a fraction of the size),
the style sheet is inline, and nothing is fetched from a network. A small inline script counts
the images that the browser decoded and writes the count on the page (`data-images-loaded`), the
page's height, where the headline ends (`data-page-height`, `data-headline-bottom`, pixels, every
section collapsed) and the number of script errors and console errors (`data-errors`), so a
headless browser can check that every figure shows and that the answer is on the first screen.

The page opens on its answer (a headline), then a table of contents with one entry per section
and sub-entries for its <h3> blocks; every section is a closed <details>, which a link of the
contents opens. Markdown (results/*.md, decision records) is rendered by markdown-it-py, its
headings moved below the page's own <h3>, so that they stay out of the contents.
"""

from __future__ import annotations

import base64
import csv
import html
import io
import re
from functools import lru_cache
from pathlib import Path

#: Widest embedded image (pixels).
MAX_WIDTH = 1100

STYLE = """
body { font-family: system-ui, sans-serif; max-width: 1180px; margin: 0 auto; padding: 0 18px 60px;
       color: #1b1b1b; line-height: 1.45; }
h1 { margin-top: 28px; } h2 { border-bottom: 2px solid #d0d7de; padding-bottom: 4px; margin-top: 40px; }
nav > ol > li { margin: 3px 0; } nav ol ul { font-size: 13px; columns: 3; margin: 2px 0 6px; }
table { border-collapse: collapse; margin: 10px 0; font-size: 13px; }
th, td { border: 1px solid #c9d1d9; padding: 3px 7px; text-align: left; vertical-align: top; }
th { background: #f1f4f7; } img { max-width: 100%; border: 1px solid #e1e4e8; margin: 6px 0; }
code, pre { background: #f5f7f9; font-size: 12.5px; } pre { padding: 8px; overflow-x: auto; }
.missing { background: #fff4e5; border-left: 4px solid #f0a020; padding: 8px 12px; }
.answer { background: #eef7ee; border-left: 4px solid #2e8b57; padding: 8px 14px; }
.figrow { display: flex; gap: 8px; flex-wrap: wrap; } .figrow figure { flex: 1 1 300px; margin: 0; }
figcaption { font-size: 13px; color: #444; }
.headline { background: #eef4fb; border-left: 5px solid #1f5fa8; padding: 6px 16px; font-size: 15.5px; }
.headline li { margin: 3px 0; }
details.section > summary { cursor: pointer; font-size: 1.35em; font-weight: 600; margin-top: 18px;
       border-bottom: 2px solid #d0d7de; padding-bottom: 4px; }
.figgrid { display: grid; grid-template-columns: repeat(3, 1fr); gap: 8px; }
.figgrid figure { margin: 0; } .figgrid img { width: 100%; }
.wide img { width: 100%; }
"""

SCRIPT = """
var pageErrors = [];
window.addEventListener('error', function (e) { pageErrors.push(String(e.message || e)); });
(function () {
  var log = console.error;
  console.error = function () {
    pageErrors.push(Array.prototype.join.call(arguments, ' '));
    log.apply(console, arguments);
  };
})();
window.addEventListener('load', function () {
  var imgs = Array.prototype.slice.call(document.images);
  var ok = imgs.filter(function (i) { return i.complete && i.naturalWidth > 0; }).length;
  var body = document.body, head = document.getElementById('headline');
  body.setAttribute('data-images-loaded', ok + '/' + imgs.length);
  body.setAttribute('data-page-height', String(document.documentElement.scrollHeight));
  if (head) {
    var bottom = head.getBoundingClientRect().bottom + window.scrollY;
    body.setAttribute('data-headline-bottom', String(Math.round(bottom)));
  }
  body.setAttribute('data-errors', String(pageErrors.length));
});
function openTarget() {
  var el = location.hash && document.getElementById(location.hash.slice(1));
  if (!el) { return; }
  var own = el.querySelector(':scope > details');
  if (own) { own.open = true; }
  for (var up = el; up; up = up.parentElement) { if (up.tagName === 'DETAILS') { up.open = true; } }
  el.scrollIntoView();
}
window.addEventListener('hashchange', openTarget);
window.addEventListener('DOMContentLoaded', openTarget);
"""


def esc(text) -> str:
    return html.escape(str(text))


class Html(str):
    """A table cell that is already HTML (`table` does not escape it)."""


def image(path: Path, alt: str, max_width: int = MAX_WIDTH) -> str:
    """<img> with the PNG at `path` embedded (downscaled, palette-reduced)."""
    from PIL import Image

    with Image.open(path) as im:
        im = im.convert("RGB")
        if im.width > max_width:
            im = im.resize((max_width, round(im.height * max_width / im.width)), Image.LANCZOS)
        im = im.quantize(colors=256, method=Image.Quantize.MEDIANCUT)
        buffer = io.BytesIO()
        im.save(buffer, format="PNG", optimize=True)
    data = base64.b64encode(buffer.getvalue()).decode("ascii")
    return f'<img alt="{esc(alt)}" src="data:image/png;base64,{data}">'


def figure(path: Path, caption: str, max_width: int = MAX_WIDTH) -> str:
    return f"<figure>{image(path, caption, max_width)}<figcaption>{esc(caption)}</figcaption></figure>"


def figure_grid(figures: list[str]) -> str:
    """Figures three to a row (the crawl's many square plots)."""
    return f"<div class='figgrid'>{''.join(figures)}</div>"


def missing(what: str, command: str) -> str:
    """The note of a section whose results are missing: what, and the command that makes it."""
    return f'<p class="missing">{esc(what)} is missing. Make it with <code>{esc(command)}</code>.</p>'


#: How every table writes the absence of a limit point (a blank limit-pressure cell).
NO_LIMIT = "no limit point"


def _is_limit_column(name: str) -> bool:
    return "limit" in name.lower() and ("kpa" in name.lower() or "pressure" in name.lower())


def number_text(value, digits: int = 4) -> str:
    """A cell's text: integers as integers, other numbers to `digits` significant digits, NaN
    and None blank, text as it is."""
    if isinstance(value, bool):
        return "yes" if value else "no"
    try:
        f = float(value)
    except (TypeError, ValueError):
        return "" if value is None else str(value)
    if f != f:  # NaN
        return ""
    if f.is_integer() and abs(f) < 1e15 and "e" not in str(value).lower():
        return str(int(f))
    return f"{f:.{digits}g}"


def table(rows: list[dict], columns: list[str] | None = None, digits: int = 4) -> str:
    """An HTML table of dict rows: integers as integers, other numbers to `digits` significant
    digits, a blank limit-pressure cell as `NO_LIMIT`; `Html` cells unescaped."""
    if not rows:
        return "<p>(empty table)</p>"
    columns = columns or list(rows[0])

    def cell(column, v):
        if isinstance(v, Html):
            return v
        text = number_text(v, digits)
        if not text and _is_limit_column(column):
            return NO_LIMIT
        return esc(text)

    head = "".join(f"<th>{esc(c)}</th>" for c in columns)
    body = "".join("<tr>" + "".join(f"<td>{cell(c, r.get(c))}</td>" for c in columns) + "</tr>" for r in rows)
    return f"<table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"


def csv_rows(path: Path) -> list[dict]:
    with open(path, newline="") as handle:
        return list(csv.DictReader(handle))


@lru_cache(maxsize=1)
def _markdown_it():
    from markdown_it import MarkdownIt

    # CommonMark with pipe tables; raw HTML in the source is escaped, not passed through.
    return MarkdownIt("commonmark", {"html": False}).enable("table")


def markdown(text: str) -> str:
    """Markdown (CommonMark and pipe tables) as HTML, by markdown-it-py; its headings start at
    <h4>, below the page's <h2> sections and <h3> blocks."""
    rendered = _markdown_it().render(text)
    return re.sub(r"<(/?)h([1-6])>", lambda m: f"<{m.group(1)}h{min(int(m.group(2)) + 3, 6)}>", rendered)


def _subsections(sid: str, body: str) -> tuple[str, list[tuple[str, str]]]:
    """The section body with an id on each <h3>, and those (id, text) pairs for the contents."""
    entries: list[tuple[str, str]] = []

    def name(match):
        anchor = f"{sid}-{len(entries) + 1}"
        entries.append((anchor, re.sub(r"<[^>]+>", "", match.group(1))))
        return f'<h3 id="{anchor}">{match.group(1)}</h3>'

    return re.sub(r"<h3>(.*?)</h3>", name, body), entries


def page(title: str, sections: list[tuple[str, str, str]], preamble: str = "", headline: str = "") -> str:
    """The whole document: title, the headline (the answer), the preamble, a table of contents
    with sub-entries, and the sections (id, heading, body html), each a closed <details>."""
    toc, body = [], []
    for sid, head, html_ in sections:
        html_, entries = _subsections(sid, html_)
        sub = "".join(f'<li><a href="#{a}">{text}</a></li>' for a, text in entries)
        toc.append(f'<li><a href="#{sid}">{esc(head)}</a>' + (f"<ul>{sub}</ul>" if sub else "") + "</li>")
        body.append(
            f'<section id="{sid}"><details class="section"><summary>{esc(head)}</summary>'
            f"{html_}</details></section>"
        )
    return (
        '<!DOCTYPE html><html lang="en"><head><meta charset="utf-8">'
        f"<title>{esc(title)}</title><style>{STYLE}</style><script>{SCRIPT}</script></head>"
        f"<body><h1>{esc(title)}</h1>{headline}{preamble}<nav><h2>Contents</h2><ol>{''.join(toc)}</ol></nav>"
        f"{''.join(body)}</body></html>\n"
    )
