"""Code compiled per shape, made once the shape was met often enough.

In: a table of compiled functions, a table of sightings, a shape's key and its maker. Out:
the function, or None while the shape has been met fewer than `after` times (compiling
costs many walks of a small tree, so a shape met a few times, as in small files, is
walked). Used by rowcode (solve) and the report's printers and checks; both tables are
bounded, and emptied when full.
"""
from __future__ import annotations


def compiled_after(fns: dict, seen: dict, key, make, after: int, limit: int,
                   seen_key=None, forget=None):
    """fns[key], made by make(key) on the shape's `after`-th sighting past the first; None
    before. `seen_key` names the sighting when one table counts for several; `forget`
    empties what else the caller keeps beside `fns` when `fns` is emptied."""
    f = fns.get(key)
    if f is not None:
        return f
    sk = key if seen_key is None else seen_key
    n = seen.get(sk, 0)
    if n < after:
        if len(seen) > 4 * limit:
            seen.clear()
        seen[sk] = n + 1
        return None
    f = make(key)
    if len(fns) >= limit:
        fns.clear()
        if forget is not None:
            forget()
    fns[key] = f
    seen.pop(sk, None)
    return f
