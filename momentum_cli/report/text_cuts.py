"""Where to cut a big report's plain text into ranges of like work, before any of it is
made: the cuts `text.iter_parts` takes (`start`, `stop`), so that two processes can make
the ranges (forked_text). Judged by sizes only (the transitions' rows and bodies): the
two processes share the ranges as they go, so a range that costs more than judged
costs its maker time, never the text its bytes.
"""
from __future__ import annotations

# a transition's work beside its rows, in equation rows' work (one row ~6-7 us): its
# heading, `why` and statements, and per body it moves its diagram's lines and its share
# of the statements (measured: ~3 rows a body in the 10^4-impact cradle, ~6.5 in the
# 10^4-ball chain's one impact)
HEAD_ROWS = 3
BODY_ROWS = 5


def cuts(transitions, count: int) -> list:
    """Cuts `(transition, row)` in increasing order that split the transitions' section
    into up to `count` ranges of about equal work, then the section's end (the blocks,
    solution and checks after it are one range more); [] for a report whose transitions
    have no `sizes` (not lazy) or that has none. A cut inside a transition is never
    before its first row (its heading and first row are made together)."""
    sizes = getattr(transitions, "sizes", None)
    if sizes is None or not len(transitions) or count < 2:
        return []
    sizes = sizes()
    work = [(HEAD_ROWS + BODY_ROWS * bodies, rows) for rows, bodies in sizes]
    step = sum(h + r for h, r in work) / count
    out: list = []
    done = 0.0  # the work before transition i
    goal = step  # the work at which the next cut is due
    for i, (head, rows) in enumerate(work):
        if done >= goal:
            out.append((i, 0))
            while goal <= done:
                goal += step
        # inside its rows: before row k, done + head + k rows of work are made
        while rows > 1:
            k = max(1, -int(-(goal - done - head) // 1))  # ceil, at least 1
            if k >= rows:
                break
            out.append((i, k))
            while goal <= done + head + k:
                goal += step
        done += head + rows
    out.append((len(work), 0))
    return out
