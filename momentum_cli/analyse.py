"""Analyse: the structure of an equation system before any number is computed.

Unknowns and equations form a bipartite graph. A maximum matching and the
Dulmage-Mendelsohn decomposition name the under-determined unknowns and the
over-determined (redundant) equations; strongly connected components of the
matched graph give the block-lower-triangular order in which the rest is solved.
"""
from __future__ import annotations

from . import rowcode
from .compile import System
from .expr import variables
from .records import record


@record
class Block:
    index: int
    equations: list[int]  # equation indices
    unknowns: list[str]
    depends: set[int]  # indices of blocks this one needs first (read only)


NO_DEPENDS = frozenset()  # shared by the blocks that need none (a set each: 216 bytes)


PACK_FROM = 2000  # equations from which `Structure.pack` pays (a small file's: not worth it)


@record
class Structure:
    incidence: list[set[str]]  # unknowns of each equation
    # equation -> its matched unknown, and back (the `match_eq`, `match_var` properties):
    # None until asked, made then from `_walk` (only an inconsistent equation's message
    # reads them: two dicts an equation the solve never needs)
    _match_eq: dict[int, str] | None
    _match_var: dict[str, int] | None
    under: set[str]  # unknowns not determined
    under_eqs: set[int]
    redundant: list[int]  # equations left over: checked after solving
    blocks: list[Block]  # in solving order
    # unknown -> its block (the `block_of_var` property): None until asked, `needed_blocks`
    # reads `_walk`'s lists instead (a dict of every unknown made for a few look-ups)
    _block_of_var: dict[str, int] | None
    constant_eqs: list[int]  # equations with no unknowns (pure checks)
    # `analyse`'s integer walk: (eq_first, var_first, meq, mvar, col_name, rank, det,
    # block_of_eq); None once the three dicts were replaced (run._shed)
    _walk: tuple | None = None

    @property
    def match_eq(self) -> dict[int, str]:
        if self._match_eq is None:
            eq_first, _, meq, _, col_name, _, _, _ = self._walk
            self._match_eq = dict(zip(eq_first, map(col_name.__getitem__,
                                                    map(meq.__getitem__, eq_first))))
        return self._match_eq

    @match_eq.setter
    def match_eq(self, value) -> None:
        self._match_eq = value
        self._replaced()

    @property
    def match_var(self) -> dict[str, int]:
        if self._match_var is None:
            _, var_first, _, mvar, col_name, _, _, _ = self._walk
            self._match_var = dict(zip(map(col_name.__getitem__, var_first),
                                       map(mvar.__getitem__, var_first)))
        return self._match_var

    @match_var.setter
    def match_var(self, value) -> None:
        self._match_var = value
        self._replaced()

    @property
    def block_of_var(self) -> dict[str, int]:
        if self._block_of_var is None:
            _, _, meq, _, col_name, _, det, block_of_eq = self._walk
            self._block_of_var = dict(zip(map(col_name.__getitem__, map(meq.__getitem__, det)),
                                          map(block_of_eq.__getitem__, det)))
        return self._block_of_var

    @block_of_var.setter
    def block_of_var(self, value) -> None:
        self._block_of_var = value
        self._replaced()

    def _replaced(self) -> None:
        """The dicts (in the order the string-keyed walk filled them) are made from the
        walk's lists: once all three were given, nothing is left to make from them."""
        if self._match_eq is not None and self._match_var is not None and \
                self._block_of_var is not None:
            self._walk = None

    def pack(self) -> None:
        """The walk's integer lists as arrays of machine integers, for a structure the
        solve rounds are done with (only an error message's dicts read them then): an
        int object and a list slot an entry (~36 bytes) become 8 bytes, ~24 MB at 10^5
        balls freed before the error bounds' peak (and the columns' dict, ~20 MB). The same
        numbers, read the same way."""
        w = self._walk
        if w is None or len(w[2]) < PACK_FROM:
            return
        from array import array

        eq_first, var_first, meq, mvar, col_name, _rank, det, block_of_eq = w
        # the columns' dict (name -> column) goes too: `needed_blocks` makes it again
        self._walk = (array("q", eq_first), array("q", var_first), array("q", meq),
                      array("q", mvar), col_name, None, array("q", det),
                      array("q", block_of_eq))

    def needed_blocks(self, names) -> list[int]:
        """The blocks that determine `names`, with everything they depend on, in order."""
        if self._block_of_var is None:  # an unknown's column, its equation, its block
            _, _, _, mvar, col_name, rank, _, block_of_eq = self._walk
            if rank is None:  # packed: the columns' dict as analyse made it
                rank = {n: i for i, n in enumerate(col_name)}
            todo = []
            for n in names:
                c = rank.get(n)
                if c is not None:
                    k = mvar[c]
                    if k >= 0 and block_of_eq[k] >= 0:
                        todo.append(block_of_eq[k])
        else:
            todo = [self._block_of_var[n] for n in names if n in self._block_of_var]
        seen: set[int] = set()
        while todo:
            b = todo.pop()
            if b in seen:
                continue
            seen.add(b)
            todo.extend(self.blocks[b].depends)
        return sorted(seen)

    def undetermined_for(self, names) -> list[str]:
        """The under-determined unknowns that `names` need (directly or through blocks)."""
        if not self.under:  # nothing is under-determined: no walk of the blocks
            return []
        out = {n for n in names if n in self.under}
        for b in self.needed_blocks(names):
            for e in self.blocks[b].equations:
                out.update(v for v in self.incidence[e] if v in self.under)
        # the unknowns coupled with them through the undetermined equations
        todo = list(out)
        while todo:
            v = todo.pop()
            for k in self.under_eqs:
                if v in self.incidence[k]:
                    for w in self.incidence[k]:
                        if w in self.under and w not in out:
                            out.add(w)
                            todo.append(w)
        return sorted(out)


def analyse(system: System, excluded=frozenset(), known=None) -> Structure:
    """The structure of `system`; `excluded` equations are left unmatched (numerically
    dependent rows: checked after solving), `known` unknowns are treated as given.

    Every choice (matching, blocks) follows the order in which the unknowns and
    equations were compiled (the file's statements), never their names: renaming the
    bodies changes no block. The graph is walked on integers (an unknown is its column,
    its rank in compile order), the dicts and sets of the result are filled in the
    order the string-keyed walk filled them (tests/reference_analyse.py).
    """
    eqs = system.equations
    known = known or {}
    full = _incidence(eqs)
    rank = {n: i for i, n in enumerate(system.unknowns)}
    col_name = list(rank)
    cols = _columns(full.rows, rank, col_name, known)  # each equation's sorted columns
    n_cols = len(col_name)
    n_eqs = len(eqs)
    stated = [k for k, e in enumerate(eqs) if e.kind in _STATED]
    constant = [k for k in range(n_eqs) if not cols[k]]
    # auto equations first: stated principles then become the checks when redundant
    if constant:
        order = [k for k in range(n_eqs) if cols[k]]
    else:
        order = list(range(n_eqs))
    if stated:
        is_stated = [False] * n_eqs
        for k in stated:
            is_stated[k] = True
        order = [k for k in order if not is_stated[k]] + [k for k in order if is_stated[k]]
        # auto equations are matched first, on their own; the principles a user states
        # (and free equations) then only take unknowns the scene left undetermined, so a
        # redundant statement becomes a check instead of displacing a derived equation
        auto = [k for k in order if not is_stated[k] and k not in excluded]
        extra = [k for k in order if is_stated[k] and k not in excluded]
    else:
        auto = [k for k in order if k not in excluded] if excluded else order
        extra = []
    matchable = cols
    if system.integrations:  # an integration sets its outputs from its inputs, not the reverse
        from .integration import matched_outputs

        matchable = list(cols)
        for k, out in matched_outputs(system).items():
            if out in full[k] and out not in known:
                matchable[k] = [rank[out]]
    meq = [-1] * n_eqs  # equation -> its matched column
    mvar = [-1] * n_cols  # column -> its matched equation
    eq_first: list[int] = []  # equations and columns in the order they were first matched
    var_first: list[int] = []
    for k in auto:  # cheap greedy pass first
        for v in matchable[k]:
            if mvar[v] < 0:
                mvar[v] = k
                meq[k] = v
                eq_first.append(k)
                var_first.append(v)
                break
    if len(eq_first) < len(auto):
        _augment(auto, matchable, meq, mvar, eq_first, var_first)
    if extra:
        _augment(extra, matchable, meq, mvar, eq_first, var_first)
    under: set[str] = set()
    under_eqs: set[int] = set()
    mvar_all = mvar
    if len(var_first) < n_cols:  # unmatched unknowns: some may be under-determined
        eq_under = _under(cols, known, rank, col_name, meq, mvar, under, under_eqs)
        redundant = [k for k in order if meq[k] < 0]
        det = [k for k in order if meq[k] >= 0 and not eq_under[k]]
    else:
        eq_under = None
        if len(eq_first) < len(order):
            redundant = [k for k in order if meq[k] < 0]
            det = [k for k in order if meq[k] >= 0]
        else:
            redundant = []
            det = order
    # BLT over the matched, determined equations (Tarjan's SCC, iterative)
    if eq_under is not None:  # an under-determined equation is no one's successor
        mvar = [-1 if k < 0 or eq_under[k] else k for k in mvar]
    blocks, block_of_eq = _blt(det, cols, mvar, meq, col_name, n_eqs)
    return Structure(full, None, None, under, under_eqs, redundant, blocks, None, constant,
                     (eq_first, var_first, meq, mvar_all, col_name, rank, det, block_of_eq))


_STATED = ("stated", "user")  # the kinds matched after the scene's own equations


def _columns(rows, rank: dict, col_name: list, known) -> list[list[int]]:
    """Each equation's unknowns as sorted columns (ranks in compile order). An unknown
    not compiled as one gets the next column, met in the order the string-keyed walk
    met it (each equation's set of names)."""
    getitem = rank.__getitem__
    cols = []
    append = cols.append
    for row in rows:
        if known:
            row = {v for v in (row if type(row) is set else set(row)) if v not in known}
        try:
            c = sorted({*map(getitem, row)})
        except KeyError:  # a name that is no compiled unknown: a new column
            c = []
            for v in (row if type(row) is set else set(row)):
                r = rank.get(v)
                if r is None:
                    r = rank[v] = len(col_name)
                    col_name.append(v)
                c.append(r)
            c.sort()
        append(c)
    return cols


def _under(cols, known, rank, col_name, meq, mvar, under, under_eqs) -> list[bool]:
    """Dulmage-Mendelsohn: the under-determined unknowns (into `under`) are those
    reachable from unmatched unknowns by alternating paths (unknown -> equation
    containing it -> that equation's unknown); their equations go into `under_eqs`.
    Each equation: whether it is one of them."""
    n_cols = len(col_name)
    var_eqs: list[list[int]] = [[] for _ in range(n_cols)]
    for k, row in enumerate(cols):
        for v in row:
            var_eqs[v].append(k)
    present = [True] * n_cols  # the unknowns the analysis is over (not known)
    get = rank.get
    for n in known:
        r = get(n)
        if r is not None and not var_eqs[r]:
            present[r] = False
    in_under = [False] * n_cols
    eq_under = [False] * len(cols)
    stack = [v for v in range(n_cols) if present[v] and mvar[v] < 0]
    while stack:
        v = stack.pop()
        if in_under[v]:
            continue
        in_under[v] = True
        under.add(col_name[v])
        for k in var_eqs[v]:
            if meq[k] >= 0 and not eq_under[k]:
                eq_under[k] = True
                under_eqs.add(k)
                stack.append(meq[k])
    return eq_under


class Incidence:
    """Each equation's unknowns, as a set when asked (`expr.variables`'s set, or the set
    of the names its residual's shape lists). The solve asks for few of them (redundant,
    constant and conflicting equations): a row is held as the shape's tuple of names
    (shared with the shape) instead of a set of its own (216 bytes an equation)."""

    __slots__ = ("rows",)

    def __init__(self, rows: list):
        self.rows = rows

    def __getitem__(self, k) -> set[str]:
        row = self.rows[k]
        return row if type(row) is set else set(row)

    def __len__(self) -> int:
        return len(self.rows)

    def __iter__(self):
        for row in self.rows:
            yield row if type(row) is set else set(row)

    def __eq__(self, other) -> bool:
        try:
            return len(self) == len(other) and all(a == b for a, b in zip(self, other))
        except TypeError:
            return NotImplemented

    __hash__ = None

    def __repr__(self) -> str:
        return f"Incidence({list(self)!r})"


def _incidence(eqs) -> Incidence:
    """Each equation's unknowns (`expr.variables`). Within a solve (`rowcode.remembered`
    open) from each residual's shape, which the solve then reads again instead of walking
    the tree a second time: a shape names exactly the unknowns `variables` finds."""
    if not (rowcode.ENABLED and rowcode._ON[0]) or rowcode._PLAIN[0]:
        return Incidence([variables(e.residual) for e in eqs])
    shape_of = rowcode.shape_of
    out = []
    for e in eqs:
        r = e.residual
        sh = shape_of(r)
        out.append(sh[2] if sh is not None else variables(r))
    return Incidence(out)


def _augment(order: list[int], incidence: list[list[int]], meq: list[int], mvar: list[int],
             eq_first: list[int], var_first: list[int]) -> None:
    """Extend a matching by augmenting paths from each unmatched equation of `order`
    (iterative DFS, each equation's columns in order; a new equation and the free
    column that ends its path are appended to eq_first and var_first)."""
    seen = [-1] * len(mvar)  # the equation whose search last visited the column
    parent = [0] * len(mvar)
    for k in order:
        if meq[k] >= 0:
            continue
        stack = [(k, iter(incidence[k]))]
        found = -1
        while stack:
            e, it = stack[-1]
            # look ahead: an unmatched unknown of this equation ends the path at once
            # (keeps chains of contacts linear instead of quadratic)
            for v in incidence[e]:
                if mvar[v] < 0 and seen[v] != k:
                    seen[v] = k
                    parent[v] = e
                    found = v
                    break
            if found >= 0:
                break
            for v in it:
                if seen[v] == k:
                    continue
                seen[v] = k
                parent[v] = e
                if mvar[v] < 0:
                    found = v
                    break
                stack.append((mvar[v], iter(incidence[mvar[v]])))
                break
            else:
                stack.pop()
            if found >= 0:
                break
        if found < 0:
            continue
        eq_first.append(k)
        var_first.append(found)
        v = found
        while True:
            e = parent[v]
            prev = meq[e]
            meq[e] = v
            mvar[v] = e
            if e == k:
                break
            v = prev


def _blt(det: list[int], cols: list, mvar: list[int], meq: list[int], col_name: list,
         n: int) -> tuple[list[Block], list[int]]:
    """The blocks of the equations `det` in solving order, and each equation's block:
    Tarjan's walk (iterative; a node whose successors are all finished is its own component at once, where the full walk would emit it too, without entering the walk), each component
    made a Block as it is emitted, and an equation's successors (the equations matched
    to its other columns, `mvar`: -1 for none) listed as the walk first reaches it. One
    pass over the equations instead of three (successor lists, components, blocks): a
    big scene's blocks are mostly one equation whose successors are all done, made at
    once where the walk meets it."""
    at = mvar.__getitem__
    succ: list = [None] * n
    index = [-1] * n
    low = [0] * n
    on = [False] * n
    block_of_eq = [-1] * n
    blocks: list[Block] = []
    stack: list[int] = []
    counter = 0
    for root in det:
        if index[root] >= 0:
            continue
        ws = succ[root] = [d for d in map(at, cols[root]) if d != root and d >= 0]
        for x in ws:
            if index[x] < 0 or on[x]:
                break
        else:  # every successor finished: a block of its own, now
            index[root] = counter
            counter += 1
            idx = block_of_eq[root] = len(blocks)
            blocks.append(Block(idx, [root], [col_name[meq[root]]],
                                {block_of_eq[d] for d in ws} if ws else NO_DEPENDS))
            continue
        index[root] = low[root] = counter
        counter += 1
        stack.append(root)
        on[root] = True
        work = [(root, iter(ws))]
        while work:
            v, it = work[-1]
            for w in it:
                iw = index[w]
                if iw < 0:
                    sw = succ[w] = [d for d in map(at, cols[w]) if d != w and d >= 0]
                    for x in sw:
                        if index[x] < 0 or on[x]:
                            break
                    else:  # a finished leaf: its own block, v's low unchanged
                        index[w] = low[w] = counter
                        counter += 1
                        idx = block_of_eq[w] = len(blocks)
                        blocks.append(Block(idx, [w], [col_name[meq[w]]],
                                            {block_of_eq[d] for d in sw} if sw else NO_DEPENDS))
                        continue
                    index[w] = low[w] = counter
                    counter += 1
                    stack.append(w)
                    on[w] = True
                    work.append((w, iter(sw)))
                    break
                if on[w] and iw < low[v]:
                    low[v] = iw
            else:
                work.pop()
                lv = low[v]
                if lv == index[v]:
                    comp = []
                    while True:
                        w = stack.pop()
                        on[w] = False
                        comp.append(w)
                        if w == v:
                            break
                    _block(comp, succ, block_of_eq, blocks, col_name, meq)
                elif lv < low[work[-1][0]]:  # not a root: a parent is on the walk
                    low[work[-1][0]] = lv
    return blocks, block_of_eq


def _block(comp: list[int], succ: list, block_of_eq: list[int], blocks: list,
           col_name: list, meq: list[int]) -> None:
    """Append the Block of the component `comp` (Tarjan emits dependencies first: the
    blocks its successors are in exist)."""
    idx = len(blocks)
    if len(comp) == 1:
        k = comp[0]
        block_of_eq[k] = idx
        out = succ[k]
        blocks.append(Block(idx, comp, [col_name[meq[k]]],
                            {block_of_eq[d] for d in out} if out else NO_DEPENDS))
        return
    for k in comp:
        block_of_eq[k] = idx
    comp.sort()
    b = Block(idx, comp, [col_name[meq[k]] for k in comp], NO_DEPENDS)
    blocks.append(b)
    dep = None
    for k in comp:
        for d in succ[k]:
            bd = block_of_eq[d]
            if bd != idx:
                if dep is None:
                    dep = b.depends = set()
                dep.add(bd)
