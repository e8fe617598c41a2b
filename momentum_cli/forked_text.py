"""CLI stage: one big file's report made by two processes (two_process.py), byte for
byte what one process makes.

Plain text (`solve --plain FILE`): the text is cut into ranges of like work
(report/text_cuts.py, text.iter_parts' `start` and `stop`); this process writes its
ranges to standard output as it makes them, then copies the child's after them, in
order. JSON (`solve --json FILE`): the result's report fields (json_out.field_makers),
each made and encoded by one of the two; the checks are this process's (the caller
reads them again).
"""
from __future__ import annotations

from . import two_process

_CLAIM_ORDER = {"checks": 0, "blocks": 2, "diagrams": 3}  # the others: 1, in key order
RANGES = 32  # ranges of the transitions' section (the rest after it is one more)
COPY_BLOCK = 1 << 20  # bytes copied at once from the child's file


def write(out, report, sig: int, failed: list, write_text) -> bool:
    """Write `report`'s full plain text to `out` by `write_text(stream, pieces)`
    (solve_cmd._write_text), made by this process and a forked child; False (nothing
    written) where that cannot be set up (no fork, serial asked, a report not lazy): the
    caller makes the text alone. A piece that fails to be made ends the text there, its
    exception in `failed` (text.until_failure)."""
    if two_process.serial_asked():
        return False
    from .report.text import until_failure
    from .report.text_cuts import cuts

    marks = cuts(report.transitions, RANGES)
    if not marks:
        return False
    bounds = [None] + marks + [None]  # range k: from bounds[k] to bounds[k + 1]
    binary = _byte_stream(out)
    encoding, errors = (out.encoding, out.errors) if binary else ("utf-8", "surrogatepass")
    _prepare(report)
    out.flush()  # before the fork: the child's copy of the buffer is empty

    def here(k: int) -> bool:
        if k == 0:  # the child makes the checks: their trees' memory goes to the text
            release = getattr(report.checks, "release", None)
            if release is not None:
                release()
        write_text(out, until_failure(_pieces(report, sig, bounds, k), failed))
        return not failed

    def there(k: int, sink) -> None:
        write_text(sink, _pieces(report, sig, bounds, k))

    def collect(k: int, fd: int, offset: int, length: int) -> None:
        _copy(out, fd, offset, length, binary, encoding, errors)

    return two_process.share(len(bounds) - 1, here, there, collect, encoding, errors)


def encoded_fields(rep, ascii_only: bool = False, min_equations: int = 0) -> dict:
    """json_out.encoded_fields(rep, ascii_only), the same strings, its fields made by this
    process and a forked child for a report of `min_equations` equations or more (and
    not serial asked)."""
    from .report import json_out

    makers = json_out.field_makers(rep)
    if (rep.counts or {}).get("equations", 0) < min_equations or \
            two_process.serial_asked() or len(makers) < 3:
        return json_out.encoded_fields(rep, ascii_only)
    # shared: every field but the title, the checks first (this process's part 0: the
    # caller reads the checks again), then the rows' fields; the blocks' and diagrams'
    # (matrices, bodies: the longest texts) last, the child's first; the small ones meet
    # in the middle
    shared = sorted((i for i, (key, _) in enumerate(makers) if key != "title"),
                    key=lambda i: _CLAIM_ORDER.get(makers[i][0], 1))
    made: dict = {}

    def encoded(k: int) -> str:
        key, make = makers[shared[k]]
        return json_out.encoded(key, make, rep, ascii_only)

    def here(k: int) -> bool:
        made[shared[k]] = encoded(k)
        return True

    def there(k: int, sink) -> None:
        sink.write(encoded(k))

    def collect(k: int, fd: int, offset: int, length: int) -> None:
        import os

        made[shared[k]] = json_out.Encoded(
            os.pread(fd, length, offset).decode("utf-8", "surrogatepass"))

    _prepare(rep)
    if not two_process.share(len(shared), here, there, collect):
        return json_out.encoded_fields(rep, ascii_only)
    return {key: made[i] if key != "title" else json_out.encoded(key, make, rep, ascii_only)
            for i, (key, make) in enumerate(makers)}


def _prepare(report) -> None:
    """What both processes would make, made once before the fork: the diagrams' shared
    lookups (this process's first range needs them anyway). A bug met here is met
    again, as one process would meet it, where they are needed."""
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


def _pieces(report, sig: int, bounds: list, k: int):
    """Range k's pieces, a newline before them from the second range on (an empty
    piece first: the writer puts a newline only before the range's first piece)."""
    from .report.text import iter_parts

    if k:
        yield ""
    yield from iter_parts(report, sig, True, bounds[k], bounds[k + 1])


def _copy(out, fd: int, offset: int, length: int, binary: bool, encoding, errors) -> None:
    """The child's bytes of one range to `out`: as bytes after the text written so far,
    or decoded (a range is whole characters)."""
    import os

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
