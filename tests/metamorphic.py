"""Metamorphic variants of a problem file: renamed bodies, reordered statements,
appended redundant equations. Built on the project's own parser (tokens and tree
positions), so a rename touches only the names a statement declares or refers to.
"""
from __future__ import annotations

import functools
import math
import re

from momentum_cli.diagnostics import ProblemError
from momentum_cli.expr import magnitude, variables
from momentum_cli.report.model import build_report
from momentum_cli.scene import build
from momentum_cli.solve import solve_scene
from momentum_cli.source import Source
from momentum_cli.syntax import parser

# member names and built-in words a renamed entity must not collide with
RESERVED = {"x", "y", "pos", "angle", "vx", "vy", "v", "omega", "speed", "mass", "center",
            "end", "ground", "t", "e", "g", "T", "T_lost", "J_n", "J_t", "Jx", "Jy", "M", "J",
            "dx", "dy", "dtheta", "alpha", "pi"}
# (rule, child index) of NAME tokens that name a kind, a function or a keyword argument
NOT_REFERENCES = {("shape", 0), ("call", 0), ("arg", 0)}

_TOP = re.compile(r"[A-Za-z_][A-Za-z_0-9]*")


@functools.lru_cache(maxsize=64)
def tree_of(text: str):
    return parser().parse(text if text.endswith("\n") else text + "\n")


def _tokens(tree):
    """(rule, index, token) for every token in the tree."""
    from lark import Token, Tree

    stack = [tree]
    while stack:
        node = stack.pop()
        for i, ch in enumerate(node.children):
            if isinstance(ch, Tree):
                stack.append(ch)
            elif isinstance(ch, Token):
                yield node.data, i, ch


def _declared(tree) -> dict[str, list[str]]:
    """The names bodies, points and labels (contacts, joints) declare."""
    out: dict[str, list[str]] = {"body": [], "point": [], "label": []}
    for node in tree.iter_subtrees_topdown():
        kind = {"body_simple": "body", "body_composite": "body", "point_stmt": "point",
                "label": "label"}.get(node.data)
        if kind:
            name = str(node.children[0])
            if name not in out[kind] and name not in RESERVED:
                out[kind].append(name)
    return out


def rename_map(text: str) -> dict[str, str]:
    """Fresh names whose sorted order reverses each kind's sorted order."""
    decl = _declared(tree_of(text))
    taken = {str(t) for _, _, t in _tokens(tree_of(text))}
    mapping: dict[str, str] = {}
    for kind, prefix in (("body", "zb"), ("point", "zp"), ("label", "zc")):
        names = sorted(n for n in decl[kind] if n not in mapping)
        for i, n in enumerate(names):
            new = f"{prefix}{len(names) - 1 - i:04d}"
            assert new not in taken
            mapping[n] = new
    return mapping


def rename(text: str, mapping: dict[str, str]) -> str:
    """The text with every reference to a mapped name replaced (by token position)."""
    edits = []
    for rule, i, tok in _tokens(tree_of(text)):
        if tok.type == "NAME" and str(tok) in mapping and (rule, i) not in NOT_REFERENCES:
            edits.append((tok.start_pos, tok.end_pos, mapping[str(tok)]))
    out = text
    for a, b, new in sorted(edits, reverse=True):
        out = out[:a] + new + out[b:]
    return out


def map_name(name: str, mapping: dict[str, str]) -> str:
    """An answer's name (program output) with the renamed identifiers in it (also the
    point of an angular momentum's name, `H_O[{rod,ball}]@2`)."""
    def one(m):
        word = m.group(0)
        if word.startswith("H_") and word[2:] in mapping:
            return "H_" + mapping[word[2:]]
        return mapping.get(word, word)
    return _TOP.sub(one, name)


# ---- reordering ---------------------------------------------------------------------------
GROUPS = ({"body_simple", "body_composite"}, {"point_stmt"}, {"state_stmt"},
          {"transition_stmt", "burn_stmt", "gain_stmt"}, {"find_stmt"}, {"equation_stmt"},
          {"conserve_momentum_stmt", "conserve_angular_stmt", "restitution_stmt"},
          {"pin_stmt", "weld_stmt", "link_stmt", "spring_stmt"})


def _reverse_find_items(text: str) -> str:
    edits = []
    for node in tree_of(text).iter_subtrees():
        if node.data == "find_stmt" and len(node.children) > 1:
            items = [c for c in node.children if hasattr(c, "meta")]
            spans = [(c.meta.start_pos, c.meta.end_pos) for c in items]
            pieces = [text[a:b] for a, b in spans]
            for (a, b), piece in zip(spans, reversed(pieces)):
                edits.append((a, b, piece))
    out = text
    for a, b, new in sorted(edits, reverse=True):
        out = out[:a] + new + out[b:]
    return out


def _reverse_clauses(text: str) -> str:
    """Reverse the clauses of each transition, when each sits on a line of its own."""
    lines = text.split("\n")
    for node in tree_of(text).iter_subtrees():
        if node.data != "transition_stmt":
            continue
        clauses = [c for c in node.children[3:] if hasattr(c, "meta") and
                   getattr(c.meta, "line", None) is not None]
        rows = [c.meta.line for c in clauses]
        if len(rows) < 2 or len(set(rows)) != len(rows) or \
                any(c.meta.end_line != c.meta.line for c in clauses):
            continue
        texts = [lines[r - 1] for r in rows]
        for r, t in zip(rows, reversed(texts)):
            lines[r - 1] = t
    return "\n".join(lines)


def reorder(text: str) -> str:
    """Statements of each free kind in reverse order (each keeps its kind's slots),
    find items and transition clauses reversed."""
    text = _reverse_clauses(_reverse_find_items(text))
    if not text.endswith("\n"):
        text += "\n"
    tree = tree_of(text)
    lines = text.split("\n")
    starts = [(c.meta.line, c.data) for c in tree.children if hasattr(c, "meta")]
    chunks = []
    for k, (line, kind) in enumerate(starts):
        end = starts[k + 1][0] if k + 1 < len(starts) else len(lines)
        chunks.append([kind, "\n".join(lines[line - 1:end - 1]) + "\n"])
    head = "\n".join(lines[:starts[0][0] - 1]) + "\n" if starts and starts[0][0] > 1 else ""
    for group in GROUPS:
        slots = [k for k, (kind, _) in enumerate(chunks) if kind in group]
        texts = [chunks[k][1] for k in slots]
        for k, t in zip(slots, reversed(texts)):
            chunks[k][1] = t
    return head + "".join(t for _, t in chunks)


# ---- solving ------------------------------------------------------------------------------
class Outcome:
    """A solve's answers (name -> (SI value, tolerance)) or its error."""

    def __init__(self, text: str, name: str = "variant.mom"):
        self.text = text
        self.error = None
        self.answers: dict[str, tuple[float, float]] = {}
        self.state_answers: list[tuple[str, float, str]] = []
        self.undecided: set[int] = set()
        try:
            sol = solve_scene(build(_parse(Source(name, text))))
        except ProblemError as exc:
            self.error = exc.diagnostics[0]
            return
        build_report(name, sol)  # the report of every variant builds too (as `solve_source`)
        # the lines of redundant statements the float solve cannot judge (it says so)
        self.undecided = {int(m) for c in sol.checks if c.status == "warning"
                          for m in re.findall(r"^cannot decide \(line (\d+)\)", c.detail)}
        bounds = {}
        for rep in sol.blocks:
            comps = rep.quality.components if rep.quality is not None else None
            for j, n in enumerate(rep.unknowns):
                v = sol.values.get(n, 0.0)
                bounds[n] = abs(v) * comps[j] if comps else \
                    max(rep.residual * 100, 1e-12) * max(abs(v), 1.0)
        for f, (n, _v, _u, si) in zip(sol.system.finds, sol.answers):
            try:
                mag = magnitude(f.expr, sol.values)
            except Exception:
                mag = abs(si)
            err = sum(bounds.get(v, 0.0) for v in variables(f.expr))
            # the answers' own bounds, plus evaluating the find's expression (round-off of
            # its terms: a difference of energies cancels)
            self.answers[n] = (si, err + 1e-13 * max(mag, abs(si)) + 1e-300)
            u = sol.system.unknowns.get(n)
            if u is not None and u.kind == "state" and n in sol.values:
                self.state_answers.append((n, sol.values[n], u.unit))

    def conflict_lines(self) -> set[int]:
        """The lines of the error's conflict note (every statement of the conflict)."""
        for text in self.error.notes:
            if text.startswith("the conflicting statements"):
                return {int(x) for x in re.findall(r"line (\d+)", text)}
        return set()

    def lines_named(self) -> set[int]:
        """Every line number the error names: its location and its notes."""
        d = self.error
        found = {d.span.line} if d.span else set()
        for text in (d.message, *d.notes):
            for m in re.finditer(r"lines? ((?:\d+(?:, | and |-)?)+)", text):
                found.update(int(x) for x in re.findall(r"\d+", m.group(1)))
        return found


def _parse(source):
    from momentum_cli.syntax import parse

    return parse(source)


def same_answers(a: Outcome, b: Outcome, mapping: dict[str, str] | None = None) -> list[str]:
    """Differences between two solves' answers (b's names mapped back through a rename)."""
    problems = []
    back = {v: k for k, v in (mapping or {}).items()}
    bmap = {map_name(n, back): v for n, v in b.answers.items()}
    if set(a.answers) != set(bmap):
        return [f"answers differ: {sorted(a.answers)} vs {sorted(bmap)}"]
    for n, (x, ex) in a.answers.items():
        y, ey = bmap[n]
        if not (abs(x - y) <= ex + ey or (math.isnan(x) and math.isnan(y))):
            problems.append(f"{n}: {x!r} vs {y!r} (tolerance {ex + ey:.3g})")
    return problems
