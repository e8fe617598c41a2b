"""The scene builder's passes take the statements of their kinds from one grouping
(scene._Kinds): the same statements, in file order, as filtering the document with
isinstance, for every kind and pair of kinds on every example."""
from __future__ import annotations

from pathlib import Path

from momentum_cli import syntax as S
from momentum_cli.scene import _Kinds
from momentum_cli.source import Source

ROOT = Path(__file__).resolve().parent.parent / "examples"
KINDS = [S.Problem, S.Gravity, S.Let, S.UnknownDecl, S.BodyDecl, S.SurfaceDecl, S.PointDecl,
         S.Joint, S.StateDecl, S.Transition, S.ConserveMomentum, S.ConserveAngular,
         S.RestitutionLaw, S.UserEquation, S.Find, S.Expect, S.SteadyDecl, S.BurnDecl,
         S.GainDecl, S.SimulateDecl]


def test_kinds_are_the_filtered_statements_in_file_order():
    paths = sorted(list(ROOT.glob("*.mom")) + list(ROOT.glob("simulate/*.mom")))
    for p in paths:
        st = S.parse(Source(p.name, p.read_text(encoding="utf-8"))).statements
        of = _Kinds(st)
        for k in KINDS:
            assert of(k) == [s for s in st if isinstance(s, k)], (p.name, k)
        for a, b in ((S.Let, S.UnknownDecl), (S.ConserveMomentum, S.ConserveAngular)):
            assert of(a, b) == [s for s in st if isinstance(s, (a, b))], p.name


def test_a_subclass_counts_as_its_base():
    class Base:
        pass

    class Sub(Base):
        pass

    st = (Base(), Sub(), 3, Base())
    of = _Kinds(st)
    assert of(Base) == [st[0], st[1], st[3]]
    assert of(Sub) == [st[1]] and of(int) == [3] and of(str) == []
