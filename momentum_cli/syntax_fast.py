"""Parse big files fast: text -> the same lark tree the whole-file parse gives, or None.

A big file repeats a few statement shapes with other names and numbers. Each top-level
statement, each line of a long block and each item of a long comma list is parsed by the
real lark parser once per shape (its text with every digit written 0: the grammar's
terminals see digits only as a class, so the tokens and the tree are the same) and copies
of that tree are moved into place. None (parse the whole text) wherever that is not safe.
"""
from __future__ import annotations

import re

_MASK = bytes.maketrans(b"123456789", b"000000000")
BUILD_AFTER = 24  # uses of a template before its copying function is written
_LINE_COL = (("line", "column"), ("end_line", "end_column"),
             ("container_line", "container_column"),
             ("container_end_line", "container_end_column"))
_POS = ("start_pos", "end_pos", "container_start_pos", "container_end_pos")
_SCAN = re.compile(r'"[^"\n]*"|#[^\n]*|[()\[\]{},]')
_BRACKETS = re.compile(r'"[^"\n]*"|#[^\n]*')
MIN_ITEMS = 8  # a block or list shorter than this is one statement parse
LONG_LINE = 200  # characters: a shorter line is one statement parse


class _Refuse(Exception):
    """This text cannot be assembled safely: parse it whole."""


def fast_tree(text: str, parse):
    """The parse tree of `text` (ending in a newline) assembled from parses of its repeated
    shapes by `parse` (lark's), or None: continuation lines, tabs, CR, brackets open across
    lines, indented first statement. Lark's errors propagate (the caller re-parses whole)."""
    if not text.endswith("\n") or "\\" in text or "\r" in text or "\t" in text or \
            "\f" in text:
        return None
    lines = text.split("\n")
    n = len(lines) - 1
    clean = _BRACKETS.sub("", text).split("\n")
    starts, pos = [], 0
    heads = []
    for i in range(n):
        x = lines[i]
        c = clean[i]
        if c.count("(") != c.count(")") or c.count("[") != c.count("]") or \
                c.count("{") != c.count("}"):
            return None
        starts.append(pos)
        pos += len(x) + 1
        if x and x[0] not in " #" and c.strip():
            heads.append(i)
        elif not heads and c.strip():
            return None  # an indented line before any statement
    starts.append(pos)
    if not heads:
        return None
    heads[0] = 0
    heads.append(n)
    import gc

    asm = _Assembler(text, lines, starts, clean, parse)
    collect = gc.isenabled()
    gc.disable()  # 10^5 new nodes, none garbage: the collector's passes would cost more
    try:
        children = []
        first = last = None
        for a, b in zip(heads, heads[1:]):
            root = asm.chunk(a, b)
            children.extend(root.children)
            first = first or root
            last = root
    except _Refuse:
        return None
    finally:
        if collect:
            gc.enable()
    from lark import Tree
    from lark.tree import Meta

    meta = Meta()
    _copy_meta(meta, first, last)
    return Tree("start", children, meta)


def _copy_meta(meta, first, last) -> None:
    """Start positions from `first`, end positions from `last` (both already in place)."""
    fd, ld, d = first.meta.__dict__, last.meta.__dict__, meta.__dict__
    for k in ("empty", "line", "column", "start_pos", "container_line", "container_column",
              "container_start_pos"):
        if k in fd:
            d[k] = fd[k]
    for k in ("end_line", "end_column", "end_pos", "container_end_line",
              "container_end_column", "container_end_pos"):
        if k in ld:
            d[k] = ld[k]
    if "empty" in ld and not ld["empty"]:
        d["empty"] = False


class _Assembler:
    def __init__(self, text, lines, starts, clean, parse):
        from lark import Token, Tree
        from lark.tree import Meta

        self.text, self.lines, self.starts, self.clean = text, lines, starts, clean
        self.parse = parse
        self.cache: dict[str, object] = {}
        self.builders: dict[tuple, tuple] = {}
        self.Token, self.Tree, self.Meta = Token, Tree, Meta

    def template(self, key: str, iso: str):
        """The parse of `iso`, once per key; every token must be the text at its place."""
        t = self.cache.get(key)
        if t is None:
            t = self.cache[key] = self.parse(iso)
            for tok in t.scan_values(lambda v: isinstance(v, self.Token)):
                if iso[tok.start_pos:tok.end_pos] != tok.value:
                    raise _Refuse
        return t

    def chunk(self, a: int, b: int):
        """The `start` tree of lines a..b (one top-level statement and the blank and
        comment lines after it), in place."""
        text, starts, lines, clean = self.text, self.starts, self.lines, self.clean
        s, e = starts[a], starts[b]
        content = [i for i in range(a + 1, b) if clean[i].strip()]
        if len(content) >= max(MIN_ITEMS, 3):
            ind = lines[content[0]][:len(lines[content[0]]) - len(lines[content[0]].lstrip(" "))]
            if ind and all(lines[i].startswith(ind) and lines[i][len(ind)] != " "
                           for i in content):
                return self.items(a, s, starts[content[0]] + len(lines[content[0]]), "\n",
                                  [(starts[i], starts[i] + len(lines[i]), i, 0)
                                   for i in content[1:]], e)
        if not content and len(lines[a]) > LONG_LINE:
            cuts = self.commas(a)
            if len(cuts) >= max(MIN_ITEMS, 2):
                ls = starts[a]
                bounds = cuts + [len(lines[a])]
                return self.items(a, s, ls + cuts[0], ",",
                                  [(ls + c + 1, ls + d, a, c + 1)
                                   for c, d in zip(bounds, bounds[1:])], e)
        seg = text[s:e]
        return self.moved(self.template(seg.encode().translate(_MASK), seg), (a, s, 0, 0, text))

    def commas(self, i: int) -> list[int]:
        """Offsets of the commas outside brackets, strings and comments of line i."""
        depth, out = 0, []
        for m in _SCAN.finditer(self.lines[i]):
            ch = m.group()
            if ch == ",":
                if depth == 0:
                    out.append(m.start())
            elif ch in "([{":
                depth += 1
            elif ch in ")]}":
                depth -= 1
        return out

    def items(self, a, s, base_end, sep, items, e):
        """A statement whose text is base, then items each after `sep`: the base parsed
        once, each item parsed after the base once per shape, their trees spliced; the
        splice of the first two is checked against their parse together."""
        text = self.text
        base = text[s:base_end]
        b = self.parse(base + "\n")
        lead = len(base) + len(sep)
        lead_line = base.count("\n") + 1 + (sep == "\n")
        lead_col = lead - (base.rfind("\n") + 1 if sep != "\n" else lead)
        shifts, trees = [], []
        last = len(items) - 1
        for k, (p, q, line, col) in enumerate(items):
            seg = text[p:q] if k < last else text[p:e]
            iso = base + sep + seg + ("\n" if k < last else "")
            key = (base, seg.encode().translate(_MASK)) if k < last else None
            t = self.template(key, iso) if key is not None else self.parse(iso)
            trees.append(t)
            shifts.append((line - (lead_line - 1), p - lead, col - lead_col, lead_line))
        got = self.splice(b, trees, [sh + (text,) for sh in shifts], (a, s, 0, 0, text))
        # check: the first two items spliced equal their parse together
        (p0, q0, l0, c0), (p1, q1, l1, c1) = items[0], items[1]
        two = self.parse(base + sep + text[p0:q1] + "\n")
        one = self.parse(base + sep + text[p1:q1] + "\n")
        iso = base + sep + text[p0:q1] + "\n"
        spliced = self.splice(b, [trees[0], one],
                              [(0, 0, 0, lead_line, iso),
                               (l1 - l0, p1 - p0, c1 - c0, lead_line, iso)],
                              (0, 0, 0, 0, iso))
        if not same_tree(spliced, two):
            raise _Refuse
        return got

    def splice(self, b, ts, shifts, bshift):
        """Node `b` of the base with the items' extra children appended where they
        first differ in length (at this node, or inside its last child)."""
        n = len(b.children)
        if all(len(t.children) == n for t in ts):
            if not n or not isinstance(b.children[-1], self.Tree):
                raise _Refuse
            kids = [self.moved(c, bshift) for c in b.children[:-1]]
            kids.append(self.splice(b.children[-1], [t.children[-1] for t in ts], shifts,
                                    bshift))
        else:
            kids = [self.moved(c, bshift) for c in b.children]
            for t, sh in zip(ts, shifts):
                if len(t.children) <= n or t.data != b.data:
                    raise _Refuse
                kids.extend(self.moved_all(t, n, sh))
        meta = self.Meta()
        first = self.Tree(b.data, [], self.moved_meta(b._meta, bshift))
        lastt = self.Tree(b.data, [], self.moved_meta(ts[-1]._meta, shifts[-1]))
        _copy_meta(meta, first, lastt)
        return self.Tree(b.data, kids, meta)

    def moved_meta(self, m, shift):
        dl, dp, dc, cl = shift[:4]
        meta = self.Meta()
        if m is None:
            return meta
        d = meta.__dict__
        d.update(m.__dict__)
        for lk, ck in _LINE_COL:
            if lk in d:
                if d[lk] == cl:
                    d[ck] += dc
                d[lk] += dl
        for k in _POS:
            if k in d:
                d[k] += dp
        return meta

    def moved(self, node, shift):
        """A copy of template `node` shifted by (lines, chars, columns on the template's
        line `cl`), its tokens' text read from `text`."""
        return self.moved_all(node, 0, shift, True)

    def moved_all(self, node, n, shift, one=False):
        """Copies of `node` (one) or of `node`'s children from the n-th on, built by a
        function written once per template node (copying 10^5 nodes one by one through
        lark's constructors is most of the time otherwise)."""
        dl, dp, dc, cl, text = shift
        key = (id(node), n, cl, one)
        hit = self.builders.get(key)
        if hit is None or hit[0] is not node:
            hit = self.builders[key] = [node, 0]
        if hit[1].__class__ is int:
            hit[1] += 1
            if hit[1] >= BUILD_AFTER:
                hit[1] = _builder([node] if one else node.children[n:], cl)
            elif one:
                return self.copy(node, shift)
            else:
                return [self.copy(c, shift) for c in node.children[n:]]
        out = hit[1](text, dl, dp, dc)
        return out[0] if one else out

    def copy(self, node, shift):
        """`moved` one node at a time (templates used a few times)."""
        dl, dp, dc, cl, text = shift
        Token = self.Token
        if isinstance(node, Token):
            return Token(node.type, text[node.start_pos + dp:node.end_pos + dp],
                         node.start_pos + dp, node.line + dl,
                         node.column + dc if node.line == cl else node.column,
                         node.end_line + dl,
                         node.end_column + dc if node.end_line == cl else node.end_column,
                         node.end_pos + dp)
        return self.Tree(node.data, [self.copy(c, shift) for c in node.children],
                         self.moved_meta(node._meta, shift) if node._meta is not None else None)


def _builder(nodes, cl):
    """A function (text, dl, dp, dc) -> copies of `nodes` moved by dl lines and dp
    characters, dc columns on template line `cl`, tokens' text read from `text`."""
    from lark import Token, Tree
    from lark.tree import Meta

    body, consts = [], []
    count = [0]

    def var() -> str:
        count[0] += 1
        return f"v{count[0]}"

    def col(value, line):
        return f"{value} + dc" if line == cl else repr(value)

    def meta(m) -> str:
        if m is None:
            return "None"
        items = []
        d = m.__dict__
        cols = {ck: lk for lk, ck in _LINE_COL}
        for k, value in d.items():
            if k in cols and cols[k] in d:
                items.append(f"{k!r}: {col(value, d[cols[k]])}")
            elif any(k == lk for lk, _ in _LINE_COL):
                items.append(f"{k!r}: {value} + dl")
            elif k in _POS:
                items.append(f"{k!r}: {value} + dp")
            elif isinstance(value, (bool, int)):
                items.append(f"{k!r}: {value!r}")
            else:
                consts.append(value)
                items.append(f"{k!r}: _K[{len(consts) - 1}]")
        v = var()
        body.append(f"{v} = _onew(_Meta); {v}.__dict__ = {{{', '.join(items)}}}")
        return v

    def emit(node) -> str:
        v = var()
        if isinstance(node, Token):
            s, e = node.start_pos, node.end_pos
            body.append(f"s = text[{s} + dp:{e} + dp]; {v} = _snew(_Token, s); "
                        f"{v}.type = {str(node.type)!r}; {v}.value = s; "
                        f"{v}.start_pos = {s} + dp; {v}.end_pos = {e} + dp; "
                        f"{v}.line = {node.line} + dl; {v}.end_line = {node.end_line} + dl; "
                        f"{v}.column = {col(node.column, node.line)}; "
                        f"{v}.end_column = {col(node.end_column, node.end_line)}")
            return v
        kids = [emit(c) for c in node.children]
        m = meta(node._meta)
        consts.append(node.data)  # a str, or a Token('RULE', ...) from a fresh parser
        body.append(f"{v} = _onew(_Tree); {v}.data = _K[{len(consts) - 1}]; "
                    f"{v}.children = [{', '.join(kids)}]; {v}._meta = {m}")
        return v

    out = [emit(x) for x in nodes]
    src = "def build(text, dl, dp, dc):\n" + "".join(f"    {x}\n" for x in body) + \
        f"    return [{', '.join(out)}]\n"
    scope = {"_onew": object.__new__, "_snew": str.__new__, "_Token": Token, "_Tree": Tree,
             "_Meta": Meta, "_K": consts}
    exec(compile(src, "<syntax_fast>", "exec"), scope)
    return scope["build"]


def same_tree(x, y) -> bool:
    """Equal trees, every token's type, text and position and every node's meta too."""
    from lark import Token, Tree

    if isinstance(x, Token) or isinstance(y, Token):
        return isinstance(x, Token) and isinstance(y, Token) and x.type == y.type and \
            str(x) == str(y) and all(getattr(x, k) == getattr(y, k) for k in
                                     ("start_pos", "line", "column", "end_line",
                                      "end_column", "end_pos"))
    if not (isinstance(x, Tree) and isinstance(y, Tree)) or x.data != y.data or \
            len(x.children) != len(y.children):
        return False
    mx = x._meta.__dict__ if x._meta is not None else {}
    my = y._meta.__dict__ if y._meta is not None else {}
    if mx != my:
        return False
    return all(same_tree(a, b) for a, b in zip(x.children, y.children))
