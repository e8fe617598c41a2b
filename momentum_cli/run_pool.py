"""Run stage, for a batch: which worker process solves which files, results in order.

In: a batch's texts (one per file, in the given order) and forked workers (Worker).
Out: the files' results, in the given order. Each worker is one process with its own
pipe, so the files can be routed: the files of one family (the same text but for
its digits) go to one worker in chunks, so each worker parses and warms up on a family
once, not every worker on every family; and files that may integrate a flow
(`gain`, `lose`, `burn`: scipy and numpy, ~1 s to import) go to the first worker, so one
worker imports them instead of each. Routing changes where a file is solved, never its
result (each file is solved alone, as in one call on it).
"""
from __future__ import annotations

import re
import sys
from collections import deque

CHUNK = 8  # files sent to a worker at once (the same family)
AHEAD = 2  # chunks queued per worker, so that none waits for the parent
WINDOW = 512  # files solved ahead of the next one printed (bounds the results held)
HEAVY = ("numpy", "scipy")  # the imports worth routing: ~0.2 s and ~1 s per process
_MAY_INTEGRATE = re.compile(r"^[ \t]*(?:gain|lose|burn)\b", re.M)


def family(text: str) -> int:
    """Files of one family share most statements (variants of one problem): the text
    without its digits (as UTF-8 bytes, whose translate is ~4x faster than str's)."""
    return hash(text.encode("utf-8", "surrogatepass").translate(None, b"0123456789"))


def may_integrate(text: str) -> bool:
    """A flow that may have no closed form: solved with scipy's solve_ivp (a hint)."""
    if "gain" not in text and "lose" not in text and "burn" not in text:
        return False  # the common file: three substring scans instead of a regex's
    return _MAY_INTEGRATE.search(text) is not None


def chunk_job(jobs, solve):
    """Worker: `solve` each job; with the results, which HEAVY modules this process had
    imported before and after (so the parent learns which families need them)."""
    before = tuple(m for m in HEAVY if m in sys.modules)
    out = [solve(job) for job in jobs]
    return out, before, tuple(m for m in HEAVY if m in sys.modules)


class Router:
    """Which pending file each worker gets next. A family belongs to the worker that
    solved its first chunk; a file that may integrate goes to worker 0 (or to a worker
    that already imported the HEAVY modules); an idle worker takes another worker's
    family only if that family needs no import the thief lacks."""

    def __init__(self, texts, workers: int):
        n = len(texts)
        self.n, self.workers = n, workers
        self.fam = [family(t) for t in texts]
        self.hint = [may_integrate(t) for t in texts]
        self.taken = bytearray(n)
        self.lo = 0  # every file before this one is taken
        self.by_fam: dict = {}
        for i, f in enumerate(self.fam):
            q = self.by_fam.get(f)
            if q is None:
                q = self.by_fam[f] = deque()
            q.append(i)
        self.hinted = deque(i for i in range(n) if self.hint[i])
        self.owner: dict = {}
        self.needs: dict = {}  # family -> HEAVY modules its first chunk imported
        self.loaded = [frozenset() for _ in range(workers)]

    def _may_take(self, w: int, i: int) -> bool:
        f = self.fam[i]
        own = self.owner.get(f)
        if own == w:
            return True
        if own is None:
            return not self.hint[i] or w == 0 or self.loaded[w] >= set(HEAVY)
        return False

    def _may_steal(self, w: int, i: int) -> bool:
        f = self.fam[i]
        if self.hint[i] and not self.loaded[w] >= set(HEAVY):
            return False
        return self.needs.get(f, frozenset()) <= self.loaded[w]

    def pick(self, w: int, limit: int):
        """The next chunk (file indices, in order) for worker `w`, from files before
        `limit`; None when none fits it now."""
        limit = min(limit, self.n)
        taken = self.taken
        while self.lo < self.n and taken[self.lo]:
            self.lo += 1
        i = None
        if w == 0:  # the files that may integrate first: worker 0 imports for them
            h = self.hinted
            while h and taken[h[0]]:
                h.popleft()
            for j in h:
                if j >= limit:
                    break
                if not taken[j] and self._may_take(w, j):
                    i = j
                    break
        if i is None:
            for j in range(self.lo, limit):
                if not taken[j] and self._may_take(w, j):
                    i = j
                    break
        if i is None:
            for j in range(self.lo, limit):
                if not taken[j] and self._may_steal(w, j):
                    i = j
                    break
        if i is None:
            return None
        f = self.fam[i]
        self.owner.setdefault(f, w)
        q = self.by_fam[f]
        while q and taken[q[0]]:
            q.popleft()
        out = []
        while q and len(out) < CHUNK and q[0] < limit:
            j = q.popleft()
            if not taken[j]:
                taken[j] = 1
                out.append(j)
        return out

    def learned(self, w: int, chunk, before, after) -> None:
        """A chunk came back from worker `w`: what its process has imported now, and
        what this family needs if its chunk imported it."""
        self.loaded[w] = frozenset(after)
        new = frozenset(after) - frozenset(before)
        if new:
            f = self.fam[chunk[0]]
            self.needs[f] = self.needs.get(f, frozenset()) | new


class WorkerDied(RuntimeError):
    """A worker process ended (killed, or out of memory) before sending a result."""


class Worker:
    """One forked process that solves the chunks (file indices) sent down its pipe, in
    order, with `solve`, which it inherits at the fork (never pickled). No threads in
    either process: a ProcessPoolExecutor's manager and feeder threads cost the parent
    more CPU than the pickling they serve. Daemonic: never waited for at exit."""

    def __init__(self, ctx, solve, initializer=None, initargs=()):
        here, there = ctx.Pipe()
        self.proc = ctx.Process(target=_serve, args=(there, solve, initializer, initargs),
                                daemon=True)
        self.proc.start()
        there.close()
        self.conn = here

    def close(self, ask: bool) -> None:
        """End the process: `ask` it to (it has no work left), else it was killed; then
        wait for it, so that it is not left a zombie (and its CPU time is counted as
        this process's children's, as `time` reports it)."""
        try:
            if ask:
                self.conn.send(None)
        except OSError:
            pass
        self.conn.close()
        self.proc.join()


def _serve(conn, solve, initializer, initargs) -> None:
    """Worker: answer each chunk with chunk_job's (results, before, after), or with the
    exception it raised (raised again in the parent), until None or the pipe's end.
    Ends with os._exit: a normal end would flush standard streams inherited from the
    parent (printing again what sat in their buffers at the fork) and tear down a heap
    that the process is about to lose anyway."""
    import os

    code = 1  # an error here ends the worker: the parent sees its pipe close
    try:
        if initializer is not None:
            initializer(*initargs)
        while True:
            try:
                chunk = conn.recv()
            except (EOFError, OSError):
                break
            if chunk is None:
                break
            try:
                msg = chunk_job(chunk, solve)
            except Exception as exc:  # a bug: the parent raises it, as a future would
                msg = exc
            try:
                conn.send(msg)
            except (EOFError, OSError):
                break
            except Exception as exc:  # a result that cannot be pickled
                conn.send(RuntimeError(f"a worker's result could not be sent: {exc!r}"))
            del msg
        code = 0
    finally:
        os._exit(code)


def routed(texts, workers):
    """Yield the result of each file i of `texts`, in order, solved by `workers`
    (Worker, forked once the parent holds the batch): chunks of indices routed by
    Router. A chunk is a few small ints: the workers inherited the files' texts with the
    parent's memory, so no text is pickled. Raises WorkerDied when a worker died,
    whether the parent was reading from it or sending to it: the caller solves the rest
    itself."""
    from multiprocessing.connection import wait

    n = len(texts)
    router = Router(texts, len(workers))
    results: dict = {}
    flying = [deque() for _ in workers]  # each worker's chunks, in the order sent
    by_conn = {wk.conn: w for w, wk in enumerate(workers)}
    nxt = 0

    def refill():
        limit = nxt + WINDOW
        for w, wk in enumerate(workers):
            while len(flying[w]) < AHEAD:
                chunk = router.pick(w, limit)
                if not chunk:
                    break
                try:
                    wk.conn.send(chunk)
                except OSError:  # a broken pipe: it died before reading this chunk
                    raise WorkerDied("a worker process ended before taking its files") \
                        from None
                flying[w].append(chunk)

    refill()
    while nxt < n:
        if nxt in results:
            res = results.pop(nxt)
            nxt += 1
            yield res
            if nxt % CHUNK == 0:
                refill()
            continue
        busy = [wk.conn for w, wk in enumerate(workers) if flying[w]]
        if not busy:
            refill()
            busy = [wk.conn for w, wk in enumerate(workers) if flying[w]]
            if not busy:  # never: every file in the window fits some worker
                raise RuntimeError("batch routing stalled")
        for conn in wait(busy):
            w = by_conn[conn]
            try:
                msg = conn.recv()
            except (EOFError, OSError):  # OSError: it died with chunks unread (reset)
                raise WorkerDied("a worker process ended before sending its results") \
                    from None
            if isinstance(msg, BaseException):
                raise msg
            out, before, after = msg
            chunk = flying[w].popleft()
            router.learned(w, chunk, before, after)
            for i, r in zip(chunk, out):
                results[i] = r
        refill()
