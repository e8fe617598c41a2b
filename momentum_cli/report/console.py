"""Report stage: the rich console the rich format prints to.

In: the --color choice (auto, always, never). Out: a rich Console (auto: colour on a
terminal, as rich decides, honouring NO_COLOR and FORCE_COLOR).
"""
from __future__ import annotations


def make_console(color: str):
    """Made here, in the report stage: only it imports rich."""
    from rich.console import Console

    if color == "always":
        return Console(force_terminal=True)
    if color == "never":
        return Console(no_color=True)
    return Console()
