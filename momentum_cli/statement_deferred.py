"""Parse stage, big files: a Document some of whose statements are still their text.

syntax_lines keeps a big file's body lines and impacts' contact lines whose shape has a
builder as deferred items, (node class, make, text, line) with make(text, line) the
node: the scene reads most of them from their text (scene_deferred.py) and never needs
their ~20 records a line. Whatever else reads `statements` gets the nodes, made on the
first read, the same nodes the parse would have made. (The Document class is passed in:
syntax imports this module.)
"""
from __future__ import annotations

_CLASSES: dict = {}  # Document class -> its deferred subclass


def made(parts) -> tuple:
    """The statement nodes of `parts` (nodes and deferred items, in file order)."""
    return tuple([p if p.__class__ is not tuple else p[1](p[2], p[3]) for p in parts])


def deferred_class(document):
    """The subclass of the record class `document` (syntax.Document) whose
    `statements` are made from `parts` when first read; equal to (and pickled as) the
    Document of those statements."""
    got = _CLASSES.get(document)
    if got is not None:
        return got
    fields = document._fields

    class DeferredDocument(document):
        __slots__ = ("parts", "_made")

        @property
        def statements(self) -> tuple:
            got = self._made
            if got is None:
                got = made(self.parts)
                object.__setattr__(self, "_made", got)
            return got

        def __eq__(self, other):
            if not isinstance(other, document):
                return NotImplemented
            return all(getattr(self, f) == getattr(other, f) for f in fields)

        def __hash__(self):
            return hash(tuple(getattr(self, f) for f in fields))

    _CLASSES[document] = DeferredDocument
    return DeferredDocument


def document(cls, source, parts: tuple, si_text: bool):
    """The document (a `cls`, syntax.Document) of `parts` (nodes and deferred items)
    read from `source`."""
    doc = object.__new__(deferred_class(cls))
    put = object.__setattr__
    put(doc, "source", source)
    put(doc, "si_text", si_text)
    put(doc, "parts", parts)
    put(doc, "_made", None)
    return doc
