"""Parse without lark: text -> statement nodes, driven by syntax_tables' tables.

In: the tables and the rule callbacks (syntax.Rules). Out: what lark's parse and then
the transformer give (same tokens, positions, callbacks, called as rules are reduced),
or Fallback for anything else (errors, deep trees): lark then parses and reports it.
"""
from __future__ import annotations

import re


class Fallback(Exception):
    """Not parsed here: parse with lark (which locates and words the error)."""


class Tok(str):
    """A token, as lark's Token: its text, terminal type and place (what the rule
    callbacks and the positions of their nodes read)."""

    def __new__(cls, type_, value, line, column, end_line, end_column):
        self = str.__new__(cls, value)
        self.type = type_
        self.line = line
        self.column = column
        self.end_line = end_line
        self.end_column = end_column
        return self

    def __repr__(self):
        return f"Tok({self.type!r}, {str(self)!r})"

    def __reduce__(self):  # pickle and copy (str's own would call __new__ with the text only)
        return (Tok, (self.type, str(self), self.line, self.column, self.end_line,
                      self.end_column))


class Box:
    """The place of a subtree (lark's Meta, as the rule callbacks and parents read it)."""

    __slots__ = ("line", "column", "end_line", "end_column")

    def __init__(self, line, column, end_line, end_column):
        self.line = line
        self.column = column
        self.end_line = end_line
        self.end_column = end_column


class Parser:
    """The tables made ready to run (regexes compiled when a lexer state is first used)."""

    def __init__(self, tables: dict, callbacks, max_height: int):
        states = tables["states"]
        self.states = [states[i] for i in range(len(states))]  # KeyError: not 0..n-1
        self.start, self.end = tables["start"], tables["end"]
        lexer_of = tables["state_lexer"]
        self.state_lexer = [lexer_of.get(i) for i in range(len(states))]
        self.lexers = tables["lexers"]
        self.scanners = [None] * len(self.lexers)
        self.ignore = frozenset(tables["ignore"])
        self.newline = frozenset(tables["newline"])
        self.indenter = tables["indenter"]
        self.max_height = max_height
        self.ok = True
        rules, through = [], []
        for origin, size, name, expand1, include in tables["rules"]:
            inline = origin == "start" or origin.startswith("_")
            cb = None if inline else getattr(callbacks, name, None)
            if cb is None and not inline and not expand1:
                self.ok = False  # a plain lark Tree would reach a callback: not reproduced
            # `?rule: child` (one symbol, kept): the child is the value, its container
            # unchanged (its only child's): the reduction only changes the state
            through.append(origin if expand1 and size == 1 and include is None else None)
            rules.append((origin, size, cb, inline, expand1, include,
                          include[0][0] if include else 0))
        self.rules, self.through = rules, through

    def _scanner(self, i: int):
        import marshal

        mres, unless = self.lexers[i]
        compiled = []
        for pattern, flags, args in marshal.loads(mres):
            made = None
            if args is not None:
                try:
                    import _sre

                    made = _sre.compile(*args)
                except Exception:  # another regex engine: compile the pattern itself
                    made = None
            compiled.append(made if made is not None else re.compile(pattern, flags))
        self.scanners[i] = sc = (tuple(compiled), unless)
        return sc

    def parse(self, text: str, line: int = 1) -> list:
        """The start rule's children (statement nodes) of `text`, or Fallback; `line`:
        the number of its first line (a statement parsed alone, at its place in a file)."""
        try:
            return self._parse(text, line)
        except Fallback:
            raise
        except Exception:  # a callback's error, a malformed indent...: lark's to report
            raise Fallback from None

    def _parse(self, text: str, first_line: int) -> list:
        states, rules, through, end = self.states, self.rules, self.through, self.end
        max_height = self.max_height
        stack, vals, boxes, hs = [self.start], [], [], []

        def feed(tok, ttype) -> bool:
            """Lark's feed_token; True when the input is accepted ($END)."""
            while True:
                act = states[stack[-1]].get(ttype)
                if act is None:
                    raise Fallback
                if act >= 0:
                    stack.append(act)
                    vals.append(tok)
                    boxes.append(tok)
                    hs.append(0)
                    return False
                o = through[~act]
                if o is not None:
                    stack[-1] = states[stack[-2]][o]
                    if tok is None and stack[-1] == end:
                        return True
                    continue
                origin, size, cb, inline, expand1, include, first_i = rules[~act]
                if size:
                    raw, rb, rh = vals[-size:], boxes[-size:], hs[-size:]
                    del stack[-size:], vals[-size:], boxes[-size:], hs[-size:]
                    first, last = rb[0], rb[-1]  # the first and last child with a place
                    if first is None:
                        for b in rb:
                            if b is not None:
                                first = b
                                break
                    if last is None:
                        for b in reversed(rb):
                            if b is not None:
                                last = b
                                break
                    h = max(rh) if size > 1 else rh[0]
                else:
                    raw, rb, rh, first, last, h = [], [], [], None, None, 0
                if include is None:
                    ch = raw
                else:
                    ch = []
                    for i, inl in include:
                        if not inl:
                            ch.append(raw[i])
                        elif ch:
                            ch.extend(raw[i])
                        else:  # left recursion: grow the list in place (lark does too)
                            ch = raw[i]
                if expand1 and len(ch) == 1:
                    # `?rule` with one child: the child, in this rule's container
                    val = ch[0]
                    if rh[first_i] > 0:
                        if rb[first_i] is None:
                            raise Fallback
                        box = Box(first.line, first.column, last.end_line, last.end_column)
                    else:
                        box = rb[first_i]
                else:
                    box = None if first is None else \
                        Box(first.line, first.column, last.end_line, last.end_column)
                    if inline:  # an inlined `_rule` or `start`: its children
                        val = ch
                    else:
                        if box is None or cb is None:
                            raise Fallback
                        val = cb(box, ch)
                        h += 1
                        if h > max_height:
                            raise Fallback
                stack.append(states[stack[-1]][origin])
                vals.append(val)
                boxes.append(box)
                hs.append(h)
                if tok is None and stack[-1] == end:
                    return True

        nl_type, opens, closes, indent_type, dedent_type, tab_len = self.indenter
        state_lexer, scanners = self.state_lexer, self.scanners
        ignore, newline = self.ignore, self.newline
        n, pos, line, ls = len(text), 0, first_line, 0
        paren, levels, last = 0, [0], None
        while pos < n:
            li = state_lexer[stack[-1]]
            mres, unless = scanners[li] or self._scanner(li)
            for mre in mres:
                m = mre.match(text, pos)
                if m:
                    break
            else:
                raise Fallback
            value, type_ = m.group(), m.lastgroup
            sline, scol = line, pos - ls + 1
            if type_ in newline:
                k = value.count("\n")
                if k:
                    line += k
                    ls = pos + value.rindex("\n") + 1
            pos = m.end()
            if type_ in ignore:
                continue
            u = unless.get(type_)
            if u is not None:
                type_ = u.get(value, type_)
            last = tok = Tok(type_, value, sline, scol, line, pos - ls + 1)
            if type_ == nl_type:
                if not paren:
                    feed(tok, type_)
                    indent_str = value.rsplit("\n", 1)[1]
                    indent = indent_str.count(" ") + indent_str.count("\t") * tab_len
                    if indent > levels[-1]:
                        levels.append(indent)
                        feed(Tok(indent_type, indent_str, sline, scol, line, tok.end_column),
                             indent_type)
                    else:
                        while indent < levels[-1]:
                            levels.pop()
                            feed(Tok(dedent_type, indent_str, sline, scol, line,
                                     tok.end_column), dedent_type)
                        if indent != levels[-1]:
                            raise Fallback
            else:
                feed(tok, type_)
            if type_ in opens:
                paren += 1
            elif type_ in closes:
                paren -= 1
                if paren < 0:
                    raise Fallback
        while len(levels) > 1:
            levels.pop()
            t = last
            feed(Tok(dedent_type, "", t.line, t.column, t.end_line, t.end_column), dedent_type)
        if not feed(None, "$END"):
            raise Fallback
        return vals[-1]
