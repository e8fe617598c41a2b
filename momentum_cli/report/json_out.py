"""JSON output: one document, a stable schema (`schema_version` "1"), never NaN.

The schema ships as `momentum_cli/schema/momentum-result.schema.json` and the tests
validate every example's output against it.
"""
from __future__ import annotations

import json
import math
from json.encoder import encode_basestring, encode_basestring_ascii

SCHEMA_VERSION = "1"


def clean(x):
    """Replace non-finite floats by None, recursively (JSON has no NaN)."""
    if isinstance(x, float):
        return x if math.isfinite(x) else None
    if isinstance(x, dict):
        return {k: clean(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [clean(v) for v in x]
    return x


def dumps(x, ascii_only: bool = False, indent: str = "") -> str:
    """`json.dumps(clean(x), allow_nan=False, indent=2, ensure_ascii=ascii_only)`, byte
    for byte, with every line after the first prefixed by `indent`: one recursive pass
    that appends strings (the json module's indented encoder is pure Python, made of
    generators, and `clean` is a second pass; a 10^4-ball result took seconds). An
    `Encoded` value is written as it is."""
    esc = encode_basestring_ascii if ascii_only else encode_basestring
    out: list = []
    _encode(x, out, "\n" + indent, esc)
    return "".join(out)


_INF = float("inf")
_FLOAT_REPR = float.__repr__
_INT_REPR = int.__repr__


def _scalar(x, esc):
    """A value that is not a list, tuple or dict as json writes it, tested in json's
    order (a str or int subclass such as an enum is the str or int it is); None for a
    container."""
    if isinstance(x, str):
        return esc(x)
    if x is None:
        return "null"
    if x is True:
        return "true"
    if x is False:
        return "false"
    if isinstance(x, int):
        return _INT_REPR(x)
    if isinstance(x, float):
        return _FLOAT_REPR(x) if x == x and x != _INF and x != -_INF else "null"
    if isinstance(x, (list, tuple, dict)):
        return None
    raise TypeError(f"Object of type {x.__class__.__name__} is not JSON serializable")


def _encode(x, out: list, nl: str, esc) -> None:
    """`x` as json's indented encoder writes it, non-finite floats as null (`clean`);
    `nl`: a newline and this level's indentation. The common exact types first."""
    if isinstance(x, dict):
        if not x:
            out.append("{}")
            return
        inner = nl + "  "
        sep = "{" + inner
        start = len(out)
        for k, v in x.items():
            if not isinstance(k, str):  # json's own conversion of such keys, for this dict
                del out[start:]
                text = json.dumps(clean(x), allow_nan=False, indent=2,
                                  ensure_ascii=esc is encode_basestring_ascii)
                out.append(text.replace("\n", nl))
                return
            t = type(v)
            if t is str:
                out.append(f"{sep}{esc(k)}: {esc(v)}")
            elif t is Encoded:
                out.append(f"{sep}{esc(k)}: {v}")
            elif t is float and v == v and v != _INF and v != -_INF:
                out.append(f"{sep}{esc(k)}: {_FLOAT_REPR(v)}")
            else:
                s = _scalar(v, esc) if t is not dict and t is not list else None
                if s is None:
                    out.append(f"{sep}{esc(k)}: ")
                    _encode(v, out, inner, esc)
                else:
                    out.append(f"{sep}{esc(k)}: {s}")
            sep = "," + inner
        out.append(nl + "}")
    elif isinstance(x, (list, tuple)):
        if not x:
            out.append("[]")
            return
        inner = nl + "  "
        sep = "[" + inner
        keys = heads = None  # the last dict's keys, and their written heads
        for v in x:
            t = type(v)
            if t is dict and v:
                # a list of records (equations, unknowns, impulses): each key's head,
                # `,\n  "key": `, written once for every dict with the same keys
                ks = tuple(v)
                if ks != keys:
                    heads = _heads(ks, inner + "  ", esc)
                    keys = ks
                if heads is None:
                    out.append(sep)
                    _encode(v, out, inner, esc)
                else:
                    out.append(sep)
                    _fields(v, heads, out, inner, esc)
                sep = "," + inner
                continue
            if t is str:
                out.append(sep + esc(v))
            elif t is float and v == v and v != _INF and v != -_INF:
                out.append(sep + _FLOAT_REPR(v))
            else:
                s = _scalar(v, esc) if t is not dict and t is not list else None
                if s is None:
                    out.append(sep)
                    _encode(v, out, inner, esc)
                else:
                    out.append(sep + s)
            sep = "," + inner
        out.append(nl + "]")
    else:
        out.append(_scalar(x, esc))


def _heads(keys: tuple, inner: str, esc) -> list | None:
    """`{` or `,` then the newline, indentation and key of each field of a dict with
    these keys (None if a key is not a str: json's own conversion then)."""
    if not all(type(k) is str for k in keys):
        return None
    return [("{" if i == 0 else ",") + inner + esc(k) + ": " for i, k in enumerate(keys)]


def _fields(x: dict, heads: list, out: list, nl: str, esc) -> None:
    """A non-empty dict whose keys' heads are `heads`, as `_encode` writes it."""
    inner = nl + "  "
    for head, v in zip(heads, x.values()):
        t = type(v)
        if t is str:
            out.append(head + esc(v))
        elif t is float:
            out.append(head + (_FLOAT_REPR(v) if v == v and v != _INF and v != -_INF
                               else "null"))
        elif v is None:
            out.append(head + "null")
        elif t is int:
            out.append(head + _INT_REPR(v))
        elif t is Encoded:
            out.append(head + v)
        else:
            s = _scalar(v, esc) if t is not dict and t is not list else None
            if s is None:
                out.append(head)
                _encode(v, out, inner, esc)
            else:
                out.append(head + s)
    out.append(nl + "}")


def result_dict(file: str, status: str, rep=None, diagnostics=(), check_counts=None) -> dict:
    """One file's result. `rep`: its report, or what a worker made of it (an object with
    `fields`, `report_fields` already encoded: see `encoded_fields`)."""
    fields = getattr(rep, "fields", None) if rep is not None else None
    if rep is not None and fields is None:
        fields = report_fields(rep)
    d: dict = {"file": file, "status": status, "title": fields["title"] if fields else None,
               "answers": [], "unknowns": [], "equations": [], "checks": [],
               "diagnostics": [x.to_json() for x in diagnostics]}
    for k, v in (fields or {}).items():
        if k != "title":
            d[k] = v  # answers ... checks in their places, the rest after diagnostics
    if check_counts is not None:
        d["counts"] = dict(check_counts)
    return d


def report_fields(rep) -> dict:
    """The report's part of a result, in the result's key order (title first)."""
    return {key: make(rep) for key, make in field_makers(rep)}


def field_makers(rep) -> list:
    """(key, make) of each field of `report_fields`, in its order: `make(rep)` gives the
    field's value, made apart from the others (two processes may make them: forked_text)."""
    # the schema's fields only: unknowns in SI; an answer's value in its unit (`find
    # ... in UNIT`, else the reader's units) beside si_value
    out = [("title", _title), ("answers", _answers), ("unknowns", _unknowns),
           ("equations", _equations), ("checks", _checks), ("blocks", _blocks),
           ("transitions", _transitions), ("regimes", _regimes), ("counts", _counts)]
    if rep.flows:
        out.append(("flows", _flows))
    if rep.diagrams:
        out.append(("diagrams", _diagrams))
    if rep.expectations:
        out.append(("expectations", _expectations))
    if rep.sensitivities:
        out.append(("sensitivities", _sensitivities))
    return out


def _title(rep):
    return rep.title


def _answers(rep) -> list:
    return [{k: a[k] for k in ("name", "value", "unit", "si_value")} for a in rep.answers]


def _unknowns(rep) -> list:
    return [{k: u[k] for k in ("name", "si_value", "unit")} for u in rep.unknowns]


def _equations(rep) -> list:
    """Every row, by its equation's number (a lazy report's made without its
    transitions' statements and diagrams)."""
    from .model import rows_of  # here: the batch's parent writes JSON without the model

    rows: list = []
    ts = rep.transitions
    for i in range(len(ts)):
        rows += rows_of(ts, i)
    rows += [r for rs in rep.other_equations.values() for r in rs]
    rows.sort(key=lambda r: r.index)
    return [dict(index=r.index + 1, principle=r.principle, group=r.group, line=r.line,
                 symbolic=r.symbolic, numeric=r.numeric, kind=r.kind, role=r.role)
            for r in rows]


def _checks(rep) -> list:
    return [dict(name=c.name, status=c.status, detail=c.detail, value=c.value)
            for c in rep.checks]


def _blocks(rep) -> list:
    return [dict(b) for b in rep.blocks]


def _transitions(rep) -> list:
    return [dict(kind=t["kind"], before=t["before"], after=t["after"], line=t["line"],
                 why=t["why"]) for t in rep.transitions]


def _regimes(rep) -> list:
    return list(rep.regimes)


def _counts(rep) -> dict:
    return dict(rep.counts)


def _flows(rep) -> list:
    return [dict(r) for r in rep.flows]


def _diagrams(rep) -> list:
    return [x.to_dict() for x in rep.diagrams]


def _expectations(rep) -> list:
    return [dict(e) for e in rep.expectations]


def _sensitivities(rep):
    return rep.sensitivities


class Encoded(str):
    """A value's JSON text, made where the file was solved (a worker), written by
    `dumps` as it is: for a value of a result inside `DocumentStream`'s document."""


def encoded_fields(rep, ascii_only: bool = False) -> dict:
    """`report_fields` with each value already JSON text, indented as `DocumentStream`
    writes a result's values: a worker ships this small dict of strings, not the report,
    and the parent only joins it. Each field is made and encoded before the next (its
    records are not held beside the others')."""
    return {key: encoded(key, make, rep, ascii_only) for key, make in field_makers(rep)}


def encoded(key: str, make, rep, ascii_only: bool = False):
    """One field of `encoded_fields`: its value made by `make` (`field_makers`), as JSON
    text (the title as it is)."""
    if key == "title":
        return make(rep)
    return Encoded(dumps(make(rep), ascii_only, "      "))


class DocumentStream:
    """`document`, written one result at a time as each file is solved (byte for byte the
    same text): a call on thousands of files holds one result, not all of them. Has the
    list's `append`, so a loop that collects results can stream them instead."""

    def __init__(self, out, version: str, ascii_only: bool = False, key: str = "results"):
        self.out, self.ascii_only, self.count = out, ascii_only, 0
        head = json.dumps({"schema_version": SCHEMA_VERSION, "momentum_version": version},
                          indent=2, ensure_ascii=ascii_only)
        self.head = head[:-2] + f',\n  {json.dumps(key)}: ['  # without the closing "\n}"

    def append(self, result: dict) -> None:
        text = dumps(result, self.ascii_only, "    ")
        self.out.write((self.head + "\n" if self.count == 0 else ",\n") + "    " + text)
        self.count += 1

    def close(self) -> None:
        self.out.write(self.head + "]\n}\n" if self.count == 0 else "\n  ]\n}\n")


def document(results: list[dict], version: str, ascii_only: bool = False,
             key: str = "results") -> str:
    """The JSON document (`results` of solve, `simulations` of simulate); `ascii_only`
    escapes non-ASCII text as \\uXXXX (for a stdout whose encoding is not UTF-8: the
    output stays valid JSON)."""
    doc = {"schema_version": SCHEMA_VERSION, "momentum_version": version, key: results}
    return dumps(doc, ascii_only) + "\n"
