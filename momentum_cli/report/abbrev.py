"""Report stage: a long list of names (bodies, unknowns, lines) shortened for reading.

In: the names in order. Out: one string, the whole list when short; else its first few,
`...`, its last and how many there are (a 10^4-ball chain names 10^4 bodies).
"""
from __future__ import annotations

LIMIT = 12  # lists up to this long are shown whole
HEAD = 3  # a longer one: its first HEAD names, `...`, its last


def abbreviate(names) -> tuple[str, int | None]:
    """(`a, b, c, ..., z`, how many) for a long list; (the whole list, None) for a short
    one. Costs the few names it shows, not the list's length."""
    if not isinstance(names, (list, tuple)):
        names = list(names)
    n = len(names)
    if n <= LIMIT:
        return ", ".join(map(str, names)), None
    return ", ".join(map(str, names[:HEAD])) + f", ..., {names[-1]}", n


def name_list(names, noun: str) -> str:
    """The list as `abbreviate` shows it, a long one followed by `(N noun)`."""
    text, n = abbreviate(names)
    return text if n is None else f"{text} ({n} {noun})"
