"""What a sweep may vary: a file's `let` constants, and its given numbers by name.

In: a parsed `Document` and the design's parameter names. Out: the document with each
varied given number (`rod.y@1` a state's given scalar, `e[A]` / `mu[A]` a contact's
restitution or friction coefficient) turned into a `let` of that name, and a scene
builder that replaces those `let` values with one variant's (a plain float, or a
`trace.Traced` for the batched path). Names that are neither are one-line errors.
"""
from __future__ import annotations

import re

from .. import syntax as S
from ..diagnostics import did_you_mean
from ..elements.kinds import Prop
from ..quantity import Q
from ..expr import Const
from ..scene import _Builder

_GIVEN = re.compile(r"^([A-Za-z_]\w*)\.([A-Za-z_]+)@(\w+)$")
_COEF = re.compile(r"^(e|mu)\[([^\]]+)\]$")


class ParamError(ValueError):
    """A parameter the file cannot vary: one line for the command line."""


def bind(doc: S.Document, names: list[str], file: str) -> S.Document:
    """The document with every varied given number made a `let` of the parameter's name."""
    lets = [s.name for s in doc.statements if isinstance(s, S.Let)]
    new_lets: list = []
    stmts = list(doc.statements)
    for name in names:
        if name in lets:
            continue
        g, c = _GIVEN.match(name), _COEF.match(name)
        if g:
            stmts, node = _rebind_given(stmts, name, *g.groups())
        elif c:
            stmts, node = _rebind_coef(stmts, name, *c.groups())
        else:
            node = None
        if node is None:
            raise ParamError(f"{name}: {file} has no `let {name}` and no given number of that "
                             "name (vary a `let`, a state's given `BODY.QTY@STATE`, or a "
                             "contact's `e[C]`, `mu[C]`)" + did_you_mean(name, lets))
        new_lets.append(S.Let(node.span, name, node))
    return S.Document(doc.source, tuple(new_lets) + tuple(stmts))


def _rebind_given(stmts, name, body, qty, sid):
    for k, s in enumerate(stmts):
        if isinstance(s, S.StateDecl) and s.id == sid:
            for i, it in enumerate(s.items):
                if isinstance(it, S.Given) and it.body == body and it.qty == qty and \
                        it.relation == "=" and not isinstance(it.value, S.VecLit):
                    ref = S.Ref(it.value.span, name)
                    items = s.items[:i] + (S.Given(it.span, it.body, it.qty, it.qty_span, ref,
                                                   it.relation),) + s.items[i + 1:]
                    out = list(stmts)
                    out[k] = S.StateDecl(s.span, s.id, s.label, items)
                    return out, it.value
    return stmts, None


def _contact_names(c: S.Contact) -> set[str]:
    out = {c.a.text}
    if c.label:
        out.add(c.label)
    if c.b is not None:
        out.add(f"{c.a.text}-{c.b.text}")
    return out


def _rebind_coef(stmts, name, which, label):
    kind = Prop.RESTITUTION if which == "e" else Prop.FRICTION
    for k, s in enumerate(stmts):
        if not isinstance(s, S.Transition):
            continue
        for ci, c in enumerate(s.clauses):
            if not isinstance(c, S.Contact) or label not in _contact_names(c):
                continue
            for pi, p in enumerate(c.props):
                if p.kind == kind and p.value is not None and not isinstance(p.value, S.Ref):
                    prop = S.Prop(p.span, p.kind, S.Ref(p.value.span, name), p.law)
                    con = S.Contact(c.span, c.label, c.a, c.b, c.normal,
                                    c.props[:pi] + (prop,) + c.props[pi + 1:])
                    t = S.Transition(s.span, s.kind, s.before, s.after,
                                     s.clauses[:ci] + (con,) + s.clauses[ci + 1:],
                                     s.before_span, s.after_span, s.groups)
                    out = list(stmts)
                    out[k] = t
                    return out, p.value
    return stmts, None


class ParamBuilder(_Builder):
    """The scene builder with the varied `let`s set to one variant's values (SI)."""

    def __init__(self, doc: S.Document, values: dict, dims: dict):
        super().__init__(doc)
        self.param_values = values
        self.param_dims = dims
        self.let_dims: dict = {}

    def _let(self, s: S.Let) -> None:
        super()._let(s)
        if s.name in self.param_values:
            q = self.constants[s.name]
            self.let_dims[s.name] = q.dim
            if q.is_vector:
                raise ParamError(f"{s.name}: `let {s.name}` is a vector; vary a scalar")
            want = self.param_dims.get(s.name)
            if want is not None and want != q.dim:
                from ..units import describe, si_label

                raise ParamError(f"{s.name} is {describe(q.dim)} in the file "
                                 f"({si_label(q.dim) or 'no unit'}); the sweep gives "
                                 f"{describe(want)}" + (f": write it with a unit, e.g. "
                                                        f"{si_label(q.dim)}"
                                                        if want == (0, 0, 0) else ""))
            self.constants[s.name] = Q(Const(self.param_values[s.name]), q.dim)


def build_variant(doc: S.Document, values: dict, dims: dict):
    """The scene of one variant (values: parameter name -> SI float or Traced)."""
    return ParamBuilder(doc, values, dims).run()
