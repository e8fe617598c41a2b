"""Compile helper: which state a body's quantity really lives at, in O(log N) a query.

In: the scene's states and transitions, and the bodies each transition moves. Out:
for (body, qty, state), the state whose variable it shares (see compile._find). A body
untouched by a transition keeps its quantities, so a sequence of N two-body impacts
has O(N) unknowns; walking the states one by one to find that out costs O(N) a query
and O(N^2) in all. When the states form simple chains (each has at most one transition
in and one out, the usual case), the answer is a binary search among the few states
where that quantity can change; other shapes fall back to the walk.
"""
from __future__ import annotations

from bisect import bisect_right

from .tracks import Track


class StateChains:
    """States numbered along their chains, and per (body, qty, chain) the sorted
    positions where the quantity breaks from the state before: given there, or moved by
    the transition into it. Velocities break where the body is busy; positions only
    where given (an impact keeps them; an interval keeps its start configuration)."""

    def __init__(self, where: dict, chains: list, into: dict, tracks: dict):
        self.where = where  # state -> (chain index, position)
        self.chains = chains  # chain index -> [state, ...] in order
        self.into = into  # state -> the one transition into it
        self.tracks = tracks  # body -> tracks.Track: its breaks, (qty, chain) -> positions

    @classmethod
    def build(cls, states, into: dict, out: dict, busy: dict,
              tracks: dict) -> "StateChains | None":
        """None unless every state has at most one transition in and one out, and
        the transitions form no cycle. The break positions go into each body's record
        in `tracks` (a body missing there gets one)."""
        if any(len(ts) > 1 for ts in into.values()) or any(len(ts) > 1 for ts in out.values()):
            return None
        where: dict = {}
        chains: list = []
        for sid in states:
            if sid in into:
                continue
            chain, cur = [], sid
            while cur is not None:
                if cur in where:
                    return None
                where[cur] = (len(chains), len(chain))
                chain.append(cur)
                nxt = out.get(cur)
                cur = nxt[0].after if nxt else None
            chains.append(chain)
        # a state reached by no walk from a root lies on a cycle (or names a missing state)
        if any(sid not in where for sid in states):
            return None
        for ts in into.values():
            if ts[0].before not in where or ts[0].after not in where:
                return None
        # positions as sorted tuples (half a one-item list's size: a big scene has ~3 a
        # body); only those that came out of order or grew long are sorted at the end
        late: dict = {}  # (id of a body's breaks, key) -> those breaks: positions that came
        # out of order or grew long
        for sid, st in states.items():
            c, p = where[sid]
            for (b, q) in st.givens:
                tr = _track(tracks, b)
                _add(tr.breaks, late, (q, c), p)
                if p and (q == "vx" or q == "vy"):
                    tr.late = True
        for sid, ts in into.items():
            c, p = where[sid]
            for b in busy[ts[0].key]:
                tr = _track(tracks, b)
                breaks = tr.breaks
                for q in tr.moves:
                    _add(breaks, late, (q, c), p)
        for (_, k), breaks in late.items():
            breaks[k] = tuple(sorted(breaks[k]))
        return cls(where, chains, {s: ts[0] for s, ts in into.items()}, tracks)

    def head(self, body: str, qty: str, sid: str, given, linked):
        """The state (body, qty, sid) shares its variable with: the last break at or before
        sid (its chain's first state if none); if that one is not given, the next break
        after it if that one is given and the transition into it keeps the quantity (a
        later state may give it, e.g. only the end velocity). `given(key)` and
        `linked(body, qty, t)` are the compiler's. None: state not on a chain."""
        w = self.where.get(sid)
        if w is None:
            return None
        c, p = w
        chain = self.chains[c]
        tr = self.tracks.get(body)
        pts = () if tr is None else tr.breaks.get((qty, c), ())
        k = bisect_right(pts, p) - 1
        start = pts[k] if k >= 0 else 0
        key = (body, qty, chain[start])
        if given(key) is not None:
            return key
        if k + 1 < len(pts):
            nxt = chain[pts[k + 1]]
            if given((body, qty, nxt)) is not None and linked(body, qty, self.into[nxt]):
                return (body, qty, nxt)
        return key

    def head_given(self, body: str, qty: str, sid: str, states: dict, linked):
        """`head`, with the value given there (None: an unknown), in one walk: the
        compiler makes each state quantity's node from both. (None, None): sid is on no
        chain."""
        w = self.where.get(sid)
        if w is None:
            return None, None
        c, p = w
        chain = self.chains[c]
        bq = (body, qty)
        tr = self.tracks.get(body)
        pts = None if tr is None else tr.breaks.get((qty, c))
        if pts is None:
            start = chain[0]
            return (body, qty, start), states[start].givens.get(bq)
        k, start = last_break(chain, pts, p)
        g = states[start].givens.get(bq)
        if g is not None:
            return (body, qty, start), g
        if k + 1 < len(pts):
            nxt = chain[pts[k + 1]]
            g = states[nxt].givens.get(bq)
            if g is not None and linked(body, qty, self.into[nxt]):
                return (body, qty, nxt), g
        return (body, qty, start), None


def _track(tracks: dict, body: str):
    """The body's record in `tracks`, made if it has none (a name no body has)."""
    tr = tracks.get(body)
    if tr is None:
        tr = tracks[body] = Track()
    return tr


def _add(breaks: dict, late: dict, k, p) -> None:
    """Add position p to key k's positions in a body's `breaks` (StateChains.build): a
    first one as a tuple of one, a short tuple grows by a copy, a long one becomes a list
    (a body in many transitions: no quadratic copies); a key out of order or made a list
    is in `late` (with its dict), sorted into a tuple at the end."""
    v = breaks.get(k)
    if v is None:
        breaks[k] = (p,)
    elif type(v) is list:
        v.append(p)
    elif len(v) >= 8:
        late[(id(breaks), k)] = breaks
        breaks[k] = [*v, p]
    else:
        if p < v[-1]:
            late[(id(breaks), k)] = breaks
        breaks[k] = v + (p,)


def last_break(chain: list, pts, p: int) -> tuple:
    """The last of a quantity's breaks `pts` (sorted chain positions; None: none) at or
    before chain position p: its index in pts (-1: none) and its state, the chain's first
    state when there is none. Every state from there to p shares its variable."""
    if pts is None:
        return -1, chain[0]
    k = bisect_right(pts, p) - 1
    return k, (chain[pts[k]] if k >= 0 else chain[0])
