"""The cache folder and its files: where the parser, its tables and compiled regexes live.

In: a file name. Out: the folder ($MOMENTUM_CACHE_DIR, XDG, ~/.cache/momentum), a file's
bytes only when it is a private regular file of this user (a pickle runs code when
loaded), and atomic writes. Shared by syntax.py (lark's pickle, the parse tables) and
regex_store.py (syntax_lines' regexes).
"""
from __future__ import annotations

import os


def cache_dir() -> str | None:
    """The cache folder: $MOMENTUM_CACHE_DIR, else $XDG_CACHE_HOME/momentum (only when
    absolute, as the XDG spec says), else ~/.cache/momentum; created private (0700)."""
    base = os.environ.get("MOMENTUM_CACHE_DIR")
    if not base:
        xdg = os.environ.get("XDG_CACHE_HOME", "")
        root = xdg if os.path.isabs(xdg) else os.path.join(os.path.expanduser("~"), ".cache")
        base = os.path.join(root, "momentum")
    if not os.path.isabs(base):
        base = os.path.abspath(base)
    try:
        os.makedirs(base, mode=0o700, exist_ok=True)
    except OSError:
        return None
    return base


def _note(message: str) -> None:
    import sys

    try:
        sys.stderr.write(f"momentum: note: {message}\n")
    except (OSError, ValueError):
        pass


def read(path: str) -> bytes | None:
    """The cache file's bytes, only when it is a regular file owned by this user and
    writable by nobody else: a pickle runs code when loaded. A symlink, FIFO or device
    is never opened for reading (O_NOFOLLOW, O_NONBLOCK, then fstat)."""
    import stat

    flags = os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_NONBLOCK", 0)
    try:
        fd = os.open(path, flags)
    except FileNotFoundError:
        return None
    except OSError:  # a symlink (ELOOP), no permission...
        _note(f"parser cache {path} is not a plain file of yours; not used")
        return None
    try:
        st = os.fstat(fd)
        owner = os.getuid() if hasattr(os, "getuid") else st.st_uid
        if not stat.S_ISREG(st.st_mode) or st.st_uid != owner or \
                st.st_mode & (stat.S_IWGRP | stat.S_IWOTH):
            _note(f"parser cache {path} is not a private file of yours (owner, mode or type); "
                  "not loaded, the parser is built in memory")
            return None
        chunks = []
        while True:
            chunk = os.read(fd, 1 << 20)
            if not chunk:
                break
            chunks.append(chunk)
        return b"".join(chunks)
    except OSError:
        return None
    finally:
        os.close(fd)


def write(path: str, data: bytes) -> None:
    """Write atomically: a private temporary file in the same folder, then rename, so
    that a concurrent start reads the old file or the new one, never half of one."""
    import tempfile

    folder = os.path.dirname(path)
    try:
        fd, tmp = tempfile.mkstemp(prefix=".grammar-", suffix=".tmp", dir=folder)
    except OSError:
        return
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
        os.replace(tmp, path)
    except OSError:
        try:
            os.unlink(tmp)
        except OSError:
            pass
