#!/usr/bin/env python3
"""README.md → PDF (run by build_pdf.sh in its own venv).

The Markdown is the one GitHub shows: maths is written as $$…$$ (display, on its own line) and
$…$ (inline), which GitHub renders with MathJax. PyMuPDF does not typeset TeX, so each formula
is drawn here by matplotlib's mathtext into a PNG and put in as an image; code spans and code
blocks are left alone.

    python make_pdf.py docs/report/README.md docs/report/report.pdf
"""

from __future__ import annotations

import hashlib
import re
import shutil
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
from matplotlib import mathtext  # noqa: E402
from matplotlib.font_manager import FontProperties  # noqa: E402
from markdown_pdf import MarkdownPdf, Section  # noqa: E402

DPI = 200
CSS = """
body { font-family: sans-serif; font-size: 10pt; }
h1 { font-size: 18pt; } h2 { font-size: 14pt; } h3 { font-size: 11pt; }
table { border-collapse: collapse; font-size: 8pt; }
th, td { border: 1px solid #999; padding: 2px 4px; }
code { font-size: 8.5pt; }
"""
CODE = re.compile(r"(```.*?```|`[^`\n]*`)", re.S)
DISPLAY = re.compile(r"^([ \t]*)\$\$(.+?)\$\$", re.S | re.M)
INLINE = re.compile(r"(?<![\\$])\$(?!\$)([^$\n]+?)(?<!\\)\$(?!\$)")


def formula_image(tex: str, folder: Path, size: float) -> tuple[str, float, float]:
    """Draws $tex$ with mathtext; returns (file name, width and height in points)."""
    name = hashlib.sha1(f"{size}:{tex}".encode()).hexdigest()[:16] + ".png"
    path = folder / name
    try:
        depth = mathtext.math_to_image(f"${tex}$", path, prop=FontProperties(size=size), dpi=DPI, format="png")
    except ValueError as e:
        raise SystemExit(f"make_pdf.py: mathtext cannot draw ${tex}$: {e}") from None
    del depth
    from PIL import Image
    with Image.open(path) as im:
        w, h = im.size
    return name, w * 72 / DPI, h * 72 / DPI


def replace_maths(text: str, folder: Path, prefix: str) -> str:
    def display(m: re.Match) -> str:
        # Kept at the line's indentation, so a formula inside a list item stays in the item.
        name, w, h = formula_image(" ".join(m.group(2).split()), folder, 12)
        return f'{m.group(1)}<img src="{prefix}/{name}" width="{w:.0f}" height="{h:.0f}">'

    def inline(m: re.Match) -> str:
        name, w, h = formula_image(m.group(1), folder, 10)
        return f'<img src="{prefix}/{name}" width="{w:.0f}" height="{h:.0f}">'

    parts = CODE.split(text)
    for i in range(0, len(parts), 2):  # even parts are outside code
        parts[i] = INLINE.sub(inline, DISPLAY.sub(display, parts[i]))
    return "".join(parts)


def main(src: str, dst: str) -> int:
    src_path, dst_path = Path(src).resolve(), Path(dst).resolve()
    root = src_path.parent
    folder = root / ".pdf-maths"
    folder.mkdir(exist_ok=True)
    try:
        text = replace_maths(src_path.read_text(), folder, folder.name)
        pdf = MarkdownPdf(toc_level=2, mode="commonmark", optimize=True)
        pdf.meta["title"] = text.splitlines()[0].lstrip("# ").strip()
        pdf.add_section(Section(text, root=str(root)), user_css=CSS)
        tmp = dst_path.with_suffix(".pdf.tmp")
        pdf.save(tmp)
        tmp.replace(dst_path)  # no half-written PDF under the real name
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    print(f"wrote {dst_path}")
    return 0


if __name__ == "__main__":
    if len(sys.argv) != 3:
        raise SystemExit("usage: make_pdf.py README.md report.pdf")
    sys.exit(main(sys.argv[1], sys.argv[2]))
