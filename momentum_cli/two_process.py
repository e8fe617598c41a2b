"""CLI stage: the numbered parts of one output made by this process and a forked child.

In: how many parts, what makes a part here, what makes it in the child (as text), what
to do with each part the child made. Out: every part made once, in about half the wall
time on two cores. The child is forked (copy-on-write: it reads what this process holds,
nothing is pickled); this process takes parts from the front, part 0 first, the child
from the back, each the next one under a lock, until they meet: the work shares itself
out whatever each part costs and whatever else the machine runs.

The child writes its parts into a temporary file, not a pipe: its half of a 10^5-ball
report is ~60 MB, which a pipe (64 kB - 1 MB) holds only if this process reads it while
it makes its own half, holding it in memory. A part is recorded once all its bytes are
written; a part the child did not finish (it failed, died or never ran) is made here, so
an error is met here, where it would be met in one process. The child never writes to
standard output, leaves by os._exit (no atexit, no flush of this process's buffers, no
teardown) and is always waited for. `MOMENTUM_SERIAL_REPORT=1` forks nothing.
"""
from __future__ import annotations

import os
import struct
import sys

CHILDREN: set = set()  # children running now: guard._on_signal ends them too

_PAIR = struct.Struct("qq")  # the shared page: the next part from the front, the first
# taken from the back; then per part its (offset, length) in the child's file (-1: none)


def serial_asked() -> bool:
    """One process: asked for, or a child would not help. Fork only on Linux (elsewhere,
    macOS above all, a forked child of a process that loaded system libraries may crash:
    Python's own multiprocessing spawns there) and only with a second CPU to run on."""
    if os.environ.get("MOMENTUM_SERIAL_REPORT", "") not in ("", "0"):
        return True
    if not hasattr(os, "fork") or not sys.platform.startswith("linux"):
        return True
    try:
        return len(os.sched_getaffinity(0)) < 2
    except (AttributeError, OSError):
        return True


def share(n: int, here, there, collect, encoding: str = "utf-8",
          errors: str = "surrogatepass") -> bool:
    """Parts 0 to n - 1 (n >= 2): `here(k)` makes part k in this process (False: a part
    failed, stop), `there(k, sink)` makes it in the child, writing its text to `sink`
    (encoded with `encoding`, `errors`); once they have met and the child has ended,
    `collect(k, fd, offset, length)` takes each part the child made, in order, and
    `here(k)` makes the others. False (nothing made) where no child can be forked: the
    caller makes the parts alone. Flush any buffered output before: the child inherits
    a copy of it."""
    if serial_asked():
        return False
    try:
        import fcntl
        import mmap
        import tempfile

        spill = tempfile.TemporaryFile()
    except (ImportError, OSError):
        return False
    try:
        shared = mmap.mmap(-1, _PAIR.size * (1 + n))  # anonymous: shared with the child
        _PAIR.pack_into(shared, 0, 1, n)  # part 0 is this process's
        for k in range(n):
            _PAIR.pack_into(shared, _PAIR.size * (1 + k), -1, -1)
        pid = os.fork()
    except (OSError, ValueError):
        spill.close()
        return False
    fd = spill.fileno()
    if pid == 0:  # the child: never returns
        _child(there, fd, shared, encoding, errors, fcntl)
    CHILDREN.add(pid)
    try:
        k = 0
        while k is not None:
            if not here(k):
                return True
            k = _claim(fd, shared, fcntl, True)
        _wait(pid)
        first = _PAIR.unpack_from(shared, 0)[0]  # the parts after this process's
        for k in range(first, n):
            offset, length = _PAIR.unpack_from(shared, _PAIR.size * (1 + k))
            if length >= 0:
                collect(k, fd, offset, length)
            elif not here(k):
                return True
        return True
    finally:
        _end(pid)
        spill.close()
        shared.close()


def _claim(fd: int, shared, fcntl, front: bool):
    """The next part to make, from the front or from the back (None: they met)."""
    fcntl.lockf(fd, fcntl.LOCK_EX)  # a process's lock: excludes the other, freed at death
    try:
        lo, hi = _PAIR.unpack_from(shared, 0)
        if lo >= hi:
            return None
        if front:
            _PAIR.pack_into(shared, 0, lo + 1, hi)
            return lo
        _PAIR.pack_into(shared, 0, lo, hi - 1)
        return hi - 1
    finally:
        fcntl.lockf(fd, fcntl.LOCK_UN)


def _child(there, fd: int, shared, encoding: str, errors: str, fcntl) -> None:
    """The forked child: parts from the back into the file `fd`, each recorded in
    `shared` once its bytes are all written. Any error ends it (this process makes the
    parts it did not record)."""
    code = 1
    try:
        import signal

        for name in ("SIGINT", "SIGTERM", "SIGHUP"):  # not the parent's handlers
            if hasattr(signal, name):
                signal.signal(getattr(signal, name), signal.SIG_DFL)
        null = os.open(os.devnull, os.O_WRONLY)
        os.dup2(null, 1)  # never the parent's output, nor holding its pipe open
        os.close(null)
        sink = Sink(fd, encoding, errors)
        while True:
            k = _claim(fd, shared, fcntl, False)
            if k is None:
                break
            start = sink.size
            there(k, sink)
            _PAIR.pack_into(shared, _PAIR.size * (1 + k), start, sink.size - start)
        code = 0
    except BaseException:  # noqa: B036 (the parent makes what is missing)
        pass
    finally:
        os._exit(code)


class Sink:
    """The child's text stream: each write encoded and written to the file at once
    (`size`: the bytes so far)."""

    def __init__(self, fd: int, encoding: str, errors: str):
        self.fd, self.encoding, self.errors, self.size = fd, encoding, errors, 0

    def write(self, text: str) -> None:
        data = memoryview(text.encode(self.encoding, self.errors))
        self.size += len(data)
        while data:
            data = data[os.write(self.fd, data):]


def _wait(pid: int) -> None:
    """Wait for the child to end (it has no more parts to take)."""
    try:
        os.waitpid(pid, 0)
    except ChildProcessError:
        pass
    CHILDREN.discard(pid)


def _end(pid: int) -> None:
    """The child ended and waited for, whatever happened here (no zombie left)."""
    if pid not in CHILDREN:
        return
    import signal

    try:
        os.kill(pid, signal.SIGKILL)
    except OSError:
        pass
    _wait(pid)


def kill_children() -> None:
    """End every child now (this process is ending on a signal)."""
    import signal

    for pid in list(CHILDREN):
        try:
            os.kill(pid, signal.SIGKILL)
        except OSError:
            pass
