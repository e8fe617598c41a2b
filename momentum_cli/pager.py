"""CLI stage: page a long report on a terminal, like git does.

In: what a command prints to stdout while the context is open. Out: the same text,
straight to the terminal when it fits (or stdout is not a terminal), else through
$PAGER (default `less -FRX`: colours kept, quits at the end, screen not cleared).
"""
from __future__ import annotations

import io
import os
import shlex
import sys
from contextlib import contextmanager

DEFAULT_PAGER = "less -FRX"


class _Captured(io.StringIO):
    """stdout while paging: still a terminal to whoever asks (rich keeps its colours)."""

    def __init__(self, real):
        super().__init__()
        self.real = real

    @property
    def encoding(self) -> str:
        return getattr(self.real, "encoding", None) or "utf-8"

    def isatty(self) -> bool:
        return True

    def fileno(self) -> int:
        return self.real.fileno()


def _is_tty(stream) -> bool:
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError):
        return False


def should_page(text: str, stream, rows: int | None = None) -> bool:
    """Longer than the terminal, and the terminal is really one (never into a pipe)."""
    if not _is_tty(stream) or os.environ.get("TERM") == "dumb":
        return False
    import shutil  # here: a piped run never pays for it

    rows = rows if rows is not None else shutil.get_terminal_size((80, 24)).lines
    return text.count("\n") >= rows


def pager_command() -> list[str] | None:
    cmd = os.environ.get("MOMENTUM_PAGER", os.environ.get("PAGER", DEFAULT_PAGER)).strip()
    if not cmd or cmd == "cat":
        return None
    return shlex.split(cmd)


def show(text: str, stream) -> None:
    """Write `text` to `stream`, through the pager when it does not fit the terminal."""
    cmd = pager_command() if should_page(text, stream) else None
    if cmd:
        import subprocess

        env = dict(os.environ)
        env.setdefault("LESS", "FRX")
        try:
            p = subprocess.Popen(cmd, stdin=subprocess.PIPE, env=env)
        except OSError:  # no such pager: print as if there were none
            cmd = None
        else:
            try:
                p.communicate(text.encode(getattr(stream, "encoding", None) or "utf-8",
                                          "replace"))
            except (BrokenPipeError, KeyboardInterrupt):
                pass
            p.wait()
            return
    stream.write(text)
    stream.flush()


@contextmanager
def paged(enabled: bool = True, color: bool = True):
    """Collect stdout while the block runs and show it (paged if long) at the end; does
    nothing unless `enabled` and stdout is a terminal."""
    real = sys.stdout
    if not enabled or not _is_tty(real):
        yield
        return
    buf = _Captured(real)
    sys.stdout = buf
    try:
        yield
    finally:
        sys.stdout = real
        show(buf.getvalue(), real)
