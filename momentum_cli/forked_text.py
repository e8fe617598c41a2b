"""CLI stage: one big file's plain report made by two processes.

In: a lazy report (`build_report(lazy=True)`, as `solve --plain` streams one file) and
standard output. Out: the report's text on standard output, byte for byte what
`text.iter_parts` gives alone, in about half the wall time on two cores. The text is cut
into ranges of like work (report/text_cuts.py); this process makes and writes ranges from
the front while a forked child (copy-on-write: nothing of the report is pickled) makes
ranges from the back into a temporary file, each taking the next range under a lock
until they meet; then the child's ranges are copied after this process's, in order.

The child writes into a file, not a pipe: its half of a 10^5-ball report is ~60 MB, which
a pipe (64 kB - 1 MB) holds only if this process reads it while it makes its own half,
holding it in memory. A range the child did not finish (it failed, died, or never ran)
is made here, so the text is whole, or stops at the same piece with the same error as
made alone. `MOMENTUM_SERIAL_REPORT=1` makes every text in one process.
"""
from __future__ import annotations

import os
import struct

RANGES = 32  # ranges of the transitions' section (the rest after it is one more)
COPY_BLOCK = 1 << 20  # bytes copied at once from the child's file
CHILDREN: set = set()  # children running now: guard._on_signal ends them too

_PAIR = struct.Struct("qq")  # the shared page: next range from the front, first taken
# from the back; then per range its (offset, length) in the child's file (-1: not made)


def _serial_asked() -> bool:
    return os.environ.get("MOMENTUM_SERIAL_REPORT", "") not in ("", "0")


def write(out, report, sig: int, failed: list, write_text) -> bool:
    """Write `report`'s full plain text to `out` by `write_text(stream, pieces)`
    (solve_cmd._write_text), made by this process and a forked child; False (nothing
    written) where that cannot be set up (no fork, serial asked, a report not lazy): the
    caller makes the text alone. A piece that fails to be made ends the text there, its
    exception in `failed` (as solve_cmd._caught)."""
    if not hasattr(os, "fork") or _serial_asked():
        return False
    from .report.text_cuts import cuts

    marks = cuts(report.transitions, RANGES)
    if not marks:
        return False
    bounds = [None] + marks + [None]  # range k: from bounds[k] to bounds[k + 1]
    n = len(bounds) - 1
    try:
        import fcntl
        import mmap
        import tempfile

        spill = tempfile.TemporaryFile()
    except (ImportError, OSError):
        return False
    try:
        shared = mmap.mmap(-1, _PAIR.size * (1 + n))  # anonymous: shared with the child
        _PAIR.pack_into(shared, 0, 1, n)  # range 0 is this process's
        for k in range(n):
            _PAIR.pack_into(shared, _PAIR.size * (1 + k), -1, -1)
        _prepare(report)
        binary = _byte_stream(out)
        encoding, errors = (out.encoding, out.errors) if binary else ("utf-8", "surrogatepass")
        out.flush()  # before the fork: the child's copy of the buffer is empty
        pid = os.fork()
    except (OSError, ValueError):
        spill.close()
        return False
    if pid == 0:  # the child: never returns
        _child(report, sig, bounds, spill.fileno(), shared, encoding, errors, fcntl,
               write_text)
    CHILDREN.add(pid)
    try:
        _front(out, report, sig, bounds, spill.fileno(), shared, failed, fcntl, write_text)
        if failed:
            return True
        _wait(pid)
        first = _PAIR.unpack_from(shared, 0)[0]  # the ranges after this process's
        for k in range(first, n):
            offset, length = _PAIR.unpack_from(shared, _PAIR.size * (1 + k))
            if length >= 0:
                _copy(out, spill.fileno(), offset, length, binary, encoding, errors)
            elif not _make(out, report, sig, bounds, k, failed, write_text):
                return True
        return True
    finally:
        _end(pid)
        spill.close()
        shared.close()


def _prepare(report) -> None:
    """What both processes' first ranges would make, made once before the fork: the
    diagrams' shared lookups (this process's first range needs them anyway). A bug met
    here is met again, as the text would meet it, by the range that needs them."""
    prepare = getattr(report.diagrams, "prepare", None)
    if prepare is not None:
        try:
            prepare()
        except Exception:  # noqa: BLE001 (said where the text meets it)
            pass


def _byte_stream(out) -> bool:
    """Whether the child's bytes can go to `out.buffer` as they are: a text stream over
    bytes in a stateless encoding (else the child's UTF-8 is decoded and written as
    text: a pager's capture, --output's)."""
    if getattr(out, "buffer", None) is None or not isinstance(getattr(out, "errors", None), str):
        return False
    import codecs

    try:
        return codecs.lookup(out.encoding).name in ("utf-8", "ascii", "iso8859-1")
    except (LookupError, TypeError):
        return False


def _claim(fd: int, shared, fcntl, front: bool):
    """The next range to make, from the front or from the back (None: they met)."""
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


def _pieces(report, sig: int, bounds: list, k: int):
    """Range k's pieces, a newline before them from the second range on (an empty
    piece first: the writer puts a newline only before the range's first piece)."""
    from .report.text import iter_parts

    if k:
        yield ""
    yield from iter_parts(report, sig, True, bounds[k], bounds[k + 1])


def _make(out, report, sig: int, bounds: list, k: int, failed: list, write_text) -> bool:
    """Write range k here; False if a piece of it failed (its exception in `failed`)."""
    write_text(out, _until_failure(_pieces(report, sig, bounds, k), failed))
    return not failed


def _until_failure(parts, failed: list):
    """The pieces of `parts` until one fails to be made; its exception goes to `failed`
    (a write's own errors, raised in the writer, are not caught here)."""
    try:
        yield from parts
    except Exception as exc:
        failed.append(exc)


def _front(out, report, sig, bounds, fd, shared, failed, fcntl, write_text) -> None:
    """This process's ranges: 0, then each next one from the front until the child's."""
    k = 0
    while k is not None and _make(out, report, sig, bounds, k, failed, write_text):
        k = _claim(fd, shared, fcntl, True)


def _child(report, sig, bounds, fd, shared, encoding, errors, fcntl, write_text) -> None:
    """The forked child: ranges from the back into the file `fd`, each recorded in
    `shared` once its bytes are all written. Leaves by os._exit (no atexit, no flush of
    the parent's streams, no teardown); any error ends it (the parent makes the rest)."""
    code = 1
    try:
        import signal

        for name in ("SIGINT", "SIGTERM", "SIGHUP"):  # not the parent's handlers
            if hasattr(signal, name):
                signal.signal(getattr(signal, name), signal.SIG_DFL)
        null = os.open(os.devnull, os.O_WRONLY)
        os.dup2(null, 1)  # never the parent's output, nor holding its pipe open
        os.close(null)
        sink = _Sink(fd, encoding, errors)
        while True:
            k = _claim(fd, shared, fcntl, False)
            if k is None:
                break
            start = sink.size
            write_text(sink, _pieces(report, sig, bounds, k))
            _PAIR.pack_into(shared, _PAIR.size * (1 + k), start, sink.size - start)
        code = 0
    except BaseException:  # noqa: B036 (the parent makes what is missing)
        pass
    finally:
        os._exit(code)


class _Sink:
    """The child's text stream: each write encoded as the parent's output would, and
    written to the file at once (`size`: the bytes so far)."""

    def __init__(self, fd: int, encoding: str, errors: str):
        self.fd, self.encoding, self.errors, self.size = fd, encoding, errors, 0

    def write(self, text: str) -> None:
        data = memoryview(text.encode(self.encoding, self.errors))
        self.size += len(data)
        while data:
            data = data[os.write(self.fd, data):]


def _copy(out, fd: int, offset: int, length: int, binary: bool, encoding, errors) -> None:
    """The child's bytes of one range to `out`: as bytes after the text written so far,
    or decoded (a range is whole characters)."""
    if not binary:
        text = os.pread(fd, length, offset).decode(encoding, errors)
        for i in range(0, len(text), COPY_BLOCK):
            out.write(text[i:i + COPY_BLOCK])
        return
    out.flush()
    buffer = out.buffer
    end = offset + length
    while offset < end:
        data = os.pread(fd, min(COPY_BLOCK, end - offset), offset)
        if not data:
            raise OSError("the child's text is shorter than it said")
        buffer.write(data)
        offset += len(data)


def _wait(pid: int) -> None:
    """Wait for the child to end (it has no more ranges to take)."""
    while True:
        try:
            os.waitpid(pid, 0)
        except InterruptedError:
            continue
        except ChildProcessError:
            pass
        CHILDREN.discard(pid)
        return


def _end(pid: int) -> None:
    """The child ended and reaped, whatever happened here (no zombie left)."""
    if pid not in CHILDREN:
        return
    import signal

    try:
        os.kill(pid, signal.SIGKILL)
    except OSError:
        pass
    _wait(pid)


def kill_children() -> None:
    """End every child now (the process is ending on a signal)."""
    import signal

    for pid in list(CHILDREN):
        try:
            os.kill(pid, signal.SIGKILL)
        except OSError:
            pass
