"""The search over Coulomb regimes (regime_search): one admissible combination is taken,
none or several are errors naming the contacts, too many contacts are refused."""
from types import SimpleNamespace as NS

import pytest

from momentum_cli import regime_search
from momentum_cli.diagnostics import ProblemError
from momentum_cli.elements.kinds import Regime


class Law:
    """A stand-in tangential law: the regimes in `ok` keep Coulomb's law, others break it."""

    def __init__(self, ok):
        self.ok = ok

    def violation(self, site, values):
        return None if site.regime.value in self.ok else f"not {site.regime.value}"


def _setup(oks):
    sites = [NS(key=f"1->2:k{i}", label=f"k{i}", transition="1->2", jn=f"J_n[k{i}]",
                span=None, slip_after=1, law=Law(ok)) for i, ok in enumerate(oks)]

    def solve_with(regimes):
        fr = [NS(**{**vars(s), "regime": Regime(regimes[s.key])}) for s in sites]
        values = {s.jn: 1.0 for s in sites}
        return NS(system=NS(friction=fr, unknowns={}), values=values, deferred=[]), {}

    start, _ = solve_with({s.key: "stick" for s in sites})
    return start, solve_with


def test_one_admissible_combination_is_kept():
    start, solve_with = _setup([{"slide+"}, {"stick"}, {"slide-"}])
    _sol, _res, regimes = regime_search.search(start.system, {}, solve_with)
    assert regimes == {"1->2:k0": "slide+", "1->2:k1": "stick", "1->2:k2": "slide-"}


def test_several_admissible_combinations_are_an_error_naming_them():
    start, solve_with = _setup([{"slide+"}, {"stick", "slide-"}])
    with pytest.raises(ProblemError) as err:
        regime_search.search(start.system, {}, solve_with)
    d = err.value.diagnostics[0]
    assert d.code == "ambiguous" and "2 solutions" in d.message
    assert "k0 slide+, k1 stick" in d.message and "k0 slide+, k1 slide-" in d.message


def test_no_admissible_combination_is_an_error_naming_the_contacts():
    start, solve_with = _setup([{"slide+"}, set()])
    with pytest.raises(ProblemError) as err:
        regime_search.search(start.system, {}, solve_with)
    d = err.value.diagnostics[0]
    assert d.code == "no-solution" and "k0 (1->2), k1 (1->2)" in d.message
    assert len(d.notes) == 9  # every combination, with why it fails
    assert "k0 slide+, k1 stick: k1: not stick" in d.notes


def test_too_many_contacts_are_refused_before_solving():
    start, _ = _setup([{"stick"}] * (regime_search.MAX_SITES + 1))

    def never(regimes):
        raise AssertionError("solved")

    with pytest.raises(ProblemError) as err:
        regime_search.search(start.system, {}, never)
    assert "too many" in err.value.diagnostics[0].message


def test_a_regime_that_does_not_solve_is_skipped_and_its_error_kept_when_none_does():
    """Stick can leave `restitution ?` undetermined where sliding decides it: the search
    takes the one combination that solves and keeps Coulomb's law; when none solves,
    the error of the regime tried on the way is raised, unchanged."""
    start, solve_with = _setup([{"stick", "slide+", "slide-"}])
    refused = ProblemError("under-determined: e[k0] is not determined", None)

    def only_slide(regimes):
        if regimes["1->2:k0"] != "slide+":
            raise ProblemError("under-determined: e[k0] is not determined", None)
        return solve_with(regimes)

    _sol, _res, regimes = regime_search.search(start.system, {}, only_slide, refused)
    assert regimes == {"1->2:k0": "slide+"}

    def never_solves(regimes):
        raise ProblemError("under-determined: e[k0] is not determined", None)

    with pytest.raises(ProblemError) as err:
        regime_search.search(start.system, {}, never_solves, refused)
    assert err.value is refused
