"""Build, big files: bodies and impact contacts read from lines the parse kept as text.

A deferred item (statement_deferred) is a line of a shape the parse has a builder for:
every line of that shape is equal but for its digits, so each token sits at the same
columns. The first line of a shape is made into nodes and read by the scene's usual
code; what it tells (where the names and numbers are, the spans' columns, whether the
form is one this reads) is kept per shape as a recipe, and every other line of the shape
is read through it: names and numbers sliced from the text, the values the usual code
gave for the same literals reused, ~20 syntax records a line never made. Anything the
recipe does not cover (a name not yet declared, a value out of range, a ground or
surface contact, an error to report) goes to the usual code with the line's nodes, so
results and errors are those of `_Builder._body` and `_Builder._contact`.
"""
from __future__ import annotations

import math

from . import syntax as S
from .source import Span

_NUMBER = None  # the grammar's number (syntax_lines), set on first use


def _digits(s: str) -> bool:
    return any(ch in "0123456789" for ch in s)


def _number_end(s: str, c: int) -> int:
    global _NUMBER
    if _NUMBER is None:
        from .syntax_lines import _NUMBER as number

        _NUMBER = number
    m = _NUMBER.match(s, c)
    return -1 if m is None else m.end()


_MAKERS: dict = {}  # record class -> its maker (made once a process)


def _makers(classes) -> list:
    """A function making each class's records as its constructor does, faster
    (syntax_lines.maker: a plain twin of its slots, filled, then given the class)."""
    out = []
    for c in classes:
        got = _MAKERS.get(c)
        if got is None:
            from .syntax_lines import maker

            got = _MAKERS[c] = maker(c)
        out.append(got)
    return out


class Deferred:
    """The scene builder's reader of deferred items (one per build)."""

    def __init__(self, builder, scene):
        self.b = builder
        self.scene = scene  # the scene module (its records and tables)
        # the records made here, by makers that skip the frozen records' slot calls
        self.Span, self.Body, self.PointOn, self.Contact = _makers(
            (Span, scene.Body, scene.PointOn, scene.Contact))
        self._bodies: dict = {}  # make -> body recipe, or False (the usual code)
        self._contacts: dict = {}  # make -> contact recipe, or False
        self._impacts: dict = {}  # make -> impact-block recipe, or False
        self._clauses: dict = {}  # make -> its transition's clause count

    # ---- bodies
    def body(self, item) -> None:
        """`_Builder._body` of a deferred body line."""
        _, make, s, L = item
        r = self._bodies.get(make)
        if r is None:
            node = make(s, L)
            self.b._body(node)  # the shape's first line: the usual code (and its errors)
            self._bodies[make] = self._body_recipe(node, s)
            return
        if r is not False:
            n0, n1, nums, memo = r[:4]
            name = s[n0:n1]
            bodies = self.b.bodies
            if name not in bodies and name != "ground":
                if len(nums) == 1:
                    key = s[nums[0][0]:nums[0][1]]
                else:
                    key = tuple([s[c:e] for c, e in nums])  # () for no numbers
                got = memo.get(key)
                if got is None:
                    got = self._body_values(r, (key,) if len(nums) == 1 else key)
                    if got is not None and len(memo) < 512:
                        memo[key] = got
                if got is not None:
                    kind, m, inertia, formula, rad, length, point_mass, w, outline = got
                    bodies[name] = self.Body(name, self.Span(L, 1, L + 1, 1), kind, m, inertia,
                                             formula, rad, length, point_mass, (0.0, 0.0), w,
                                             outline)
                    return
        self.b._body(make(s, L))

    def _body_recipe(self, node, s: str):
        """Where a simple body's name and literal numbers are in its line, the shape,
        how each number is read and its constants' values; False when the line is not
        such a body."""
        sc, b = self.scene, self.b
        if node.composite or len(node.shapes) != 1 or sc._shape_key(node.shapes[0]) is None:
            return False
        shape = node.shapes[0]
        kind = shape.kind
        if kind not in sc.SHAPES or len({a.name for a in shape.args}) != len(shape.args):
            return False
        n0 = s.find(node.name, 4)
        if n0 < 0 or s[4:n0].strip(" ") or s[n0 + len(node.name):].lstrip(" ")[:1] != ":":
            return False
        nums, plan, fixed = [], [], {}
        for a in shape.args:
            v = a.value
            if _digits(a.name) or (type(v) is S.Num and _digits(v.unit or "")) or \
                    (type(v) is S.Ref and _digits(v.name)):
                return False  # the same shape could hold another name or unit there
            if type(v) is S.Num:
                c = v.span.column - 1
                e = _number_end(s, c)
                if e < 0 or v.span.line != node.span.line or float(s[c:e]) != v.value or \
                        v.unit is None:
                    return False
                zero_ok = (a.name == "radius" and kind in ("particle", "rigid")) or \
                    (a.name == "inertia" and kind == "rigid")
                nums.append((c, e))
                plan.append((a.name, (v.unit, sc.ARG_DIMS[a.name]), zero_ok))
            else:
                fixed[a.name] = (b.value(v, sc.ARG_DIMS[a.name], f"'{a.name}'"), None)
        # the drawing's sizes, when no number gives one: the same for every line
        sized = any(name in ("radius", "length", "width", "height") for name, _, _ in plan)
        outline = None if sized else ((kind, (0.0, 0.0), b._dims(shape, fixed), 0.0),)
        # a particle whose one number is its mass: `_Builder._simple` passes the mass
        # through and makes the rest from the constants, the same for every line
        rest = None
        if kind == "particle" and [name for name, _, _ in plan] == ["mass"]:
            got = self._body_values((None,) * 4 + (shape, fixed, (), outline, None),
                                    (), {"mass": (1.0, None)})
            rest = got[2:]
        return (n0, n0 + len(node.name), tuple(nums), {}, shape, fixed, tuple(plan), outline,
                rest)

    def _body_values(self, r, texts, args=None):
        """The body's (kind, mass, inertia, ...) from its numbers' texts as
        `_Builder._body` makes them, or None (then the usual code reads the line)."""
        shape, fixed, plan, outline, rest = r[4:]
        sc = self.scene
        factors, tiny, huge = sc._FACTORS, sc.TINY, sc.HUGE
        args = dict(fixed) if args is None else dict(fixed, **args)
        for (name, unit_dim, zero_ok), text in zip(plan, texts):
            factor = factors.get(unit_dim)
            if factor is None:
                return None
            v = float(text) * factor  # `_Builder._literal`'s product
            if not math.isfinite(v) or (v != 0 and abs(v) < tiny) or abs(v) > huge or \
                    (v <= 0 and not (zero_ok and v == 0)):
                return None  # the usual code reports it
            args[name] = (v, None)
            if rest is not None:  # a particle's mass: the rest is known
                return (shape.kind, v) + rest
        if len(args) > 1:
            args = {a.name: args[a.name] for a in shape.args}  # the usual code's order
        b = self.b
        kind = shape.kind
        m, inertia, formula, rad, length, w = b._simple(shape, args)
        point_mass = kind == "particle" or (kind == "rigid" and inertia == 0)
        if outline is None:
            outline = ((kind, (0.0, 0.0), b._dims(shape, args), 0.0),)
        return (kind, m, inertia, formula,
                rad if kind in sc.ROUND or kind in ("particle", "rigid") else None, length,
                point_mass, w, outline)

    # ---- contacts
    def contacts(self, clauses, i: int, kind: str, labels: set, out: list) -> int:
        """The Contacts of clauses[i:] while they are contact lines read through their
        recipe with results known (`_fast`) and new labels, appended to `out` (their
        labels to `labels`); the index of the first clause left to the caller."""
        b = self.b
        if b._contacts_seen is None or b.points:
            return i  # no memo, or named points: the usual code
        recipes, fast, bodies = self._contacts, self._fast, b.bodies
        n = len(clauses)
        while i < n:
            c = clauses[i]
            if c.__class__ is not tuple:
                break
            r = recipes.get(c[1])
            if not r:
                break
            con = fast(r, c[2], c[3], kind, bodies)
            if con is None or con.label in labels:
                break
            labels.add(con.label)
            out.append(con)
            i += 1
        return i

    def contact(self, item, kind: str, before):
        """The Contact of a deferred contact line by the usual code, whose results the
        line's recipe then keeps for `_fast`; None when the recipe cannot read the line
        (the caller reads its node the usual way)."""
        _, make, x, L = item
        r = self._contacts.get(make)
        if r is None:
            r = self._contacts[make] = self._contact_recipe(make(x, L), x)
        if r is False or self.b._contacts_seen is None:
            return None
        return self._slow(r, make(x, L), x, kind, before)

    def _slow(self, r, node, x: str, kind: str, before):
        """`_Builder._contact` of a line's node; its results kept by the line's recipe
        when the usual code keeps them (its memo) and the line's bodies are plain."""
        b = self.b
        con = b._contact(node, kind, before)  # the usual code, its memo filled
        seen = b._contacts_seen
        k = self.scene._contact_key(node, kind)
        if seen is not None and k is not None and k in seen and con.restitution_name is None:
            r[6][(kind, x[r[4]:])] = seen[k]
        return con

    def _contact_recipe(self, c, x: str):
        """The columns of a plain contact line's names and spans, and where its normal
        starts; False when it is not `contact [LABEL:] A with B normal (...): ...` with
        literal numbers."""
        a, b = c.a, c.b
        if b is None or a.member is not None or a.end is not None or b.member is not None \
                or b.end is not None or c.normal is None or type(c.normal) is not S.VecLit:
            return False
        if self.scene._contact_key(c, "impact") is None:
            return False
        line = c.span.line
        spans = [a.span, b.span, c.span, c.normal.span] + [p.span for p in c.props]
        if any(sp.line != line or sp.end_line != line for sp in spans):
            return False
        cols = []
        for ref in (a, b):
            p = ref.span.column - 1
            if x[p:p + len(ref.name)] != ref.name or ref.span.end_column - 1 != p + len(ref.name):
                return False
            cols.append((p, p + len(ref.name)))
        label = None
        if c.label is not None:
            p = x.index("contact") + 7
            while x[p:p + 1] == " ":
                p += 1
            if x[p:p + len(c.label)] != c.label:
                return False
            label = (p, p + len(c.label))
        props = tuple((p.span.column, p.span.end_column) for p in c.props)
        return (cols[0], cols[1], label, (c.span.column, c.span.end_column),
                c.normal.span.column - 1, props, {})  # the last: results by kind and text

    def _fast(self, r, x: str, L: int, kind: str, bodies):
        """The Contact of contact line x (line L) from its recipe, when its two names
        are two bodies and the results of its normal and properties are known; else
        None. What `_Builder._contact` makes of it: the bodies' centres as points."""
        (a0, a1), (b0, b1), label_at, (c0, c1), n0, props, hits = r
        hit = hits.get((kind, x[n0:]))
        if hit is None:
            return None
        na, nb = x[a0:a1], x[b0:b1]
        ba, bb = bodies.get(na), bodies.get(nb)
        if ba is None or bb is None or ba is bb:
            return None
        Span_, PointOn = self.Span, self.PointOn
        pa = PointOn(na, (0.0, 0.0), na, Span_(L, a0 + 1, L, a1 + 1), True, None)
        pb = PointOn(nb, (0.0, 0.0), nb, Span_(L, b0 + 1, L, b1 + 1), True, None)
        normal, e, e_unknown, mode, mu, slip, separation, law, law_at, mu_static = hit
        law_span = None
        if law_at >= 0:
            p0, p1 = props[law_at]
            law_span = Span_(L, p0, L, p1)
        # Contact's fields in order: label, span, a, b, normal, restitution,
        # restitution_unknown, mode, mu, slip, surface, restitution_name, separation, law,
        # law_span, mu_static
        return self.Contact(x[label_at[0]:label_at[1]] if label_at is not None else
                            f"{na}-{nb}", Span_(L, c0, L, c1), pa, pb, normal, e, e_unknown,
                            mode, mu, slip, None, None, separation, law, law_span, mu_static)

    # ---- impacts of one contact (a short block kept whole)
    def clause_count(self, item) -> int:
        """The number of clauses of a deferred transition."""
        if item[1].__name__ == "fill_transition":
            return len(item[2].clauses)
        n = self._clauses.get(item[1])
        if n is None:
            n = self._clauses[item[1]] = len(item[1](item[2], item[3]).clauses)
        return n

    def transition(self, item, states):
        """`_Builder._transition` of a deferred transition."""
        _, make, text, L = item
        b = self.b
        if make.__name__ == "fill_transition":
            return b._transition(text, states)  # its deferred contacts: `contact`
        r = self._impacts.get(make)
        if r is None:
            r = self._impacts[make] = self._impact_recipe(make(text, L), text)
        if r is not False:
            f0, f1, t0, t1, dl, nl, k = r
            before, after = text[f0:f1], text[t0:t1]
            spec = states.get(before)
            if spec is not None and after in states and before != after and \
                    b._contacts_seen is not None and not b.points:
                x = text[nl:]
                con = self._fast(k, x, L + 1, "impact", b.bodies)
                if con is None:
                    con = self._slow(k, make(text, L).clauses[0], x, "impact", spec)
                if con is not None:
                    sc = self.scene
                    t = sc.TransitionSpec(sc.TransitionKind.IMPACT, before, after,
                                          self.Span(L, 1, L + dl, 1))
                    t.contacts.append(con)
                    return t
        return b._transition(make(text, L), states)

    def _impact_recipe(self, t, text: str):
        """Where an impact of one contact line keeps its states, and its contact's
        recipe; False for any other transition."""
        lines = text.split("\n")
        if t.kind != "impact" or t.groups or len(t.clauses) != 1 or len(lines) != 2 or \
                type(t.clauses[0]) is not S.Contact:
            return False
        c = t.clauses[0]
        if c.span.line != t.span.line + 1:
            return False
        k = self._contact_recipe(c, lines[1])
        if k is False:
            return False
        got = []
        for sp, v in ((t.before_span, t.before), (t.after_span, t.after)):
            p = sp.column - 1
            if sp.line != t.span.line or lines[0][p:p + len(v)] != v:
                return False
            got.append((p, p + len(v)))
        if t.span.column != 1 or t.span.end_column != 1:
            return False
        return got[0] + got[1] + (t.span.end_line - t.span.line, len(lines[0]) + 1, k)
