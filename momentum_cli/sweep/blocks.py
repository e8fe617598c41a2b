"""One compiled structure solved for many variants: linear blocks and Newton blocks.

In: a traced `System` (numbers that are functions of the parameters), its `Structure`
and the blocks the scalar solve needs. Out: `Plan`, whose `run(p, values, ok)` fills
the solved unknowns' arrays for every variant. Linear blocks are `np.linalg.solve` on
stacked (n, k, k) matrices; energy blocks are a vectorised damped Newton from the
scalar solve's starts with its root rules (hints; one root or a hint that separates
them). A variant whose block is near-singular, whose Newton fails or finds another
set of roots is marked with the reason and left to the scalar solve.
"""
from __future__ import annotations

import numpy as np

from ..expr import Add, Const, Fn, Known, Mul, NonLinear, Pow, Var, add_all, diff, mul
from .kernel import function


def affine_sym(e, block: set):
    """`expr.affine` as trees: (coefficient tree per block unknown, constant tree)."""
    t = type(e)
    if t is Const or t is Known:
        return {}, e
    if t is Var:
        return ({e.name: Const(1.0)}, Const(0.0)) if e.name in block else ({}, e)
    if t is Add:
        coef: dict = {}
        consts = []
        for x in e.terms:
            c, k = affine_sym(x, block)
            consts.append(k)
            for n, v in c.items():
                coef.setdefault(n, []).append(v)
        return {n: add_all(v) for n, v in coef.items()}, add_all(consts)
    if t is Mul:
        if any(type(f) in (Const, Known) and type(f.value) is float and f.value == 0.0
               for f in e.factors):
            return {}, Const(0.0)
        coef, const = {}, Const(1.0)
        for f in e.factors:
            c, k = affine_sym(f, block)
            if c and coef:
                raise NonLinear()
            if c:
                coef = {n: mul(const, v) for n, v in c.items()}
                const = mul(k, const)
            else:
                coef = {n: mul(v, k) for n, v in coef.items()}
                const = mul(const, k)
        return coef, const
    if t is Pow or t is Fn:
        inner = e.base if t is Pow else e.arg
        c, _ = affine_sym(inner, block)
        if c:
            raise NonLinear()
        return {}, e
    raise NonLinear()


class LinearBlock:
    def __init__(self, names, residuals, params, unknowns):
        self.names = names
        k = len(names)
        bset = set(names)
        col = {n: j for j, n in enumerate(names)}
        exprs, where = [], []
        for i, r in enumerate(residuals):
            coef, const = affine_sym(r, bset)
            for n, c in coef.items():
                exprs.append(c)
                where.append(("A", i, col[n]))
            exprs.append(const)
            where.append(("b", i, 0))
        self.k = k
        self.where = where
        self.fn = function(exprs, params, unknowns, "linear")
        self.idx = [unknowns.index(n) for n in names]

    def run(self, p, v, m, ok, why):
        k = self.k
        vals = self.fn(p, v)
        if k == 1:
            self._run1(vals, v, m, ok, why)
            return
        A = np.zeros((m, k, k))
        b = np.zeros((m, k))
        for (what, i, j), val in zip(self.where, vals):
            if what == "A":
                A[:, i, j] += val
            else:
                b[:, i] -= val
        bad = ~(np.abs(_equilibrated_det(A, k)) > 1e-12)  # also a nan or inf in A
        x = np.linalg.solve(A, b[:, :, None])[:, :, 0]
        fin = np.isfinite(x[:, 0])
        for j in range(1, k):
            fin &= np.isfinite(x[:, j])
        if not fin.all():
            _mark(ok, why, ~fin, "a value that is not finite in block " +
                  ", ".join(self.names[:3]))
        for j, gi in enumerate(self.idx):
            v[gi] = x[:, j]

    def _run1(self, vals, v, m, ok, why):
        a = np.zeros(m)
        b = np.zeros(m)
        for (what, _i, _j), val in zip(self.where, vals):
            if what == "A":
                a = a + val
            else:
                b = b - val
        a = np.broadcast_to(a, (m,))
        b = np.broadcast_to(b, (m,))
        bad = ~(np.isfinite(a) & np.isfinite(b) & (a != 0))
        if bad.any():
            _mark(ok, why, bad, "near-singular block " + self.names[0])
        with np.errstate(all="ignore"):
            v[self.idx[0]] = np.where(bad, np.nan, b / np.where(bad, 1.0, a))


def _equilibrated_det(A, k):
    """The determinant of A scaled as the scalar solve equilibrates it (rows, then
    columns, by their largest entries), from views (no scaled copy of A): a small one
    marks a near-singular block."""
    if k > 3:
        absA = np.abs(A)
        r = absA.max(axis=2)
        r[r == 0] = 1.0
        As = A / r[:, :, None]
        c = np.abs(As).max(axis=1)
        c[c == 0] = 1.0
        return np.linalg.det(As / c[:, None, :])
    a = [[np.abs(A[:, i, j]) for j in range(k)] for i in range(k)]
    scale = np.ones(A.shape[0])
    rows = []
    for i in range(k):
        r = a[i][0].copy()
        for j in range(1, k):
            np.maximum(r, a[i][j], out=r)
        r[r == 0] = 1.0
        rows.append(r)
        scale *= r
    for j in range(k):
        c = a[0][j] / rows[0]
        for i in range(1, k):
            np.maximum(c, a[i][j] / rows[i], out=c)
        c[c == 0] = 1.0
        scale *= c
    return _det(A, k) / scale


def _det(A, k):
    """Determinants of stacked k x k matrices (closed forms for 2 and 3)."""
    if k == 2:
        return A[:, 0, 0] * A[:, 1, 1] - A[:, 0, 1] * A[:, 1, 0]
    if k == 3:
        a = A
        return (a[:, 0, 0] * (a[:, 1, 1] * a[:, 2, 2] - a[:, 1, 2] * a[:, 2, 1])
                - a[:, 0, 1] * (a[:, 1, 0] * a[:, 2, 2] - a[:, 1, 2] * a[:, 2, 0])
                + a[:, 0, 2] * (a[:, 1, 0] * a[:, 2, 1] - a[:, 1, 1] * a[:, 2, 0]))
    return np.linalg.det(A)


def _cramer(J, b):
    """x with J x = b for (k, k, n) stacks, k = 2 or 3, by the adjugate; nan where
    J is singular (as the scalar Newton gives up there)."""
    if J.shape[0] == 2:
        det = J[0, 0] * J[1, 1] - J[0, 1] * J[1, 0]
        x0 = b[0] * J[1, 1] - J[0, 1] * b[1]
        x1 = J[0, 0] * b[1] - b[0] * J[1, 0]
        out = np.array([x0, x1])
    else:
        c00 = J[1, 1] * J[2, 2] - J[1, 2] * J[2, 1]
        c01 = J[1, 2] * J[2, 0] - J[1, 0] * J[2, 2]
        c02 = J[1, 0] * J[2, 1] - J[1, 1] * J[2, 0]
        det = J[0, 0] * c00 + J[0, 1] * c01 + J[0, 2] * c02
        x0 = b[0] * c00 + J[0, 1] * (J[1, 2] * b[2] - b[1] * J[2, 2]) + \
            J[0, 2] * (b[1] * J[2, 1] - J[1, 1] * b[2])
        x1 = J[0, 0] * (b[1] * J[2, 2] - J[1, 2] * b[2]) + b[0] * c01 + \
            J[0, 2] * (J[1, 0] * b[2] - b[1] * J[2, 0])
        x2 = J[0, 0] * (J[1, 1] * b[2] - b[1] * J[2, 1]) + \
            J[0, 1] * (b[1] * J[2, 0] - J[1, 0] * b[2]) + b[0] * c02
        out = np.array([x0, x1, x2])
    with np.errstate(all="ignore"):
        return np.where(det != 0, out / det, np.nan)


def _take(arrays, sel):
    """The selected variants of each input (scalars and absent ones as they are)."""
    return [a[..., sel] if a is not None and np.ndim(a) else a for a in arrays]


def _mark(ok, why, mask, reason):
    new = mask & ok
    why[new] = reason
    ok &= ~mask


SPREAD = (0.7, -0.7, 2.0, -2.0, 0.3, -1.3, 1.1, -0.4)


class NewtonBlock:
    """The scalar `_newton`: every root from the same starts, then the hints decide."""

    def __init__(self, system, names, residuals, params, unknowns):
        from ..solve import _given_states

        self.names = names
        self.k = len(names)
        self.idx = [unknowns.index(n) for n in names]
        self.F = function(residuals, params, unknowns, "F")
        self.J = function([diff(f, n) for f in residuals for n in names], params, unknowns,
                          "J")
        givens = list(_given_states(residuals))
        self.S = function([Fn("abs", g) for g in givens], params, unknowns, "S") \
            if givens else None
        self.base = []
        self.hints = []
        for n in names:
            u = system.unknowns[n]
            checked = u.kind not in ("impulse", "duration")
            self.hints.append([(rel, float(b)) for rel, b, _ in u.hints] if checked else [])
            if u.kind == "restitution" and not u.hints:
                self.base.append([0.5, 0.9, 0.2])
                continue
            lo = max((float(b) for rel, b, _ in u.hints if rel == ">"), default=None)
            hi = min((float(b) for rel, b, _ in u.hints if rel == "<"), default=None)
            if lo is not None and hi is not None:
                self.base.append([(lo + hi) / 2, lo + (hi - lo) * 0.25, lo + (hi - lo) * 0.75])
            elif lo is not None:
                w = max(abs(lo), 1.0)
                self.base.append([lo + 0.5 * w, lo + 2 * w, lo + 0.05 * w])
            elif hi is not None:
                w = max(abs(hi), 1.0)
                self.base.append([hi - 0.5 * w, hi - 2 * w, hi - 0.05 * w])
            else:
                self.base.append(None)
        self.has_hint = any(h for h in self.hints)

    def _starts(self, p, v, m):
        S = np.ones(m)
        if self.S is not None:
            for s in self.S(p, v):
                S = np.maximum(S, s)
        starts = [[np.full(m, b[min(k, len(b) - 1)]) if b else np.full(m, SPREAD[k])
                   for b in self.base] for k in range(3)]
        extra = (S > 1.0) | (self.k > 1)
        if extra.any():
            for k in range(len(SPREAD)):
                starts.append([np.full(m, b[0]) if b else S * SPREAD[(k + 3 * i) % len(SPREAD)]
                               for i, b in enumerate(self.base)])
        return starts, extra

    def run(self, p, v, m, ok, why):
        with np.errstate(all="ignore"):
            starts, extra = self._starts(p, v, m)
            found = []
            for s, x0 in enumerate(starts):
                x, conv = self._newton(p, v, m, np.array(x0))
                if s >= 3:
                    conv &= extra
                found.append((x, conv))
        self._choose(found, m, ok, why, v)

    def _choose(self, found, m, ok, why, v):
        """The scalar rules on the roots found: one hinted root, and no ambiguity."""
        k = self.k
        # distinct roots (the scalar `_close`), in the order of the starts
        n_roots = np.zeros(m, int)
        n_hinted = np.zeros(m, int)
        first = np.full((k, m), np.nan)
        for s, (x, conv) in enumerate(found):
            new = conv.copy()
            for t in range(s):
                y, cy = found[t]
                same = cy & np.all(np.abs(x - y) <= 1e-7 * np.maximum(np.abs(x), np.abs(y))
                                   + 1e-9, axis=0)
                new &= ~same
            hinted = conv & self._satisfies(x)
            n_roots += new
            newh = new & hinted
            n_hinted += newh
            take = newh & np.isnan(first[0])
            first[:, take] = x[:, take]
        good = (n_hinted == 1) & ~((n_roots > 1) & (not self.has_hint))
        _mark(ok, why, ~good, f"roots of {', '.join(self.names[:3])} differ")
        for j, gi in enumerate(self.idx):
            v[gi] = np.where(good, first[j], np.nan)

    def _satisfies(self, x):
        out = np.ones(x.shape[1], bool)
        for j, hs in enumerate(self.hints):
            for rel, bound in hs:
                out &= (x[j] > bound) if rel == ">" else (x[j] < bound)
        return out

    def _eval(self, p, v, x):
        for j, gi in enumerate(self.idx):
            v[gi] = x[j]
        return np.array(np.broadcast_arrays(*self.F(p, v), x[0]))[:-1]

    def _newton(self, p, v, m, x0):
        """`solve._newton_from` for every variant at once: (x, converged). Each step
        evaluates only the variants still iterating (and, in the line search, only
        those still halving their step)."""
        k = self.k
        X = np.array(x0, dtype=float)
        conv = np.zeros(m, bool)
        idx = np.arange(m)
        ps, vs = p, list(v)
        x = X.copy()
        r = self._eval(ps, vs, x)

        def keep(mask):
            nonlocal idx, x, r, ps, vs
            idx, x, r = idx[mask], x[:, mask], r[:, mask]
            ps, vs = _take(ps, mask), _take(vs, mask)

        def finish(mask):
            conv[idx[mask]] = True
            X[:, idx[mask]] = x[:, mask]

        keep(np.isfinite(r).all(axis=0))
        for _ in range(100):
            if not idx.size:
                break
            scale = np.maximum(1.0, np.abs(x).max(axis=0))
            zero = np.abs(r).max(axis=0) == 0.0
            if zero.any():
                finish(zero)
                keep(~zero)
                scale = scale[~zero]
                if not idx.size:
                    break
            for j, gi in enumerate(self.idx):  # the Jacobian at x
                vs[gi] = x[j]
            n = idx.size
            Jv = np.array(np.broadcast_arrays(*self.J(ps, vs), x[0]))[:-1].reshape(k, k, n)
            if k == 1:
                dx = -r / Jv[0]
            elif k <= 3:
                dx = _cramer(Jv, -r)  # a Newton step: its round-off corrects itself
            else:
                Jm = np.moveaxis(Jv, 2, 0).copy()
                sing = ~np.isfinite(Jm).all(axis=(1, 2)) | (np.abs(np.linalg.det(Jm)) == 0)
                Jm[sing] = np.eye(k)
                dx = np.linalg.solve(Jm, -r.T[:, :, None])[:, :, 0].T
                dx[:, sing] = np.nan
            okdx = np.isfinite(dx).all(axis=0)
            if not okdx.all():
                keep(okdx)
                dx, scale = dx[:, okdx], scale[okdx]
                n = idx.size
            norm0 = np.sqrt((r * r).sum(axis=0))
            step = np.ones(n)
            acc = np.zeros(n, bool)
            xn, rn = x.copy(), r.copy()
            while True:
                t = np.nonzero(~acc & (step > 1e-6))[0]
                if not t.size:
                    break
                xt = x[:, t] + step[t] * dx[:, t]
                rt = self._eval(_take(ps, t), _take(vs, t), xt)
                nt = np.sqrt((rt * rt).sum(axis=0))
                better = np.isfinite(rt).all(axis=0) & (nt < norm0[t] * (1 - 1e-4 * step[t]))
                tb = t[better]
                xn[:, tb] = xt[:, better]
                rn[:, tb] = rt[:, better]
                acc[tb] = True
                step[t[~better]] /= 2
            stuck = ~acc
            if stuck.any():
                finish(stuck & (norm0 <= 1e-10 * scale))
                keep(acc)
                xn, rn, step, dx, scale = xn[:, acc], rn[:, acc], step[acc], dx[:, acc], \
                    scale[acc]
            x, r = xn, rn
            done = np.abs(step * dx).max(axis=0) <= 1e-14 * scale
            if done.any():
                finish(done)
                keep(~done)
        if idx.size:
            finish(np.abs(r).max(axis=0) < 1e-9 * np.maximum(1.0, np.abs(x).max(axis=0)))
        return X, conv


class NotQuadratic(Exception):
    pass


def quadratic_sym(e, x: str):
    """(c0, c1, c2) trees with e = c2 x^2 + c1 x + c0, or NotQuadratic."""
    from ..expr import variables

    t = type(e)
    if t is Var:
        return (Const(0.0), Const(1.0), Const(0.0)) if e.name == x else (e, Const(0.0),
                                                                          Const(0.0))
    if t is Const or t is Known:
        return (e, Const(0.0), Const(0.0))
    if x not in variables(e):
        return (e, Const(0.0), Const(0.0))
    if t is Add:
        parts = [quadratic_sym(a, x) for a in e.terms]
        return tuple(add_all([q[d] for q in parts]) for d in range(3))
    if t is Mul:
        if any(type(f) in (Const, Known) and type(f.value) is float and f.value == 0.0
               for f in e.factors):
            return (Const(0.0), Const(0.0), Const(0.0))
        acc = (Const(1.0), Const(0.0), Const(0.0))
        for f in e.factors:
            q = quadratic_sym(f, x)
            out = [[], [], []]
            for i in range(3):
                for j in range(3):
                    if _zero(acc[i]) or _zero(q[j]):
                        continue
                    if i + j > 2:
                        raise NotQuadratic()
                    out[i + j].append(mul(acc[i], q[j]))
            acc = tuple(add_all(o) if o else Const(0.0) for o in out)
        return acc
    if t is Pow and e.exp == 2.0:
        q = quadratic_sym(e.base, x)
        if not _zero(q[2]):
            raise NotQuadratic()
        return (mul(q[0], q[0]), mul(Const(2.0), mul(q[0], q[1])), mul(q[1], q[1]))
    raise NotQuadratic()


def _zero(e) -> bool:
    return type(e) is Const and type(e.value) is float and e.value == 0.0


class QuadraticBlock(NewtonBlock):
    """One unknown in a quadratic: its real roots in closed form (every root the
    scalar Newton can find), then the same root rules."""

    def __init__(self, system, names, residuals, params, unknowns, coefs):
        super().__init__(system, names, residuals, params, unknowns)
        self.coef = function(list(coefs), params, unknowns, "quadratic")

    def run(self, p, v, m, ok, why):
        with np.errstate(all="ignore"):
            c0, c1, c2 = (np.broadcast_to(np.asarray(c, float), (m,)) for c in self.coef(p, v))
            disc = c1 * c1 - 4.0 * c2 * c0
            real = disc >= 0
            q = -0.5 * (c1 + np.copysign(np.sqrt(np.where(real, disc, 0.0)), c1))
            lin = c2 == 0
            r1 = np.where(lin, -c0 / c1, q / c2)
            r2 = np.where(lin, np.nan, c0 / q)
            r1 = np.where(real, r1, np.nan)
            r2 = np.where(real, r2, np.nan)
            # a root where q = 0 (c0 = 0): both roots from the product form
            r2 = np.where(real & ~lin & (q == 0), 0.0, r2)
        found = [(r1[None, :], np.isfinite(r1)), (r2[None, :], np.isfinite(r2))]
        self._choose(found, m, ok, why, v)
        # the chosen root polished by a Newton step on the residual as solve evaluates it
        with np.errstate(all="ignore"):
            v[self.idx[0]] = self._polish(p, v, v[self.idx[0]])

    def _polish(self, p, v, x):
        """Newton steps on the residual as the scalar solve evaluates it, kept only
        where they reduce it (the closed form rounds differently)."""
        r = self._eval(p, v, x[None, :])[0]
        for _ in range(1):
            d = np.broadcast_to(np.asarray(self.J(p, v)[0], float), x.shape)
            xn = x - np.where(d != 0, r / d, 0.0)
            rn = self._eval(p, v, xn[None, :])[0]
            better = np.isfinite(rn) & (np.abs(rn) < np.abs(r))
            x = np.where(better, xn, x)
            r = np.where(better, rn, r)
        return x


def block_for(system, structure, block, params, unknowns):
    """The batched solver of one block, or None if it is of a kind the batch leaves to
    the scalar solve."""
    from .trace import Traced

    residuals = [system.equations[k].residual for k in block.equations]
    if len(residuals) != len(block.unknowns):
        return None
    if any(isinstance(b, Traced) for n in block.unknowns
           for _r, b, _s in system.unknowns[n].hints):
        return None  # a hint whose bound is a parameter: the scalar solve decides
    try:
        return LinearBlock(block.unknowns, residuals, params, unknowns)
    except NonLinear:
        pass
    if len(block.unknowns) == 1:
        try:
            coefs = quadratic_sym(residuals[0], block.unknowns[0])
            return QuadraticBlock(system, block.unknowns, residuals, params, unknowns, coefs)
        except NotQuadratic:
            pass
    return NewtonBlock(system, block.unknowns, residuals, params, unknowns)


__all__ = ["block_for", "affine_sym", "LinearBlock", "NewtonBlock", "QuadraticBlock"]
