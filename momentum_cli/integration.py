"""Integration blocks: a phase with no closed form, integrated numerically (part of solve).

In: an `Integration` that compile describes (flows.py, accretion.py): its inputs, the
start state's values and parameters as expressions; its outputs, unknowns for the
phase's changes, end mass and duration; and `run`, the integration itself. compile adds
one equation per output (`emit`): analyse matches it to its output only and orders it
after every input; solve calls `solve_integration` when the block comes up, with the
inputs known by then. Out: the outputs' values, set in solve's `values`.
"""
from __future__ import annotations

import math

from .diagnostics import ProblemError
from .expr import Known, Var, add_all, evaluate, mul, variables
from .numbers import fmt_num
from .records import field, record
from .source import Span


@record(identity=True)
class Integration:
    label: str  # "gain drop 1 -> 2": names the phase in messages
    span: Span
    inputs: dict  # name in `run` -> expression of the start state or a parameter
    outputs: list  # unknown names `run` sets, in the order it returns them
    run: object  # callable({input: float}) -> list[float]; raises ProblemError
    what: list  # per output, what it is ("the change of vx over the gain")
    rtol: float = 1e-10  # the integrator's relative tolerance: the outputs' error scale
    equations: dict = field(default_factory=dict)  # equation index -> output position
    result: list | None = None  # computed once, when solve first reaches the block

    def depends_on(self) -> list[str]:
        """The unknowns among its inputs: the blocks that must be solved before it."""
        out: set[str] = set()
        for e in self.inputs.values():
            variables(e, out)
        return sorted(out)


def emit(c, integ: Integration, principle: str, group: str, registry: list) -> None:
    """Add one equation per output to compiler `c`: `out = integral(...)`, whose
    right-hand side only carries the structure (it depends on every input; its
    coefficients are NaN, never evaluated: solve_integration sets the value)."""
    deps = integ.depends_on()
    for n, (out, what) in enumerate(zip(integ.outputs, integ.what)):
        stand_in = add_all([mul(Known(f"d{out}/d{v}", math.nan), Var(v)) for v in deps] +
                           [Known(f"integral[{out}]", math.nan)])
        how = f"{what} ({principle})" if n == 0 else f"{what} (the same integration)"
        e = c.eq(Var(out), stand_in, how, group, integ.span)
        if e is None:  # the same equation twice: the compiler keeps the first
            continue
        text = f"{out} = integrated from " + (", ".join(deps) if deps else "the given start")
        e._texts = {False: text, True: text}
        integ.equations[e.index] = n
    registry.append(integ)


def matched_outputs(system) -> dict[int, str]:
    """{equation index: its output}: an integration sets its outputs from its inputs,
    never the reverse, so analyse matches each such equation to its output only."""
    out = {}
    for integ in system.integrations:
        for k, j in integ.equations.items():
            out[k] = integ.outputs[j]
    return out


def solve_integration(system, block, values: dict) -> Integration | None:
    """Solve `block` if it is an integration's output equation: the Integration (None
    for any other block)."""
    owner = {k: (integ, j) for integ in system.integrations
             for k, j in integ.equations.items()}
    mine = [k for k in block.equations if k in owner]
    if not mine:
        return None
    integ, j = owner[mine[0]]
    if len(block.equations) > 1:
        loop = sorted(set(block.unknowns) - set(integ.outputs))
        raise ProblemError(
            f"the {integ.label} is integrated forward from its start, but its start depends "
            f"on its end here (through {', '.join(loop)}): give the start state's values "
            "(an integration does not run backwards)", integ.span, code="under-determined")
    if integ.result is None:
        start = {}
        for name, e in integ.inputs.items():
            try:
                start[name] = evaluate(e, values)
            except KeyError as exc:  # an input analyse left undetermined
                raise ProblemError(f"the {integ.label} is integrated from its start, which "
                                   f"needs {exc.args[0]}: it is not determined", integ.span,
                                   code="under-determined") from None
        integ.result = [float(x) for x in integ.run(start)]
    value = integ.result[j]
    values[integ.outputs[j]] = value
    e = system.equations[mine[0]]
    e._texts[True] = f"{integ.outputs[j]} = {fmt_num(value, 6)}"
    return integ
