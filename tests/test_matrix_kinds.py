"""Plain text's tables made per kind, against the general table they lay out: a block's
matrix made once per kind of block (text._matrix keeps a kind's cells, widths and rows
on the formatter), and a table given as columns (the Solution table: no row made).

Blocks of one matrix and right side under unknowns of other lengths, other numbers
(-0.0 beside 0.0, None, ints), ragged and empty matrices, other precisions: each block,
made by a formatter that has seen the others, equals `table(unknowns + ["", "rhs"], ...)`.
"""
from __future__ import annotations

import random

from momentum_cli.numbers import fmt_num
from momentum_cli.report import text


def _general(unknowns, matrix, rhs, sig):
    def f(x):
        return "-" if x is None else fmt_num(x, sig)
    rows = [[f(x) for x in row] + ["|", f(r)] for row, r in zip(matrix, rhs)]
    return text.table(unknowns + ["", "rhs"], rows, indent="      ")


def _blocks(rng: random.Random):
    numbers = [1.0, -1.0, 0.0, -0.0, 0.1, 2, None, 123456.789, -1e-12, 3.0]
    names = ["b2.vx@2", "b1.vx@2", "J_n[c1]@1->2", "x", "b10000.vx@10000", "J"]
    kinds = []
    for n in (1, 2, 3, 5):
        m = [[rng.choice(numbers) for _ in range(n)] for _ in range(n)]
        kinds.append((m, [rng.choice(numbers) for _ in range(n)]))
    kinds.append(([[1.0, 2.0], [3.0]], [1.0, 2.0]))  # ragged
    kinds.append(([], []))
    for _ in range(300):
        m, r = rng.choice(kinds)
        n = len(m[0]) if m else rng.randint(0, 2)
        yield [rng.choice(names) for _ in range(n)], m, r


def test_blocks_of_one_kind_print_as_the_general_table():
    rng = random.Random(5)
    for sig in (6, 3):
        f = text.formatter(sig)
        for unknowns, matrix, rhs in _blocks(rng):
            out: list = []
            text._matrix(unknowns, matrix, rhs, f, out)
            assert out == _general(unknowns, matrix, rhs, sig)
        assert f.matrices  # kinds were kept (and so reused)


def test_a_kind_kept_at_one_precision_is_not_shown_at_another():
    m, r = [[1.23456789, 0.0], [2.0, 1.0]], [1.0, 9.87654321]
    for sig in (6, 2, 6):
        out: list = []
        text._matrix(["a", "b"], m, r, text.formatter(sig), out)
        assert out == _general(["a", "b"], m, r, sig)


def _laid_out(headers: list, rows: list) -> list:
    """The table by hand: each cell padded to its column's widest, the last not."""
    widths = [max([len(h)] + [len(r[i]) for r in rows]) for i, h in enumerate(headers)]

    def line(cells):
        return ("  " + "  ".join(c.ljust(w) if i < len(cells) - 1 else c
                                 for i, (c, w) in enumerate(zip(cells, widths)))).rstrip()
    return [line(headers), "  " + "  ".join("-" * w for w in widths)] + [line(r) for r in rows]


def test_a_table_of_columns_is_the_table_of_its_rows():
    rng = random.Random(11)
    cells = ["", "a", "b.vx@2", "  ", "x ", "0.00154984", "-1", "m/s", "N*s", "J_n[b2-b1]@1->2"]
    for n_cols in (2, 3, 4):
        for _ in range(20):
            headers = [rng.choice(["unknown", "value", "unit", "x"]) for _ in range(n_cols)]
            rows = [[rng.choice(cells) for _ in range(n_cols)]
                    for _ in range(rng.choice([0, 1, 2, 7]))]
            cols = [[r[i] for r in rows] for i in range(n_cols)]
            want = _laid_out(headers, rows)
            assert text.column_table(headers, cols) == want
            assert text.table(headers, rows) == want
