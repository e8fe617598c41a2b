"""Syntax stage: a module's regular expressions compiled once per Python, kept on disk.

In: a set name and its patterns ({name: pattern}). Out: {name: compiled pattern}, the
same objects `re.compile` makes, built from CPython's regex code stored in the cache
folder (`syntax_tables._sre_args`, the way the parse tables keep their lexers): the
regex compiler costs syntax_lines ~13 ms a process, loading its code ~0.2 ms. The file
is used only when it was written by this Python from exactly these patterns.
"""
from __future__ import annotations

import re
import sys

FORMAT = 1  # bump when the file's layout changes


def _identity(patterns: dict[str, str]) -> dict:
    return {"format": FORMAT, "python": sys.version, "patterns": patterns}


def cache_name(group: str, patterns: dict[str, str]) -> str:
    """The file's name: the set's name, its patterns' checksum, the Python version."""
    import zlib

    crc = zlib.crc32(repr(sorted(patterns.items())).encode())
    v = sys.version_info
    return f"regex-{group}-{crc:08x}-{v[0]}{v[1]}-{FORMAT}.marshal"


def compiled(group: str, patterns: dict[str, str]) -> dict[str, re.Pattern]:
    """Each pattern compiled: from the stored code when a file of this Python and these
    patterns is in the cache folder, else by `re.compile` (and the file written for the
    next process). Any doubt about the file (another Python, a pattern changed, a
    damaged file, code `_sre` refuses): `re.compile`."""
    folder, path = None, None
    try:
        import os

        from . import cache_files

        folder = cache_files.cache_dir()
        path = os.path.join(folder, cache_name(group, patterns)) if folder else None
        data = cache_files.read(path) if path else None
        made = _load(data, patterns) if data else None
    except Exception:  # noqa: BLE001 - the cache is an optimisation only
        made = None
    if made is not None:
        return made
    out = {k: re.compile(p) for k, p in patterns.items()}
    if path:
        _store(path, patterns)
    return out


def _load(data: bytes, patterns: dict[str, str]) -> dict[str, re.Pattern] | None:
    """The patterns made from a file's bytes, or None when they do not belong here."""
    import _sre
    import marshal

    try:
        stored = marshal.loads(data)
    except (EOFError, ValueError, TypeError):
        return None
    if not isinstance(stored, dict) or stored.get("identity") != _identity(patterns):
        return None
    codes = stored.get("codes")
    if not isinstance(codes, dict) or codes.keys() != patterns.keys():
        return None
    out = {}
    for k, p in patterns.items():
        args = codes[k]
        if not isinstance(args, tuple) or not args or args[0] != p:
            return None
        made = _sre.compile(*args)  # (it validates the code: a bad file raises)
        if made.pattern != p:
            return None
        out[k] = made
    return out


def _store(path: str, patterns: dict[str, str]) -> None:
    """Write the patterns' code for the next process (nothing when this Python's regex
    compiler is not the one `_sre_args` knows)."""
    import marshal

    from .cache_files import write
    from .syntax_tables import _sre_args

    codes = {}
    for k, p in patterns.items():
        args = _sre_args(p, 0)
        if args is None:
            return
        codes[k] = args
    write(path, marshal.dumps({"identity": _identity(patterns), "codes": codes}))
