"""The document formats by name: which renderer writes a mode, which an --output suffix names.

Stage: report (called by cli). In: a mode (markdown, latex, html) and reports, or a path.
Out: the document's text, or the format's name.
"""
from __future__ import annotations

import os

DOCUMENT_SUFFIXES = {".md": "markdown", ".markdown": "markdown", ".tex": "latex",
                     ".html": "html", ".htm": "html", ".json": "json"}


def output_format(path: str) -> str:
    """The format an --output file's suffix names (plain text for any other)."""
    return DOCUMENT_SUFFIXES.get(os.path.splitext(path)[1].lower(), "plain")


def render_document(mode: str, reports: list, sig: int = 6, detail: str = "full") -> str:
    """One document (markdown, latex or html) holding every report (`detail`: --steps)."""
    if mode == "markdown":
        from .markdown_out import render
    elif mode == "latex":
        from .latex_out import render
    else:
        from .html_out import render
    return render(reports, sig, detail)
