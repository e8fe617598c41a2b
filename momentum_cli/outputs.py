"""Where the command line writes: files asked for (`--csv`, `--plot`) and standard output.

Stage: cli. In: the paths the user named, the text or drawing to put there. Out: files
written whole or not at all (a temporary file, then a rename), never over an input or an
existing file without --force; and one-line errors instead of tracebacks when standard
output is closed, full or a pipe that went away.
"""
from __future__ import annotations

import errno
import os
import stat
import sys


# temporary files being filled now: a signal handler removes them before the process ends
PENDING: set[str] = set()


def remove_pending() -> None:
    """Remove every temporary file still being written (the run is ending)."""
    for tmp in list(PENDING):
        _drop(tmp)


def _drop(tmp: str) -> None:
    """Remove one temporary file (gone already is fine) and forget it."""
    try:
        os.unlink(tmp)
    except OSError:
        pass
    PENDING.discard(tmp)


class OutputError(Exception):
    """A path that cannot be written as asked; its message is one line."""


def check_path(path: str, inputs, force: bool, option: str, formats=None) -> None:
    """Before any work: refuse a path that would lose data or cannot be written.

    `-` is standard output. `formats` (suffixes without a dot) limits the file types.
    """
    if path == "-":
        return
    if formats is not None:
        ext = os.path.splitext(path)[1].lstrip(".").lower()
        if ext not in formats:
            raise OutputError(f"{option} {path}: unknown file type '.{ext}' (use one of "
                              f"{', '.join('.' + f for f in sorted(formats))})")
    for src in inputs:
        if src != "-" and _same(src, path):
            raise OutputError(f"{option} {path}: that is an input file; it would be "
                              "overwritten")
    if os.path.isdir(path):
        raise OutputError(f"{option} {path}: is a directory")
    if os.path.lexists(path):
        st = os.lstat(path)
        if not stat.S_ISREG(st.st_mode):
            raise OutputError(f"{option} {path}: exists and is not a regular file (write to "
                              "standard output with '-')")
        if not force:
            raise OutputError(f"{option} {path}: exists; add --force to overwrite it")
    folder = os.path.dirname(path) or "."
    if not os.path.isdir(folder):
        raise OutputError(f"{option} {path}: no such folder {folder}")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise OutputError(f"{option} {path}: the folder {folder} is not writable")


def _same(a: str, b: str) -> bool:
    try:
        return os.path.samefile(a, b)
    except OSError:
        return os.path.abspath(a) == os.path.abspath(b)


def write_text(path: str, text: str, force: bool, option: str) -> None:
    """`text` to `path` whole (or to standard output for `-`)."""
    if path == "-":
        sys.stdout.write(text)
        sys.stdout.flush()
        return
    _atomic(path, force, option, lambda tmp: _write_file(tmp, text.encode("utf-8")))


def write_stream(path: str, write, force: bool, option: str) -> None:
    """`write(fh)` writes text to an open file that then takes `path` whole (large
    outputs are never held in memory), or to standard output for `-`."""
    if path == "-":
        write(sys.stdout)
        sys.stdout.flush()
        return

    def fill(tmp: str) -> None:
        with open(tmp, "w", encoding="utf-8", newline="") as fh:
            write(fh)
            fh.flush()
            os.fsync(fh.fileno())

    _atomic(path, force, option, fill)


def write_drawing(path: str, draw, force: bool, option: str) -> None:
    """`draw(tmp_path)` makes the file (its type from the suffix); it then takes `path`
    whole, or goes to standard output for `-` (as PNG)."""
    import tempfile  # only when writing a file

    if path == "-":
        fd, tmp = tempfile.mkstemp(suffix=".png")
        os.close(fd)
        PENDING.add(tmp)
        try:
            draw(tmp)
            with open(tmp, "rb") as fh:
                data = fh.read()
        finally:
            os.unlink(tmp)
            PENDING.discard(tmp)
        sys.stdout.flush()
        sys.stdout.buffer.write(data)
        sys.stdout.buffer.flush()
        return
    _atomic(path, force, option, draw)


def _write_file(tmp: str, data: bytes) -> None:
    with open(tmp, "wb") as fh:
        fh.write(data)
        fh.flush()
        os.fsync(fh.fileno())


def _atomic(path: str, force: bool, option: str, fill) -> None:
    """A temporary file beside `path`, filled, then renamed onto it (`os.replace` with
    --force; else `os.link`, which refuses a file that appeared meanwhile)."""
    import tempfile

    folder = os.path.dirname(path) or "."
    try:
        fd, tmp = tempfile.mkstemp(prefix=".momentum-", suffix=os.path.splitext(path)[1],
                                   dir=folder)
        os.close(fd)
        PENDING.add(tmp)
    except OSError as exc:
        raise OutputError(f"{option} {path}: cannot write: {exc.strerror}") from None
    try:
        fill(tmp)
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
        if force:
            os.replace(tmp, path)
        else:
            os.link(tmp, path)
    except FileExistsError:
        raise OutputError(f"{option} {path}: exists; add --force to overwrite it") from None
    except OSError as exc:
        raise OutputError(f"{option} {path}: cannot write: {exc.strerror or exc}") from None
    finally:
        _drop(tmp)


# ---- standard output ------------------------------------------------------------------
class OutputGone(BaseException):
    """Standard output's reader went away (a broken pipe): stop quietly. A BaseException,
    so that no `except Exception` on the way turns it into an internal error."""


class OutputFailed(BaseException):
    """Standard output cannot be written (disk full, closed, I/O error)."""

    def __init__(self, exc: OSError):
        super().__init__(exc.strerror or str(exc))
        self.reason = exc.strerror or str(exc)


class GuardedStream:
    """Standard output, with its write errors turned into OutputGone / OutputFailed."""

    def __init__(self, stream):
        self._stream = stream

    def _call(self, fn, *args):
        try:
            return fn(*args)
        except BrokenPipeError:
            raise OutputGone() from None
        except OSError as exc:
            raise OutputFailed(exc) from None
        except ValueError as exc:  # written after a close
            raise OutputFailed(OSError(errno.EBADF, str(exc))) from None

    def write(self, text):
        return self._call(self._stream.write, text)

    def flush(self):
        return self._call(self._stream.flush)

    @property
    def buffer(self):
        return _GuardedBuffer(self._stream.buffer, self._call)

    def __getattr__(self, name):
        return getattr(self._stream, name)


class _GuardedBuffer:
    def __init__(self, buffer, call):
        self._buffer, self._call = buffer, call

    def write(self, data):
        return self._call(self._buffer.write, data)

    def flush(self):
        return self._call(self._buffer.flush)

    def __getattr__(self, name):
        return getattr(self._buffer, name)


def stdout_is_closed() -> bool:
    """True when the process started with file descriptor 1 closed (`>&-`)."""
    if sys.stdout is None:
        return True
    try:
        os.fstat(1)
    except OSError:
        return True
    return False


def silence_stdout() -> None:
    """Point descriptor 1 at /dev/null, so that the interpreter's last flush at exit
    finds nothing to complain about."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, 1)
        os.close(devnull)
    except OSError:
        pass
