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


@record
class Structure:
    incidence: list[set[str]]  # unknowns of each equation
    match_eq: dict[int, str]  # equation -> its matched unknown
    match_var: dict[str, int]
    under: set[str]  # unknowns not determined
    under_eqs: set[int]
    redundant: list[int]  # equations left over: checked after solving
    blocks: list[Block]  # in solving order
    block_of_var: dict[str, int]
    constant_eqs: list[int]  # equations with no unknowns (pure checks)

    def needed_blocks(self, names) -> list[int]:
        """The blocks that determine `names`, with everything they depend on, in order."""
        todo = [self.block_of_var[n] for n in names if n in self.block_of_var]
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
    incidence = [{v for v in inc if v not in known} for inc in full] if known else full
    rank = {n: i for i, n in enumerate(system.unknowns)}
    col_name = list(rank)
    cols: list[list[int]] = []  # each equation's unknowns as sorted columns
    get = rank.get
    for inc in incidence:
        row = []
        for v in inc:
            r = get(v)
            if r is None:
                r = rank[v] = len(col_name)
                col_name.append(v)
            row.append(r)
        row.sort()
        cols.append(row)
    n_cols = len(col_name)
    n_eqs = len(eqs)
    stated = [e.kind in ("stated", "user") for e in eqs]
    constant = [k for k in range(n_eqs) if not cols[k]]
    # auto equations first: stated principles then become the checks when redundant
    order = [k for k in range(n_eqs) if cols[k] and not stated[k]] + \
        [k for k in range(n_eqs) if cols[k] and stated[k]]
    # auto equations are matched first, on their own; the principles a user states
    # (and free equations) then only take unknowns the scene left undetermined, so a
    # redundant statement becomes a check instead of displacing a derived equation
    auto = [k for k in order if not stated[k] and k not in excluded]
    extra = [k for k in order if stated[k] and k not in excluded]
    matchable = cols
    if system.integrations:  # an integration sets its outputs from its inputs, not the reverse
        from .integration import matched_outputs

        matchable = list(cols)
        for k, out in matched_outputs(system).items():
            if out in incidence[k]:
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
    _augment(auto, matchable, meq, mvar, eq_first, var_first)
    _augment(extra, matchable, meq, mvar, eq_first, var_first)
    # Dulmage-Mendelsohn: under-determined = reachable from unmatched unknowns by
    # alternating paths (unknown -> equation containing it -> that equation's unknown).
    var_eqs: list[list[int]] = [[] for _ in range(n_cols)]
    for k, row in enumerate(cols):
        for v in row:
            var_eqs[v].append(k)
    present = [True] * n_cols  # the unknowns the analysis is over (not known)
    for n in known:
        r = get(n)
        if r is not None and not var_eqs[r]:
            present[r] = False
    in_under = [False] * n_cols
    eq_under = [False] * n_eqs
    under: set[str] = set()
    under_eqs: set[int] = set()
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
    redundant = [k for k in order if meq[k] < 0]
    # BLT over the matched, determined equations (Tarjan's SCC, iterative)
    det = [k for k in order if meq[k] >= 0 and not eq_under[k]]
    succ: list = [None] * n_eqs
    for k in det:
        out = []
        for v in cols[k]:
            d = mvar[v]
            if d >= 0 and d != k and not eq_under[d]:
                out.append(d)
        succ[k] = out
    comps = _tarjan(det, succ, n_eqs)
    blocks: list[Block] = []
    block_of_eq = [-1] * n_eqs
    for comp in comps:  # Tarjan emits dependencies first
        idx = len(blocks)
        for k in comp:
            block_of_eq[k] = idx
        comp.sort()
        blocks.append(Block(idx, comp, [col_name[meq[k]] for k in comp], NO_DEPENDS))
    for b in blocks:
        own = b.index
        dep = None
        for k in b.equations:
            for d in succ[k]:
                bd = block_of_eq[d]
                if bd != own:
                    if dep is None:
                        dep = b.depends = set()
                    dep.add(bd)
    match_eq = {k: col_name[meq[k]] for k in eq_first}
    match_var = {col_name[v]: mvar[v] for v in var_first}
    block_of_var = {col_name[meq[k]]: block_of_eq[k] for k in det}
    return Structure(full, match_eq, match_var, under, under_eqs, redundant, blocks,
                     block_of_var, constant)


def _incidence(eqs) -> list[set[str]]:
    """Each equation's unknowns (`expr.variables`). Within a solve (`rowcode.remembered`
    open) from each residual's shape, which the solve then reads again instead of walking
    the tree a second time: a shape names exactly the unknowns `variables` finds."""
    if not (rowcode.ENABLED and rowcode._ON[0]) or rowcode._PLAIN[0]:
        return [variables(e.residual) for e in eqs]
    shape_of = rowcode.shape_of
    out = []
    for e in eqs:
        r = e.residual
        sh = shape_of(r)
        out.append(set(sh[2]) if sh is not None else variables(r))
    return out


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


def _tarjan(nodes: list[int], succ: list, n: int) -> list[list[int]]:
    """Strongly connected components, dependencies before dependents (iterative)."""
    index = [-1] * n
    low = [0] * n
    on = [False] * n
    stack: list[int] = []
    out: list[list[int]] = []
    counter = 0
    for root in nodes:
        if index[root] >= 0:
            continue
        work = [(root, 0)]
        while work:
            v, pi = work.pop()
            if pi == 0:
                index[v] = low[v] = counter
                counter += 1
                stack.append(v)
                on[v] = True
            recurse = False
            ws = succ[v]
            for i in range(pi, len(ws)):
                w = ws[i]
                if index[w] < 0:
                    work.append((v, i + 1))
                    work.append((w, 0))
                    recurse = True
                    break
                if on[w] and index[w] < low[v]:
                    low[v] = index[w]
            if recurse:
                continue
            if low[v] == index[v]:
                comp = []
                while True:
                    w = stack.pop()
                    on[w] = False
                    comp.append(w)
                    if w == v:
                        break
                out.append(comp)
            if work:
                parent = work[-1][0]
                if low[v] < low[parent]:
                    low[parent] = low[v]
    return out
