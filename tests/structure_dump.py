"""A canonical dump of what build, compile and analyse produce, for equality tests.

In: a problem text. Out: one digest (and the full text on request) of the scene's
records, every equation node for node (node types, leaf names with their Key fields,
leaf values as repr), the unknowns in column order with their metadata, the
transitions' info and the friction sites, and the structure (matching, blocks in order,
dependencies): what tests/test_compile_equal.py compares with the digests recorded
from the code before the compile/analyse rewrite (tests/data/structure_digests.json).
"""
from __future__ import annotations

import hashlib

from momentum_cli.diagnostics import ProblemError
from momentum_cli.elements.keys import Key
from momentum_cli.expr import Add, Const, Fn, Known, Mul, Pow, Var


def _name(n) -> str:
    if isinstance(n, Key):
        return f"{str(n)}<{n.kind},{n.body},{n.qty},{n.state},{n.transition},{n.label}," \
               f"{n.comp}>"
    return f"{n}<str>"


def node(e, out: list) -> None:
    """The tree in prefix form (iterative: the big scenes' sums are long, not deep)."""
    stack = [e]
    while stack:
        x = stack.pop()
        t = type(x)
        if t is Const:
            out.append(f"C{x.value!r}")
        elif t is Known:
            out.append(f"K{_name(x.name)}={x.value!r}")
        elif t is Var:
            out.append(f"V{_name(x.name)}")
        elif t is Add:
            out.append(f"A{len(x.terms)}")
            stack.extend(reversed(x.terms))
        elif t is Mul:
            out.append(f"M{len(x.factors)}")
            stack.extend(reversed(x.factors))
        elif t is Pow:
            out.append(f"P{x.exp!r}")
            stack.append(x.base)
        elif t is Fn:
            out.append(f"F{x.name}")
            stack.append(x.arg)
        elif x is None:
            out.append("None")
        else:
            out.append(f"?{type(x).__name__}:{x!r}")


def _deep(x, out: list) -> None:
    """Tuples, lists and dicts of expressions, node by node."""
    if isinstance(x, (tuple, list)):
        out.append(f"({len(x)}")
        for y in x:
            _deep(y, out)
    elif isinstance(x, dict):
        out.append(f"{{{len(x)}")
        for k, y in x.items():
            out.append(repr(k))
            _deep(y, out)
    elif hasattr(x, "x") and hasattr(x, "y") and not isinstance(x, (int, float, str)):
        _v2(x, out)
    else:
        node(x, out) if x is None or type(x).__module__.endswith("expr") else \
            out.append(repr(x))


def _v2(v, out: list) -> None:
    node(v.x, out)
    node(v.y, out)


def system_lines(system, structure=None) -> list[str]:
    out: list[str] = []
    for name, u in system.unknowns.items():
        out.append(f"U {_name(name)} {u.dim} {u.unit} {u.kind} {u.hints!r} {u.state} "
                   f"{u.body} {u.qty}")
    for e in system.equations:
        out.append(f"E{e.index} {e.principle!r} {e.group!r} {e.span!r} {e.kind}")
        node(e.lhs, out)
        out.append("=")
        node(e.rhs, out)
    for t in system.transitions:
        out.append(f"T {t.kind} {t.key} {t.before} {t.after} {t.span!r} {t.why!r} "
                   f"{t.bodies!r}")
        for label, a, b in t.contacts:
            out.append(f"TC {label}")
            node(a, out)
            node(b, out)
        if t.energy is not None:
            node(t.energy[0], out)
            node(t.energy[1], out)
        for law in t.laws:
            out.append(f"TL {law.kind} {law.principle!r} {law.why!r} {law.bodies!r} "
                       f"{law.parallel!r}")
            for e in (law.lhs, law.rhs, law.locked):
                node(e, out)
            for k, v in law.alias.items():
                out.append(f"TLA {k!r}")
                node(v, out)
            _deep(law.parts, out)
        for a in t.impulses:
            out.append(f"TI {a.body} {a.point!r} {a.what!r}")
            _v2(a.J, out)
            node(a.torque, out)
            _v2(a.arm, out)
    for f in system.friction:
        out.append(f"FR {f.key} {f.label} {f.transition} {f.mu!r} {f.jn} {f.jt} {f.regime} "
                   f"{f.decided} {f.span!r}")
        node(f.slip_expr, out)
        node(f.slip_after, out)
    out.append(f"N {[(d.severity, d.message, d.span) for d in system.notes.items]!r}")
    out.append(f"I {system.invalid_stated!r}")
    for f in system.finds:
        out.append(f"FI {f.name} {f.dim} {f.unit} {f.factor!r} {f.span!r} {f.explicit}")
        node(f.expr, out)
        node(f.alt, out)
    if structure is not None:
        s = structure
        out.append(f"S inc {[sorted(i) for i in s.incidence]!r}")
        out.append(f"S match {sorted(s.match_eq.items())!r}")
        out.append(f"S under {sorted(s.under)!r} {sorted(s.under_eqs)!r}")
        out.append(f"S red {s.redundant!r} const {s.constant_eqs!r}")
        for b in s.blocks:
            out.append(f"B {b.index} {b.equations!r} {b.unknowns!r} {sorted(b.depends)!r}")
        out.append(f"S bov {list(s.block_of_var.items())!r}")
    return out


def digest(text: str, name: str = "t.mom", solve: bool = True) -> str:
    """The digest of build -> compile -> analyse for `text` (and of the system the full
    solve ends with, friction regimes settled), or of the error it raises."""
    from momentum_cli.analyse import analyse
    from momentum_cli.compile import compile_scene
    from momentum_cli.scene import build
    from momentum_cli.solve import solve_scene
    from momentum_cli.source import Source
    from momentum_cli.syntax import parse

    lines: list[str] = []
    try:
        scene = build(parse(Source(name, text)))
        lines.append(f"scene {scene.bodies!r} {scene.states!r} {scene.transitions!r}")
        system = compile_scene(scene)
        lines += system_lines(system, analyse(system))
        if solve:
            sol = solve_scene(scene)
            lines.append("solved")
            lines += system_lines(sol.system, sol.structure)
    except ProblemError as exc:
        lines.append(f"error {exc}")
    return hashlib.sha256("\n".join(lines).encode()).hexdigest()
