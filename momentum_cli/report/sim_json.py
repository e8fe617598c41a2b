"""One simulation's entry in the JSON document of `momentum simulate` (the document
itself is report/json_out.document, shared with `solve`).
"""
from __future__ import annotations


def json_result(rep: dict | None, name: str, status: str, diagnostics) -> dict:
    d = {"file": name, "status": status, "diagnostics": [x.to_json() for x in diagnostics]}
    if rep is not None:
        d.update({k: rep[k] for k in ("title", "start", "stop", "t_end", "rtol", "dt",
                                      "seconds", "effects", "events", "phases", "final",
                                      "forces", "checks", "impacts")})
    return d
