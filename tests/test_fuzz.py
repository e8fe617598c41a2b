"""Fuzzing: mutated example files never raise; they solve or give located diagnostics.

Every example file is mutated (tokens deleted, swapped or duplicated, random
characters inserted, numbers replaced by huge, tiny or non-finite ones, deep
brackets, very long lines, broken indentation). Whatever the mutation, `solve_source`
returns a FileResult: solved, or an error with diagnostics whose positions are 1-based
and inside the file, which render without error; a solved result gives valid JSON
with no NaN. Bounded and derandomized so that CI runs the same cases every time.

An example that already raises unmutated is left out here (test_cli reports it as an
internal error, exit code 3), so that a failure below is always due to a mutation.
"""
from __future__ import annotations

import functools
import json
import re

from conftest import EXAMPLES
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from momentum_cli.report.json_out import document, result_dict
from momentum_cli.run import FileResult, SourceTextError, decode_source, solve_source
from momentum_cli.source import Source

TEXTS = {p.name: p.read_text(encoding="utf-8") for p in sorted(EXAMPLES.glob("*.mom"))}
TOKEN = re.compile(r"\s+|[A-Za-z_][A-Za-z_0-9]*|\d+\.?\d*(?:[eE][-+]?\d+)?|.", re.S)
NUMBER = re.compile(r"\d+\.?\d*(?:[eE][-+]?\d+)?")
ODD_NUMBERS = ["1e999", "1e308", "-1e308", "1e-320", "1e-999", "0", "0.0", "-0", "nan", "inf",
               "-inf", "NaN", "9" * 400, "1e308 * 1e308", "0 / 0", "1 / 0", "(1e308)^2",
               "exp(1e9)", "sqrt(-1)", "1e-308 / 1e308"]



@functools.lru_cache(maxsize=1)
def runnable() -> list[str]:
    """The examples that run without an exception as they are."""
    out = []
    for name, text in TEXTS.items():
        try:
            solve_source(Source(name, text))
        except Exception:  # reported by test_cli's every-example test
            continue
        out.append(name)
    return out


FUZZ = settings(max_examples=200, deadline=None, derandomize=True, database=None,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])


def _delete(toks, i, _j, _s):
    return toks[:i] + toks[i + 1:]


def _duplicate(toks, i, _j, _s):
    return toks[:i + 1] + toks[i:]


def _swap(toks, i, j, _s):
    toks = list(toks)
    toks[i], toks[j] = toks[j], toks[i]
    return toks


def _insert(toks, i, _j, s):
    return toks[:i] + [s] + toks[i:]


def _deep(toks, i, j, _s):
    k = 1 + (j * 7) % 260  # up to 260 brackets: some over the limit, most under
    return toks[:i] + ["(" * k + toks[i] + ")" * k] + toks[i + 1:]


def _long(toks, i, j, _s):
    k = 50 + (j * 97) % 3000  # a long flat sum, or a long run of a token
    filler = "+1" * k if j % 2 else toks[i] * k
    return toks[:i + 1] + [filler] + toks[i + 1:]


def _odd_number(toks, i, j, _s):
    nums = [n for n, t in enumerate(toks) if NUMBER.fullmatch(t)]
    if not nums:
        return toks
    n = nums[i % len(nums)]
    return toks[:n] + [ODD_NUMBERS[j % len(ODD_NUMBERS)]] + toks[n + 1:]


def _indent(toks, i, j, _s):
    spaces = [n for n, t in enumerate(toks) if "\n" in t]
    if not spaces:
        return toks
    n = spaces[i % len(spaces)]
    toks = list(toks)
    toks[n] = toks[n].split("\n")[0] + "\n" + ["", "  ", "\t", "      ", "   \t"][j % 5]
    return toks


MUTATIONS = [_delete, _duplicate, _swap, _insert, _deep, _long, _odd_number, _indent]

mutation = st.tuples(st.sampled_from(MUTATIONS), st.integers(0, 10_000), st.integers(0, 10_000),
                     st.text(max_size=6) | st.sampled_from(["(", ")", ":", ",", "->", "@", "\n",
                                                            "\n    ", "\t", "#", '"', "\\\n",
                                                            "\x00", "\r", "\ufeff", "1e999"]))


def mutate(text: str, steps) -> str:
    toks = TOKEN.findall(text)
    for fn, i, j, s in steps:
        if not toks:
            toks = [s]
            continue
        toks = fn(toks, i % len(toks), j % len(toks), s)
    return "".join(toks)


def assert_well_formed(res: FileResult, source: Source) -> None:
    assert isinstance(res, FileResult)
    assert res.status in ("solved", "error"), res.status
    n_lines = source.text.count("\n") + 1
    if res.status == "error":
        assert any(d.severity == "error" for d in res.diagnostics)
    for d in res.diagnostics:
        assert d.message
        if d.span is not None:
            assert 1 <= d.span.line <= n_lines, (d.span, d.message)
            assert d.span.column >= 1, (d.span, d.message)
        d.format(source)  # the snippet renders whatever the line holds
    doc = json.loads(document([result_dict(source.name, res.status, res.report,
                                           res.diagnostics)], "0"))
    assert doc["results"][0]["status"] == res.status


@FUZZ
@given(data=st.data(), steps=st.lists(mutation, min_size=1, max_size=3))
def test_mutated_examples_solve_or_fail_with_located_diagnostics(data, steps):
    name = data.draw(st.sampled_from(runnable()), label="example")
    source = Source(name, mutate(TEXTS[name], steps))
    assert_well_formed(solve_source(source), source)


@FUZZ
@given(pick=st.data(), data=st.binary(max_size=16), at=st.integers(0, 10**6))
def test_random_bytes_in_a_file_never_raise(pick, data, at):
    name = pick.draw(st.sampled_from(runnable()), label="example")
    raw = TEXTS[name].encode("utf-8")
    at %= len(raw) + 1
    try:
        source = decode_source(name, raw[:at] + data + raw[at:])
    except SourceTextError as exc:
        d = exc.diagnostics[0]
        assert d.span.line >= 1 and d.span.column >= 1 and d.code == "encoding"
        d.format(exc.source)
        return
    assert_well_formed(solve_source(source), source)


def test_the_seed_examples_are_all_fuzzed():
    seeds = [n for n in TEXTS if n.startswith("seed_")]
    assert len(seeds) >= 9 and set(seeds) <= set(runnable())
