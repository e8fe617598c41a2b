"""`--set NAME=VALUE`: replacing a file's `let` constants before the scene is built.

In: the option's text (`v0=5 m/s`) and a parsed `Document`. Out: the document with
those `let` values replaced. An option that names no `let` of a file is a usage error
(the CLI checks it before solving, with "did you mean").
"""
from __future__ import annotations

import re

from . import syntax as S
from .diagnostics import ProblemError
from .source import Source

_LET = re.compile(r"^[ \t]*let[ \t]+([A-Za-z_][A-Za-z_0-9]*)[ \t]*=", re.M)


class OverrideError(ValueError):
    """A `--set` that cannot be used: the message is for the command line."""


def split(option: str) -> tuple[str, str]:
    """`v0=5 m/s` -> ("v0", "5 m/s"); the value is checked by parsing it as a `let`."""
    name, eq, value = option.partition("=")
    name, value = name.strip(), value.strip()
    if not eq or not re.fullmatch(r"[A-Za-z_][A-Za-z_0-9]*", name) or not value:
        raise OverrideError(f"--set {option!r}: write NAME=VALUE, e.g. --set v0='5 m/s'")
    value_node(name, value)
    return name, value


def value_node(name: str, value: str):
    """The expression of `--set NAME=VALUE`, parsed as the file's own `let` would be."""
    try:
        doc = S.parse(Source("--set", f"let {name} = {value}\n"))
    except ProblemError as exc:
        raise OverrideError(f"--set {name}={value}: {exc.diagnostics[0].message}") from None
    lets = [s for s in doc.statements if isinstance(s, S.Let)]
    if len(lets) != 1 or len(doc.statements) != 1:
        raise OverrideError(f"--set {name}={value}: one value, such as 5 m/s")
    return lets[0].value


def let_names(text: str) -> list[str]:
    """The `let` names of a problem file, read line by line (no parse needed)."""
    return _LET.findall(text)


def check_names(overrides, text: str, file: str) -> None:
    """Every override names a `let` of the file, else OverrideError with "did you mean"."""
    names = let_names(text)
    for name, _ in overrides:
        if name not in names:
            have = f" (it has: {', '.join(names)})" if names and len(names) <= 8 else ""
            import difflib  # (here: an error's hint)

            close = difflib.get_close_matches(name, names, n=1, cutoff=0.5)
            raise OverrideError(f"--set {name}: {file} has no `let {name}`" +
                                (f"; did you mean '{close[0]}'?" if close else have))


def apply(doc: S.Document, overrides) -> S.Document:
    """The document with each overridden `let` given its new value (spans kept: an error
    in the value points at the `let` line)."""
    if not overrides:
        return doc
    new = dict(overrides)
    out = []
    for s in doc.statements:
        if isinstance(s, S.Let) and s.name in new:
            s = S.Let(s.span, s.name, _relocate(value_node(s.name, new[s.name]), s.value.span))
        out.append(s)
    return S.Document(doc.source, tuple(out))


def _relocate(node, span):
    """The override's expression with every span set to the replaced value's span."""
    if isinstance(node, tuple):
        return tuple(_relocate(n, span) for n in node)
    fields = getattr(type(node), "_fields", None)
    if not fields:
        return node
    vals = []
    for f in fields:
        v = getattr(node, f)
        if f.endswith("span") and v is not None:
            v = span
        else:
            v = _relocate(v, span)
        vals.append(v)
    return type(node)(*vals)
