"""Building blocks of the self-contained HTML design review (`studies.review.report`).

Self-contained: every image is a base64 `data:` URI (PNG, downscaled to `MAX_WIDTH` pixels and
reduced to a 256-colour palette, which keeps plots and renders sharp at a fraction of the size),
the style sheet is inline, and nothing is fetched from a network. A small inline script counts
the images that the browser decoded and writes the count on the page (`data-images-loaded`), so a
headless browser can check that every figure shows.
"""

from __future__ import annotations

import base64
import csv
import html
import io
import re
from pathlib import Path

#: Widest embedded image (pixels).
MAX_WIDTH = 1100

STYLE = """
body { font-family: system-ui, sans-serif; max-width: 1180px; margin: 0 auto; padding: 0 18px 60px;
       color: #1b1b1b; line-height: 1.45; }
h1 { margin-top: 28px; } h2 { border-bottom: 2px solid #d0d7de; padding-bottom: 4px; margin-top: 40px; }
nav ol { columns: 2; } table { border-collapse: collapse; margin: 10px 0; font-size: 13px; }
th, td { border: 1px solid #c9d1d9; padding: 3px 7px; text-align: left; vertical-align: top; }
th { background: #f1f4f7; } img { max-width: 100%; border: 1px solid #e1e4e8; margin: 6px 0; }
code, pre { background: #f5f7f9; font-size: 12.5px; } pre { padding: 8px; overflow-x: auto; }
.missing { background: #fff4e5; border-left: 4px solid #f0a020; padding: 8px 12px; }
.answer { background: #eef7ee; border-left: 4px solid #2e8b57; padding: 8px 14px; }
.figrow { display: flex; gap: 8px; flex-wrap: wrap; } .figrow figure { flex: 1 1 300px; margin: 0; }
figcaption { font-size: 13px; color: #444; }
"""

SCRIPT = """
window.addEventListener('load', function () {
  var imgs = Array.prototype.slice.call(document.images);
  var ok = imgs.filter(function (i) { return i.complete && i.naturalWidth > 0; }).length;
  document.body.setAttribute('data-images-loaded', ok + '/' + imgs.length);
});
"""


def esc(text) -> str:
    return html.escape(str(text))


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


def figure(path: Path, caption: str) -> str:
    return f"<figure>{image(path, caption)}<figcaption>{esc(caption)}</figcaption></figure>"


def missing(what: str, command: str) -> str:
    """The note of a section whose results are missing: what, and the command that makes it."""
    return f'<p class="missing">{esc(what)} is missing. Make it with <code>{esc(command)}</code>.</p>'


def table(rows: list[dict], columns: list[str] | None = None, digits: int = 4) -> str:
    """An HTML table of dict rows; numbers to `digits` significant digits."""
    if not rows:
        return "<p>(empty table)</p>"
    columns = columns or list(rows[0])

    def cell(v):
        try:
            f = float(v)
        except (TypeError, ValueError):
            return esc("" if v is None else v)
        if f != f:  # NaN
            return ""
        return esc(f"{f:.{digits}g}")

    head = "".join(f"<th>{esc(c)}</th>" for c in columns)
    body = "".join("<tr>" + "".join(f"<td>{cell(r.get(c))}</td>" for c in columns) + "</tr>" for r in rows)
    return f"<table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"


def csv_rows(path: Path) -> list[dict]:
    with open(path, newline="") as handle:
        return list(csv.DictReader(handle))


def _inline(text: str) -> str:
    text = esc(text)
    text = re.sub(r"`([^`]+)`", r"<code>\1</code>", text)
    return re.sub(r"\*\*([^*]+)\*\*", r"<b>\1</b>", text)


def markdown(text: str) -> str:
    """The Markdown subset of results/*.md: headings, pipe tables, bullet lists, paragraphs,
    indented or fenced code."""
    out, para, rows, items, code = [], [], [], [], []

    def flush():
        if para:
            out.append("<p>" + _inline(" ".join(para)) + "</p>")
            para.clear()
        if rows:
            cells = [[c.strip() for c in r.strip().strip("|").split("|")] for r in rows]
            body = [c for c in cells[1:] if not all(set(x) <= set("-: ") for x in c)]
            head = "".join(f"<th>{_inline(c)}</th>" for c in cells[0])
            trs = "".join("<tr>" + "".join(f"<td>{_inline(c)}</td>" for c in r) + "</tr>" for r in body)
            out.append(f"<table><thead><tr>{head}</tr></thead><tbody>{trs}</tbody></table>")
            rows.clear()
        if items:
            out.append("<ul>" + "".join(f"<li>{_inline(i)}</li>" for i in items) + "</ul>")
            items.clear()
        if code:
            out.append("<pre>" + esc("\n".join(code)) + "</pre>")
            code.clear()

    for line in text.splitlines():
        if line.startswith("    ") and not items:
            flush() if not code else None
            code.append(line[4:])
        elif line.startswith("#"):
            flush()
            level = min(len(line) - len(line.lstrip("#")) + 2, 5)
            out.append(f"<h{level}>{_inline(line.lstrip('#').strip())}</h{level}>")
        elif line.startswith("|"):
            if not rows:
                flush()
            rows.append(line)
        elif line.lstrip().startswith("- "):
            if not items:
                flush()
            items.append(line.lstrip()[2:])
        elif not line.strip():
            flush()
        elif items:
            items[-1] += " " + line.strip()
        else:
            if code:
                flush()
            para.append(line.strip())
    flush()
    return "\n".join(out)


def page(title: str, sections: list[tuple[str, str, str]], preamble: str = "") -> str:
    """The whole document: title, table of contents, sections (id, heading, body html)."""
    toc = "".join(f'<li><a href="#{sid}">{esc(head)}</a></li>' for sid, head, _ in sections)
    body = "".join(
        f'<section id="{sid}"><h2>{esc(head)}</h2>{html_}</section>' for sid, head, html_ in sections
    )
    return (
        '<!DOCTYPE html><html lang="en"><head><meta charset="utf-8">'
        f"<title>{esc(title)}</title><style>{STYLE}</style><script>{SCRIPT}</script></head>"
        f"<body><h1>{esc(title)}</h1>{preamble}<nav><ol>{toc}</ol></nav>{body}</body></html>\n"
    )
