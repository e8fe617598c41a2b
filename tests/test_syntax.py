"""Stage 1, parse: text -> frozen syntax nodes with spans."""
from __future__ import annotations

import dataclasses

import pytest

from momentum_cli import syntax as S
from momentum_cli.diagnostics import ProblemError
from momentum_cli.source import Source


def parse(text: str) -> S.Document:
    return S.parse(Source("t.mom", text))


def test_units_bind_to_the_number_before_them():
    (stmt,) = parse("let v = sqrt(2*g*1 m)\n").statements
    call = stmt.value
    assert isinstance(call, S.Call) and call.fn == "sqrt"
    product = call.args[0]
    assert isinstance(product.right, S.Num) and product.right.unit == "m"
    assert isinstance(product.left.right, S.Ref) and product.left.right.name == "g"


def test_caret_and_double_star_powers_in_units_are_one_token():
    (stmt,) = parse("gravity 9.81 m/s**2 down\n").statements
    assert stmt.magnitude.unit == "m/s**2" and stmt.direction == "down"


def test_inch_is_a_unit_where_a_quantity_is_expected():
    (stmt,) = parse("let r = 6 in\n").statements
    assert stmt.value.unit == "in"


def test_find_in_unit_is_not_taken_for_inches():
    (stmt,) = parse("find rod.omega@3 in rpm, t@1->2\n").statements
    a, b = stmt.items
    assert a.unit == "rpm" and a.expr.text == "rod.omega@3"
    assert b.expr.text == "t@1->2" and b.unit is None


def test_references_keep_index_member_and_states():
    (stmt,) = parse("find J_n[A]@2->3, e[C], rod.v@3\n").statements
    refs = [i.expr for i in stmt.items]
    assert (refs[0].name, refs[0].index, refs[0].at) == ("J_n", "A", ("2", "3"))
    assert (refs[1].name, refs[1].index, refs[1].at) == ("e", "C", ())
    assert (refs[2].name, refs[2].member, refs[2].at) == ("rod", "v", ("3",))


def test_transition_clauses_are_an_indented_block():
    text = ("impact 2 -> 3:\n"
            "    contact A with ground normal (0, 1): restitution 1, smooth\n"
            "    contact hit: B with C: restitution ?, friction 0.2\n")
    (t,) = parse(text).statements
    assert t.kind == "impact" and (t.before, t.after) == ("2", "3")
    c1, c2 = t.clauses
    assert c1.b is None and [p.kind for p in c1.props] == ["restitution", "smooth"]
    assert c2.label == "hit" and [p.kind for p in c2.props] == ["restitution?", "friction"]


def test_state_lines_continue_in_an_indented_block():
    text = 'state 2 "before": rod.angle = 30 deg\n    rod.vy < 0, rod at rest\n'
    (st,) = parse(text).statements
    assert st.label == "before"
    kinds = [type(i).__name__ for i in st.items]
    assert kinds == ["Given", "Given", "AtRest"]
    assert st.items[1].relation == "<"


def test_nodes_are_frozen_and_carry_one_based_spans():
    (stmt,) = parse("\n\nlet mu = 0.3\n").statements
    assert stmt.span.line == 3 and stmt.span.column == 1
    with pytest.raises(dataclasses.FrozenInstanceError):
        stmt.name = "x"


def test_comments_and_blank_lines_are_ignored():
    doc = parse("# header\n\nlet a = 1   # trailing\n\n# end\n")
    assert [type(s).__name__ for s in doc.statements] == ["Let"]


def test_missing_comma_between_contact_properties_points_at_the_word():
    with pytest.raises(ProblemError) as exc:
        parse("impact 1 -> 2:\n    contact A with ground normal (0, 1): restitution 1 1\n")
    d = exc.value.diagnostics[0]
    assert d.span.line == 2 and "syntax error" in d.message


def test_end_of_file_inside_a_block_points_past_the_last_character():
    with pytest.raises(ProblemError) as exc:
        parse("find rod.omega@3,")
    d = exc.value.diagnostics[0]
    assert d.span.line == 1 and d.span.column >= 1


def test_the_parser_is_built_once():
    assert S.parser() is S.parser()
