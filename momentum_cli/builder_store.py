"""Parse stage: syntax_lines' builders (a function per shape of line) kept between runs.

In: each builder's compiled code, keyed by its shape (the line's text with the digits
1-9 written 0). Out: the code of the shapes a run met before, from a file in the cache
folder. Making a builder costs ~0.5 ms (three readings of a line, its source, the
compile, three checks): the 10^4-ball chain's masses come in 93 layouts of digits, 34 ms
of its 150 ms parse. The file is used only when written by this Python from the same
syntax_lines, syntax and source modules and the same grammar (a checksum of their text).
"""
from __future__ import annotations

import sys

FORMAT = 1
LIMIT = 1024  # builders kept in the file (the newest when more; ~2.5 kB each)

_STORED: list = []  # [codes by shape] once loaded ({} when there is no file or no folder)
_ADDED: dict = {}  # shape -> code made in this run, not in the file yet
_PATH: list = []  # [the file's path or None, the identity], once asked
_MADE_FROM: list = []  # [(grammar text, the modules whose text the builders depend on)]


def configure(grammar: str, modules) -> None:
    """What builders are made from (syntax_lines.setup): another grammar or module set
    starts afresh."""
    if _MADE_FROM and _MADE_FROM[0][0] == grammar and _MADE_FROM[0][1] == tuple(modules):
        return
    forget()
    _MADE_FROM.append((grammar, tuple(modules)))


def _identity(grammar: str, modules) -> dict | None:
    """What the stored code was made from, or None when a module's text is unreadable
    (then nothing is stored)."""
    import zlib

    crc = zlib.crc32(grammar.encode())
    for mod in modules:
        try:
            with open(mod.__file__, "rb") as fh:
                crc = zlib.crc32(fh.read(), crc)
        except (OSError, TypeError, AttributeError):
            return None
    return {"format": FORMAT, "python": sys.version, "modules": crc}


def _path() -> str | None:
    if not _PATH:
        import os

        from . import cache_files

        folder = cache_files.cache_dir() if _MADE_FROM else None
        ident = _identity(*_MADE_FROM[0]) if folder else None
        _PATH.append(os.path.join(folder, f"builders-{ident['modules']:08x}-"
                                          f"{sys.version_info[0]}{sys.version_info[1]}-"
                                          f"{FORMAT}.marshal") if ident else None)
        _PATH.append(ident)
    return _PATH[0]


def get(shape: bytes):
    """The stored code of `shape`'s builder, or None."""
    if not _STORED:
        _STORED.append(_load())
    return _STORED[0].get(shape)


def _load() -> dict:
    import marshal

    from . import cache_files

    path = _path()
    data = cache_files.read(path) if path else None
    if not data:
        return {}
    try:
        stored = marshal.loads(data)
    except (EOFError, ValueError, TypeError):
        return {}
    if not isinstance(stored, dict) or stored.get("identity") != _PATH[1]:
        return {}
    codes = stored.get("codes")
    return codes if isinstance(codes, dict) else {}


def add(shape: bytes, code) -> None:
    """Remember a builder made in this run (written by `flush`)."""
    _ADDED[shape] = code


def flush() -> None:
    """Write the builders made in this run beside those stored (once per parse)."""
    if not _ADDED:
        return
    import marshal

    from . import cache_files

    path = _path()
    if path is None:
        _ADDED.clear()
        return
    if not _STORED:
        _STORED.append(_load())
    codes = _STORED[0]
    codes.update(_ADDED)
    _ADDED.clear()
    if len(codes) > LIMIT:
        for k in list(codes)[:len(codes) - LIMIT]:
            del codes[k]
    cache_files.write(path, marshal.dumps({"identity": _PATH[1], "codes": codes}))


def forget() -> None:
    """Forget what was loaded and made (tests: another cache folder, another run)."""
    _STORED.clear()
    _ADDED.clear()
    _PATH.clear()
    _MADE_FROM.clear()
