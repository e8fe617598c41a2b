"""Poisson's and Stronge's restitution at an impact contact: compile rows and solve pass.

Stage: compile (the contact's rows) and solve (the impulse path between two passes).
In: a contact written `restitution E poisson` or `restitution E energetic`; the
solved first pass. Out: the contact impulse (P_t, P_n) its law gives, stamped as rows
J_n = P_n, J_t = P_t in the second pass; checks naming the phases; and, for Newton's
law with friction, a warning where an impact gains kinetic energy.

The contact's W and v0 come from the impact's own linear equations (impulse-momentum
of the bodies it moves, the other contacts' and the joints' rows, the joints'
velocity constraints after the impact), with the contact impulse as a parameter:
v(P) = v0 + W P is the relative velocity after an impact that applied P at the
contact (the laws module integrates Coulomb friction along the path in P_n).
"""
from __future__ import annotations

import math

from .diagnostics import ProblemError
from .expr import ZERO, Known, Var, affine, evaluate, mul, neg
from .numbers import fmt_num
from .records import record
from .source import Span


@record
class PathLawSite:
    """A contact resolved by the impulse path (Poisson or energetic)."""

    key: str  # site: "<transition>:<label>"
    label: str
    transition: str
    before: str
    after: str
    law: str
    e: float
    mu: float | None  # None: smooth; inf: rough
    jn: str
    jt: str | None
    v_after: tuple  # (v_t, v_n) expressions after the impact
    rows: list[int]  # the contact's own law rows
    post: list[str]  # the post-impact velocity unknowns of the bodies the impact moves
    group: str
    span: Span


def stamp_path_law(cmp, t, c, Jn: Var, Jt, v_before: tuple, v_after: tuple, group: str) -> None:
    """The contact's rows: in the first pass Newton's law with the slip stopped (only the
    state before the impact is used from it); then J_n = P_n, J_t = P_t from the path."""
    site = f"{t.key}:{c.label}"
    for other in cmp.path_laws:
        if other.transition == t.key:
            raise ProblemError(f"impact {t.before} -> {t.after} has two contacts with a "
                               f"Poisson or energetic law ({other.label} and {c.label}); the "
                               "impulse path is solved for one contact per impact: give the "
                               "others Newton's law", c.span, code="name")
    first = len(cmp.equations)
    P = cmp.impulses.get(site)
    vt1, vn1 = v_before
    vt2, vn2 = v_after
    if P is None:
        e = Known(f"e[{c.label}]", c.restitution)
        cmp.eq(vn2, mul(neg(e), vn1), f"restitution at {c.label} (Newton, a first pass for the "
               f"{c.law} law)", group, c.span)
        if c.mode != "smooth":
            cmp.eq(vt2, ZERO, f"no slip at {c.label} (a first pass for the {c.law} law)", group,
                   c.span)
    else:
        what = "Poisson: P_n = (1 + e) P_c" if c.law == "poisson" else \
            "energetic: restitution work = e^2 x compression work"
        cmp.eq(Jn, Known(f"P_n[{c.label}]", P[1]),
               f"{c.law} restitution at {c.label} ({what}): J_n from the impulse path", group,
               c.span)
        if Jt is not ZERO:
            cmp.eq(Jt, Known(f"P_t[{c.label}]", P[0]),
                   f"{c.law} restitution at {c.label}: J_t from Coulomb friction along the "
                   "impulse path", group, c.span)
    post = []
    for b in sorted(cmp._busy[t.key]):
        for q in ("vx", "vy", "omega"):
            v = cmp.sv(b, q, t.after)
            if isinstance(v, Var):
                post.append(v.name)
    mu = None if c.mode == "smooth" else math.inf if c.mode == "rough" else c.mu
    cmp.path_laws.append(PathLawSite(
        site, c.label, t.key, t.before, t.after, c.law, c.restitution, mu, Jn.name,
        Jt.name if Jt is not ZERO else None, (vt2, vn2), list(range(first, len(cmp.equations))),
        post, group, c.span))


def _impact_rows(system, site: PathLawSite):
    """The impact's unknowns U (velocities after, its impulses) and its rows that hold
    for any contact impulse (all but the contact's own law rows)."""
    from .expr import variables

    U = list(site.post)
    U += [n for n, u in system.unknowns.items()
          if u.kind in ("impulse", "angular-impulse") and
          getattr(n, "transition", None) == site.transition]
    Uset = set(U)
    own = set(site.rows)
    eqs = [e for e in system.equations if e.group == site.group and e.kind == "auto" and
           e.index not in own]
    eqs += [e for e in system.equations if e.group == f"state {site.after}" and
            e.kind == "auto" and variables(e.residual) & Uset]
    return U, eqs


def _site_needs(system, site: PathLawSite) -> tuple[set[str], set[str]]:
    """What one site's impulse path reads from before its impact, and what it decides."""
    from .expr import variables

    U, eqs = _impact_rows(system, site)
    need: set[str] = set()
    for e in eqs:
        need |= variables(e.residual)
    need |= variables(site.v_after[0]) | variables(site.v_after[1])
    return {n for n in need if n in system.unknowns} - set(U), set(U)


def next_site(system, pending: list) -> tuple[PathLawSite, set[str], set[str]]:
    """The next contact to resolve, with what it needs and what the pending ones decide:
    the first whose state before does not wait for another pending impact (impacts in
    sequence resolve in order; a contact that needs its own far side is refused later)."""
    needs = [_site_needs(system, s) for s in pending]
    after = set().union(*(U for _, U in needs))
    for site, (need, U) in zip(pending, needs):
        if not need & (after - U):
            return site, need, after
    return pending[0], needs[0][0], after


def not_before(system, names: list[str], what: str) -> ProblemError:
    """The state before a Poisson or energetic impact must be known without it."""
    site = next((s for s in system.path_laws if set(names) & _site_needs(system, s)[0]),
                system.path_laws[0])
    shown = ", ".join(names[:6]) + ("..." if len(names) > 6 else "")
    verb = what if len(names) == 1 else what.replace("is ", "are ", 1)
    return ProblemError(f"{site.law} restitution at {site.label}: {shown} (before the impact) "
                        f"{verb}; the impulse path starts from a known state before the "
                        "impact (or use Newton's law)", site.span, code="under-determined")


def resolve_site(system, values, site: PathLawSite, precision: str = "float"):
    """The contact's impulse by its law (a laws.ImpactResult), from the state before."""
    from .laws import resolve

    W, v0 = contact_map(system, values, site, precision)
    try:
        return resolve(W, v0, site.e, site.mu, site.law)
    except ValueError as exc:
        raise ProblemError(f"{site.law} restitution at {site.label}: {exc} (v_n = "
                           f"{fmt_num(v0[1], 4)} m/s before the impact)", site.span,
                           code="no-solution") from None


def contact_map(system, values, site: PathLawSite, precision: str = "float"):
    """W (2x2, in (t, n)) and v0 of v(P) = v0 + W P, from the impact's linear rows."""
    from .expr import NonLinear
    from .linalg import SingularError, solve

    U, eqs = _impact_rows(system, site)
    col = {n: k for k, n in enumerate(U)}
    Uset = set(U)
    rows, const = [], []
    try:
        for e in eqs:
            coef, k = affine(e.residual, Uset, values)
            rows.append({col[n]: v for n, v in coef.items() if v != 0.0})
            const.append(k)
        lin_t, _ = affine(site.v_after[0], Uset, values)
        lin_n, _ = affine(site.v_after[1], Uset, values)
    except (KeyError, NonLinear, ValueError, ZeroDivisionError) as exc:
        raise ProblemError(f"{site.law} restitution at {site.label}: the impact's equations "
                           f"are not linear in its unknowns given the state before it ({exc})",
                           site.span, code="no-solution") from None
    params = [site.jt, site.jn] if site.jt else [site.jn]
    n_rows = len(rows) + len(params)
    if n_rows != len(U):
        raise ProblemError(f"{site.law} restitution at {site.label}: the impact's velocities "
                           "after it must follow from momentum, joints and this contact's "
                           f"impulse alone ({n_rows} equations for {len(U)} unknowns); leave "
                           f"the velocities of state {site.after} unknown, or use Newton's law",
                           site.span, code="name")
    for p in params:
        rows.append({col[p]: 1.0})

    def run(rhs_params, homogeneous):
        rhs = [0.0 if homogeneous else -k for k in const] + rhs_params
        try:
            x, _ = solve(rows, rhs, len(U), precision)
        except SingularError:
            raise ProblemError(f"{site.law} restitution at {site.label}: the impact's "
                               "equations do not determine its velocities for a given "
                               "contact impulse", site.span, code="singular") from None
        return x

    def lin(coef, x):
        return sum(v * x[col[n]] for n, v in coef.items())

    x0 = run([0.0] * len(params), False)
    env = dict(values)
    env.update(zip(U, x0))
    v0 = (evaluate(site.v_after[0], env), evaluate(site.v_after[1], env))
    xn = run([0.0, 1.0] if site.jt else [1.0], True)
    wtn, wnn = lin(lin_t, xn), lin(lin_n, xn)
    if site.jt:
        xt = run([1.0, 0.0], True)
        wtt, wnt = lin(lin_t, xt), lin(lin_n, xt)
        if abs(wtn - wnt) > 1e-8 * max(abs(wtt), abs(wnn)):
            raise ProblemError(f"{site.law} restitution at {site.label}: the contact's inverse "
                               f"mass matrix is not symmetric (W_tn = {fmt_num(wtn, 4)}, W_nt = "
                               f"{fmt_num(wnt, 4)}); another contact of the impact does work: "
                               "give it alone, or use Newton's law", site.span, code="name")
        wtn = wnt = 0.5 * (wtn + wnt)
    else:
        # smooth: P_t = 0 and W_tt never enters; any value keeping W definite will do
        wtt = wnn + wtn * wtn / wnn
        wnt = wtn
    return ((wtt, wtn), (wnt, wnn)), v0


def path_law_checks(system, results: dict) -> list[tuple[str, str, str]]:
    """(name, status, detail) per path-law contact: its law, phases and compression end."""
    out = []
    for site in system.path_laws:
        r = results.get(site.key)
        if r is None:
            continue
        spans: list[list] = []  # [regime, P_n from, P_n to], merged across compression's end
        for p in r.phases:
            if spans and spans[-1][0] == p.regime:
                spans[-1][2] = p.pn[1]
            else:
                spans.append([p.regime, p.pn[0], p.pn[1]])
        phases = ", ".join("stop (slip stopped at once)" if reg == "stop" else
                           f"{reg} {fmt_num(a, 4)} -> {fmt_num(b, 4)}" for reg, a, b in spans)
        law = "Poisson: P_n = (1 + e) P_c" if r.law == "poisson" else \
            "energetic: restitution work = e^2 x |compression work|"
        detail = (f"{law}; phases in P_n (N*s): {phases}; compression ends at P_c = "
                  f"{fmt_num(r.compression_end, 4)} N*s (normal work "
                  f"{fmt_num(r.work_compression, 4)} J), restitution to "
                  f"{fmt_num(r.impulse[1], 4)} N*s (normal work {fmt_num(r.work_restitution, 4)} "
                  "J)")
        if r.locked:
            detail += ("; the contact locks: it sticks and, with one degree of freedom at the "
                       "contact, restitution cannot separate it")
        status = "warning" if r.gains_energy else "ok"
        out.append((f"impact law at {site.label} ({site.before} -> {site.after})", status,
                    detail))
    return out


def energy_gain_checks(system, values) -> list[tuple[str, str, str]]:
    """Newton's law with friction can create energy (Kane and Levinson's rod and double
    pendulum): where an impact's kinetic energy rises, name its Newton friction contacts."""
    from .expr import variables

    out = []
    specs = {t.key: t for t in system.scene.transitions}
    for info in system.transitions:
        if info.kind != "impact" or info.energy is None:
            continue
        spec = specs.get(info.key)
        newton = [c.label for c in (spec.contacts if spec else ())
                  if c.law == "newton" and c.mode in ("friction", "rough")
                  and c.separation is None]
        if not newton:  # first: the energies of a large impact are long sums
            continue
        T1, T2 = info.energy
        if not (variables(T1) | variables(T2)) <= values.keys():
            continue
        a, b = evaluate(T1, values), evaluate(T2, values)
        if not b - a > 1e-9 * max(a, b, 1e-300):
            continue
        out.append((
            f"impact law at {', '.join(newton)} ({info.before} -> {info.after})", "warning",
            f"Newton's law with friction gains {fmt_num(b - a, 4)} J of kinetic energy: the "
            "friction impulse it finds does positive work (it acts along the slip); "
            "`restitution E energetic` "
            "(Stronge's law, friction along the impulse path) never gains energy"))
    return out
