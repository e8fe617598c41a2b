"""The given numbers of a problem file: each literal a parameter with a name and a place.

Stage: syntax (read-only). In: a parsed `Document`. Out: `GivenNumber`s (the literal's
`Num` node, a label such as `rod mass`, its line:column and text; a `for` loop's passes
are one number) and `replaced`, the document with literals' values changed, for the
sensitivities (`sensitivity.py`, `traced_partials.py`).
"""
from __future__ import annotations

import re

from . import syntax as S
from .records import record

# statements whose numbers are not data of the problem (what to print, what to
# simulate, what to expect, the title)
_NOT_DATA = (S.Find, S.SimulateDecl, S.Expect, S.Problem)
_NUMBER = re.compile(r"(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?")


@record(frozen=True)
class GivenNumber:
    id: str  # #1, #2, ... in the file's order
    node: S.Num
    label: str  # what it is: `rod mass`, `let mu`, `rod.vx@1`, `restitution at A`
    text: str  # as written: `10 kg`
    copies: tuple = ()  # the same literal in the other passes of a `for` loop

    @property
    def nodes(self) -> tuple:
        """Every node of the literal: moving the number as written moves them all."""
        return (self.node,) + self.copies

    @property
    def line(self) -> int:
        return self.node.span.line

    @property
    def column(self) -> int:
        return self.node.span.column

    @property
    def value(self) -> float:
        return self.node.value

    @property
    def unit(self) -> str:
        return self.node.unit or ""


def given_numbers(doc: S.Document) -> list[GivenNumber]:
    """Every literal number that is data: not in a `find`, hint, `simulate` or `expect`,
    not an exponent, and not a bare `0` (a zero that takes any dimension is a structural
    zero: `rod.omega = 0`, `(0, 1)`; written with a unit it is a parameter)."""
    found: dict = {}  # (line, column) -> [(num, label)]: a loop's passes share a place
    for st in doc.statements:
        if isinstance(st, _NOT_DATA):
            continue
        for num, path in _nums(st, []):
            if num.value == 0 and not num.unit:
                continue
            found.setdefault((num.span.line, num.span.column, num.value),
                             []).append((num, _label(st, path)))
    out: list[GivenNumber] = []
    for group in found.values():
        (num, label), rest = group[0], group[1:]
        if rest:
            label += f" (in {len(group)} loop passes)"
        out.append(GivenNumber(f"#{len(out) + 1}", num, label, _text(doc.source, num),
                               tuple(n for n, _ in rest)))
    return out


def _nums(node, path):
    """(Num, path of (node, field)) for every literal under `node`, in source order."""
    if isinstance(node, S.Num):
        yield node, path
        return
    if isinstance(node, tuple):
        for item in node:
            yield from _nums(item, path)
        return
    fields = getattr(type(node), "_fields", None)
    if not fields:
        return
    if isinstance(node, S.Given) and node.relation != "=":
        return  # a branch hint (`rod.vy < 0`) is not data
    for f in fields:
        if f.endswith("span"):
            continue
        if isinstance(node, S.BinOp) and node.op in ("^", "**") and f == "right":
            continue  # an exponent is the form of a law, not a measured number
        yield from _nums(getattr(node, f), path + [(node, f)])


def replaced(doc: S.Document, values: dict) -> S.Document:
    """The document with each literal whose id() is a key of `values` holding its value
    (one walk for many numbers; a traced value, for exact derivatives, is a float)."""
    def walk(node):
        if isinstance(node, S.Num):
            if id(node) in values:
                return S.Num(node.span, values[id(node)], node.unit, node.unit_span)
            return node
        if isinstance(node, tuple):
            items = tuple(walk(n) for n in node)
            return node if all(a is b for a, b in zip(items, node)) else items
        fields = getattr(type(node), "_fields", None)
        if not fields:
            return node
        vals = [getattr(node, f) for f in fields]
        out = [walk(v) for v in vals]
        if all(a is b for a, b in zip(out, vals)):
            return node
        return type(node)(*out)

    return S.Document(doc.source, tuple(walk(s) for s in doc.statements))


def _text(source, num: S.Num) -> str:
    sp = num.span
    end = num.unit_span if num.unit_span is not None else sp
    line = source.line_text(sp.line) if hasattr(source, "line_text") else ""
    if line and end.end_line == sp.line and end.end_column:
        text = line[sp.column - 1:end.end_column - 1].strip()
        m = _NUMBER.match(text)
        if m and float(m.group(0)) == num.value:  # not a `--set` value at the let's place
            return text
    return f"{num.value:g} {num.unit or ''}".strip()


def _label(st, path) -> str:
    """A short name for a literal from the statement and the fields that lead to it."""
    nodes = [n for n, _ in path]
    comp = ""
    for n, f in path:
        if isinstance(n, S.VecLit):
            comp = f" {f}"  # the component of a written vector
    if isinstance(st, S.Gravity):
        return "g" + comp
    if isinstance(st, S.Let):
        return f"let {st.name}" + comp
    if isinstance(st, S.BodyDecl):
        args = [n for n in nodes if isinstance(n, S.Arg)]
        if args:
            return f"{st.name} {args[-1].name}" + comp
        return f"{st.name} part position" + comp
    if isinstance(st, S.PointDecl):
        return f"point {st.name}" + comp
    if isinstance(st, S.SurfaceDecl):
        field = path[0][1] if path else ""
        return f"surface {st.name} {field}" + comp
    if isinstance(st, S.Joint):
        field = path[0][1] if path else ""
        return f"{st.kind} {st.label or st.a.text} {field}".rstrip() + comp
    if isinstance(st, S.StateDecl):
        given = [n for n in nodes if isinstance(n, S.Given)]
        if given:
            return f"{given[0].body}.{given[0].qty}@{st.id}" + comp
        return f"state {st.id}" + comp
    if isinstance(st, S.Transition):
        where = f"{st.before}->{st.after}"
        contact = [n for n in nodes if isinstance(n, S.Contact)]
        prop = [n for n in nodes if isinstance(n, S.Prop)]
        clause = [n for n in nodes if isinstance(n, S.Clause)]
        if contact:
            c = contact[0]
            name = c.label or c.a.text
            what = prop[0].kind if prop else "normal"
            return f"{what} at {name} ({where})" + comp
        if clause:
            return f"{clause[0].kind} ({where})" + comp
        return f"{st.kind} {where}" + comp
    kind = type(st).__name__.replace("Decl", "").lower()
    field = path[0][1] if path else ""
    name = getattr(st, "name", None) or getattr(st, "body", None) or ""
    return " ".join(x for x in (kind, name, field) if x) + comp
