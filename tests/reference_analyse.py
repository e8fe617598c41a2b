"""The string-keyed analyse as it was before the integer rewrite (momentum_cli/analyse.py):
the reference tests/test_compile_equal.py compares the new one with.

Analyse: the structure of an equation system before any number is computed.

Unknowns and equations form a bipartite graph. A maximum matching and the
Dulmage-Mendelsohn decomposition name the under-determined unknowns and the
over-determined (redundant) equations; strongly connected components of the
matched graph give the block-lower-triangular order in which the rest is solved.
"""
from __future__ import annotations

from momentum_cli.analyse import Block, Structure
from momentum_cli.expr import variables


def analyse(system, excluded=frozenset(), known=None) -> Structure:
    """The structure of `system`; `excluded` equations are left unmatched (numerically
    dependent rows: checked after solving), `known` unknowns are treated as given.

    Every choice (matching, blocks) follows the order in which the unknowns and
    equations were compiled (the file's statements), never their names: renaming the
    bodies changes no block.
    """
    eqs = system.equations
    known = known or {}
    full = [variables(e.residual) for e in eqs]
    incidence = [{v for v in inc if v not in known} for inc in full] if known else full
    names = [n for n in system.unknowns if n not in known]
    rank = {n: i for i, n in enumerate(system.unknowns)}
    for inc in incidence:
        for v in inc:
            rank.setdefault(v, len(rank))
    constant = [k for k, inc in enumerate(incidence) if not inc]
    # auto equations first: stated principles then become the checks when redundant
    order = sorted((k for k, inc in enumerate(incidence) if inc),
                   key=lambda k: (eqs[k].kind in ("stated", "user"), k))
    # auto equations are matched first, on their own; the principles a user states
    # (and free equations) then only take unknowns the scene left undetermined, so a
    # redundant statement becomes a check instead of displacing a derived equation
    auto = [k for k in order if eqs[k].kind not in ("stated", "user") and k not in excluded]
    extra = [k for k in order if eqs[k].kind in ("stated", "user") and k not in excluded]
    ordered = [sorted(inc, key=rank.__getitem__) for inc in incidence]
    matchable = ordered
    if system.integrations:  # an integration sets its outputs from its inputs, not the reverse
        from momentum_cli.integration import matched_outputs

        matchable = list(ordered)
        for k, out in matched_outputs(system).items():
            if out in incidence[k]:
                matchable[k] = [out]
    match_eq, match_var = _max_matching(auto, matchable)
    _augment(extra, matchable, match_eq, match_var)
    # Dulmage-Mendelsohn: under-determined = reachable from unmatched unknowns by
    # alternating paths (unknown -> equation containing it -> that equation's unknown).
    var_eqs: dict[str, list[int]] = {n: [] for n in names}
    for k, inc in enumerate(ordered):
        for v in inc:  # ordered everywhere: block order must not depend on hashing
            var_eqs.setdefault(v, []).append(k)
    under: set[str] = set()
    under_eqs: set[int] = set()
    stack = [n for n in var_eqs if n not in match_var]
    while stack:
        v = stack.pop()
        if v in under:
            continue
        under.add(v)
        for k in var_eqs.get(v, ()):
            if k in match_eq and k not in under_eqs:
                under_eqs.add(k)
                stack.append(match_eq[k])
    redundant = [k for k in order if k not in match_eq]
    # BLT over the matched, determined equations (Tarjan's SCC, iterative)
    det = [k for k in order if k in match_eq and k not in under_eqs]
    succ: dict[int, list[int]] = {}
    for k in det:
        succ[k] = [match_var[v] for v in ordered[k]
                   if v in match_var and match_var[v] != k and match_var[v] not in under_eqs]
    comps = _tarjan(det, succ)
    blocks: list[Block] = []
    block_of_eq: dict[int, int] = {}
    for comp in comps:  # Tarjan emits dependencies first
        idx = len(blocks)
        for k in comp:
            block_of_eq[k] = idx
        blocks.append(Block(idx, sorted(comp), [match_eq[k] for k in sorted(comp)], set()))
    for b in blocks:
        for k in b.equations:
            for d in succ[k]:
                if block_of_eq[d] != b.index:
                    b.depends.add(block_of_eq[d])
    block_of_var = {match_eq[k]: block_of_eq[k] for k in det}
    return Structure(full, match_eq, match_var, under, under_eqs, redundant, blocks,
                     block_of_var, constant)


def _max_matching(order: list[int], incidence: list[list[str]]):
    """Maximum bipartite matching by augmenting paths (equations in the given order,
    each equation's unknowns in the order given)."""
    match_eq: dict[int, str] = {}
    match_var: dict[str, int] = {}
    # cheap greedy pass first
    for k in order:
        for v in incidence[k]:
            if v not in match_var:
                match_var[v] = k
                match_eq[k] = v
                break
    _augment(order, incidence, match_eq, match_var)
    return match_eq, match_var


def _augment(order: list[int], incidence: list[list[str]], match_eq: dict, match_var: dict):
    """Extend a matching by augmenting paths from each unmatched equation of `order`."""
    adj: dict[int, list[str]] = {}

    def nbrs(k):
        if k not in adj:
            adj[k] = incidence[k]
        return adj[k]

    for k in order:
        if k in match_eq:
            continue
        # iterative DFS for an augmenting path from equation k
        visited: set[str] = set()
        parent: dict[str, int] = {}
        stack = [(k, iter(nbrs(k)))]
        found = None
        while stack and found is None:
            e, it = stack[-1]
            # look ahead: an unmatched unknown of this equation ends the path at once
            # (keeps chains of contacts linear instead of quadratic)
            free = next((v for v in nbrs(e) if v not in match_var and v not in visited), None)
            if free is not None:
                visited.add(free)
                parent[free] = e
                found = free
                break
            for v in it:
                if v in visited:
                    continue
                visited.add(v)
                parent[v] = e
                if v not in match_var:
                    found = v
                    break
                stack.append((match_var[v], iter(nbrs(match_var[v]))))
                break
            else:
                stack.pop()
        if found is None:
            continue
        v = found
        while True:
            e = parent[v]
            prev = match_eq.get(e)
            match_eq[e] = v
            match_var[v] = e
            if e == k:
                break
            v = prev


def _tarjan(nodes: list[int], succ: dict[int, list[int]]) -> list[list[int]]:
    """Strongly connected components, dependencies before dependents (iterative)."""
    index: dict[int, int] = {}
    low: dict[int, int] = {}
    on: set[int] = set()
    stack: list[int] = []
    out: list[list[int]] = []
    counter = 0
    for root in nodes:
        if root in index:
            continue
        work = [(root, 0)]
        while work:
            v, pi = work.pop()
            if pi == 0:
                index[v] = low[v] = counter
                counter += 1
                stack.append(v)
                on.add(v)
            recurse = False
            ws = succ.get(v, [])
            for i in range(pi, len(ws)):
                w = ws[i]
                if w not in index:
                    work.append((v, i + 1))
                    work.append((w, 0))
                    recurse = True
                    break
                if w in on:
                    low[v] = min(low[v], index[w])
            if recurse:
                continue
            if low[v] == index[v]:
                comp = []
                while True:
                    w = stack.pop()
                    on.discard(w)
                    comp.append(w)
                    if w == v:
                        break
                out.append(comp)
            if work:
                parent = work[-1][0]
                low[parent] = min(low[parent], low[v])
    return out
