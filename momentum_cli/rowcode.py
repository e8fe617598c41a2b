"""Solve stage: an equation's walks compiled once per shape of tree, not walked per node.

In: a residual tree of sums, products and leaves (the rows of large scenes). Out: its
shape (the tree's layout, which leaves are zero, which unknowns repeat) with its numbers
and names, and Python functions, compiled once per shape (once met COMPILE_AFTER times), that
perform the very float operations of `expr._affine_float`, `bounds.derivatives_and_size`
and `expr.evaluate` in the same order (bit-identical results, the same dict orders, the
same exceptions; anything else, and every failure, goes back to those walks). A 10^4-ball
chain has a handful of shapes; a scene's energy is walked at the top, its terms compiled.
"""
from __future__ import annotations

import math

from . import expr as _expr
from .expr import Add, Const, Known, Mul, NonLinear, Var
from .expr import evaluate as walk_value
from .shape_codes import compiled_after

ENABLED = True  # tests turn it off: every caller then takes the walks
MAX_TOKENS = 400  # larger trees (a scene's total energy) keep the walks
LIMIT = 512  # compiled shapes kept

_GS: dict = {}  # compiled walks by shape: derivatives and size, affine rows, values
_AFF: dict = {}
_VAL: dict = {}
_KEYS: dict = {}  # each shape's key, once
_SEEN: dict = {}  # (cache, key) -> times met before it was compiled
# a shape is compiled once met this often: compile() costs many walks of a small tree, so
# a small file's shapes (met a few times each) are walked (newtons_cradle_sequence alone:
# 291 -> 264 M instructions), a batch of variants is as fast either way, and a big
# scene's handful of shapes, met 10^4 times, are compiled after 64 walks of each
COMPILE_AFTER = 64
_SHAPES: dict = {}  # tree -> shape within one solve (`remembered`)
_NONE = object()
_ON = [0]  # how many `remembered` are open
# set within the `remembered` of a solve of fewer equations than COMPILE_AFTER: no tree
# is shaped, every one walked. Such a solve meets no shape often enough to compile it,
# so a tree's shape (one more walk) and the look-ups of its compiled walks would only
# add to the walk that runs anyway (the bench's 1,000 small files: ~0.08 s less CPU)
_PLAIN = [False]
PLAIN_SMALL = True  # tests turn it off: a small solve's trees shaped as a large one's


class _No(Exception):
    pass


def shape(e):
    """(key, numbers, names) of a tree of Const, Known, Var, Add and Mul with float numbers,
    in pre-order; a product with a zero number factor is one token (every walk stops
    there); None for anything else or a tree too large. A sum or product first tries
    the readers of the shapes met most at its root (`_reader`): a big scene's rows come
    in a few shapes, and reading a known shape's leaves costs half of walking it (a
    solve's first GUESS_AFTER trees are walked)."""
    t = type(e)
    if GUESS and (t is Add or t is Mul) and len(_SHAPES) >= GUESS_AFTER:
        last = _LAST[0]
        f = _NEXT.get(last)  # the rows of stamped kinds come in a period: the shape
        if f is not None:  # that followed the last two last time, first
            got = f(e)
            if got is not None:
                _LAST[0] = (last[1], id(got[0]))
                return got
        sig = len(e.terms) if t is Add else -1 - len(e.factors)
        readers = _READERS.get(sig)
        if readers is not None:
            for f in readers:
                got = f(e)
                if got is not None:
                    _follows(last, got[0], f)
                    return got
        sh = walk_shape(e)
        if sh is not None:
            f = _learn(sig, sh[0])
            if f is not None:
                _follows(last, sh[0], f)
            else:
                _LAST[0] = (last[1], id(sh[0]))
        return sh
    return walk_shape(e)


def _follows(last, key, f) -> None:
    if len(_NEXT) >= LIMIT:
        _NEXT.clear()
    _NEXT[last] = f
    _LAST[0] = (last[1], id(key))


def walk_shape(e):
    """`shape(e)` by walking the tree (the reference the readers are tested against)."""
    toks: list = []
    nums: list = []
    names: list = []
    first: dict = {}
    try:
        _walk(e, toks, nums, names, first)
    except (_No, RecursionError):
        return None
    if len(toks) > MAX_TOKENS:
        return None
    key = tuple(toks)
    key = _KEYS.setdefault(key, key)  # one tuple per shape: a remembered row is small
    if len(_KEYS) > 4 * LIMIT:
        _KEYS.clear()
    # tuples: a remembered shape is kept per equation for the whole solve, and a tuple
    # is half a short list's size (the compiled walks only index them)
    return key, tuple(nums), tuple(names)


GUESS = True  # tests turn it off: every shape walked
# readers once a solve has shaped this many trees (`remembered`): a small file's few
# rows are walked as before (learning their shapes would cost more than it saves)
GUESS_AFTER = 256
_READERS: dict = {}  # root signature -> readers of the shapes met there, latest first
_READER_OF: dict = {}  # key -> its reader (made once the key was met COMPILE_AFTER times)
_FEW = 4  # readers tried per root signature before walking
# the shapes that followed the last two: (id of a key, id of a key) -> the reader of the
# shape that came next last time (a guess: any reader on any tree is right or None)
_NEXT: dict = {}
_LAST = [(0, 0)]  # the ids of the last two shapes' keys


def _learn(sig, key):
    """Count a walked shape; once met often enough, its reader (returned) goes first at
    its root."""
    f = _READER_OF.get(key)
    if f is None:
        f = compiled_after(_READER_OF, _SEEN, key, _reader, COMPILE_AFTER, LIMIT,
                           seen_key=("reader", key), forget=_forget)
        if f is None:
            return None
    readers = _READERS.get(sig)
    if readers is None:
        if len(_READERS) >= LIMIT:
            _READERS.clear()
        readers = _READERS[sig] = []
    if f not in readers:  # else walked although its reader is there: it failed
        readers.insert(0, f)
        del readers[_FEW:]
    return f


def _forget() -> None:
    _READERS.clear()
    _NEXT.clear()


def _is_zero_product(m) -> bool:
    """Whether `_walk` makes the product `m` one zero token: every number factor a float,
    one of them zero."""
    zero = False
    for f in m.factors:
        tf = type(f)
        if tf is Const or tf is Known:
            v = f.value
            if type(v) is not float:
                return False
            if v == 0.0:
                zero = True
    return zero


def _reader(key):
    """f(e) -> `walk_shape(e)` where e has the shape `key`, None where it has not (then
    the walk decides). Generated: the leaves read by position, every fact the walk
    checks checked (node types, float numbers, no zero number in a product, which
    unknowns are the same), the key itself captured."""
    root, _ = _parse(key)
    lines: list[str] = []
    boxes: list[str] = []  # each sum or product and its type
    nums: list[str] = []  # each number's node
    values: list[str] = []
    nonzero: list[str] = []
    zeros: list[str] = []
    var_nodes: list[str] = []
    names: list[str] = []
    firsts: list[str] = []
    k = [0]

    def node(nd, at: str, in_mul: bool) -> None:
        if nd.kind == "v":
            nm = f"n{nd.i}"
            lines.append(f"        {nm} = {at}.name")
            var_nodes.append(at)
            names.append(nm)
            if nd.same == nd.i:
                firsts.append(nm)
            else:
                lines.append(f"        if {nm} != n{nd.same}: return None")
        elif nd.kind == "c":
            c = f"c{nd.i}"
            lines.append(f"        {c} = {at}.value")
            nums.append(at)
            values.append(c)
            if in_mul:
                nonzero.append(c)
        elif nd.kind == "zero":
            zeros.append(at)
        else:
            cls, attr = ("Add", "terms") if nd.kind == "add" else ("Mul", "factors")
            boxes.append((at, cls))
            kids = []
            for _ in nd.kids:
                k[0] += 1
                kids.append(f"x{k[0]}")
            lines.append(f"        {''.join(x + ', ' for x in kids)}= {at}.{attr}")
            for kid, x in zip(nd.kids, kids):
                node(kid, x, nd.kind == "mul")

    node(root, "e", False)
    # the types expected, as constants (`type` a default argument: no global lookups)
    tail = [f"    if ({''.join(f'type({b}), ' for b, _ in boxes)}) != BOXES: return None"]
    if var_nodes:
        tail.append(f"    if ({''.join(f'type({x}), ' for x in var_nodes)}) != VARS: return None")
    if nums:
        tail.append(f"    if not {{{''.join(f'type({x}), ' for x in nums)}}} <= NUMBER: return None")
        tail.append(f"    if ({''.join(f'type({c}), ' for c in values)}) != FLOATS: return None")
    if nonzero:
        tail.append(f"    if 0.0 in ({''.join(c + ', ' for c in nonzero)}): return None")
    for z in zeros:
        tail.append(f"    if type({z}) is not Mul or not zero_product({z}): return None")
    if len(firsts) > 1:
        tail.append(f"    if len({{{', '.join(firsts)}}}) != {len(firsts)}: return None")
    tail.append(f"    return KEY, ({''.join(c + ', ' for c in values)}), "
                f"({''.join(n + ', ' for n in names)})")
    src = "def read(e, type=type):\n    try:\n" + "\n".join(lines or ["        pass"]) + \
        "\n    except (AttributeError, ValueError, TypeError):\n        return None\n" + \
        "\n".join(tail) + "\n"
    ns = {"Mul": Mul, "NUMBER": frozenset((Const, Known)), "zero_product": _is_zero_product,
          "KEY": key, "BOXES": tuple(Add if c == "Add" else Mul for _, c in boxes),
          "VARS": (Var,) * len(var_nodes), "FLOATS": (float,) * len(values)}
    exec(compile(src, "<rowcode reader>", "exec"), ns)
    return ns["read"]


class remembered:
    """Within it, `shape_of` keeps each tree's shape: the solve takes an equation's rows
    and its bounds in two passes, the shape is read once. `size`: the solve's number of
    equations, read by the outermost; below COMPILE_AFTER no tree is shaped within it
    (`shape_of` gives None: every reader takes its walk)."""

    def __init__(self, size: int | None = None):
        self.size = size

    def __enter__(self):
        if not _ON[0]:
            _SHAPES.clear()
            _PLAIN[0] = PLAIN_SMALL and self.size is not None and self.size < COMPILE_AFTER
        _ON[0] += 1
        return self

    def __exit__(self, *exc):
        _ON[0] -= 1
        if not _ON[0]:
            _SHAPES.clear()
            _PLAIN[0] = False


def shape_of(e):
    """`shape(e)`, remembered for the tree itself (held, so its id is not reused); None
    within a small solve's `remembered`."""
    if _PLAIN[0]:
        return None
    hit = _SHAPES.get(e, _NONE)  # trees hash by identity: the key holds the tree
    if hit is not _NONE:
        return hit
    sh = shape(e)
    if _ON[0]:
        _SHAPES[e] = sh
    return sh


def shapes_of(trees) -> list:
    """`shape_of` of each tree, in order (a large block's rows, a long sum's terms: the
    remembered ones looked up in line)."""
    if _PLAIN[0]:
        return [None] * len(trees)
    get = _SHAPES.get
    out = []
    for e in trees:
        sh = get(e, _NONE)
        out.append(shape_of(e) if sh is _NONE else sh)
    return out


def grouped(trees):
    """({shape key: ([index], [numbers], [names])}, [index of a tree without a shape]):
    the trees' shapes gathered by key, in order; trees of one shape come in runs, so the
    group of the last key is kept at hand."""
    groups: dict = {}
    free: list[int] = []
    last = g = None
    for i, sh in enumerate(shapes_of(trees)):
        if sh is None:
            free.append(i)
            continue
        key = sh[0]
        if key is not last:
            g = groups.get(key)
            if g is None:
                g = groups[key] = ([], [], [])
            last = key
        g[0].append(i)
        g[1].append(sh[1])
        g[2].append(sh[2])
    return groups, free


def _walk(e, toks, nums, names, first):
    t = type(e)
    if len(toks) > MAX_TOKENS:
        raise _No
    if t is Add:
        terms = e.terms
        toks.append(2)
        toks.append(len(terms))
        for x in terms:
            tx = type(x)
            if tx is Var:
                nm = x.name
                toks.append(1)
                toks.append(first.setdefault(nm, len(names)))
                names.append(nm)
            elif tx is Const or tx is Known:
                v = x.value
                if type(v) is not float:
                    raise _No
                toks.append(0)
                nums.append(v)
            else:
                _walk(x, toks, nums, names, first)
    elif t is Mul:
        fs = e.factors
        zero = False
        for f in fs:
            tf = type(f)
            if tf is Const or tf is Known:
                v = f.value
                if type(v) is not float:
                    raise _No
                if v == 0.0:
                    zero = True
        if zero:
            toks.append(4)
            return
        toks.append(3)
        toks.append(len(fs))
        for f in fs:
            tf = type(f)
            if tf is Var:
                nm = f.name
                toks.append(1)
                toks.append(first.setdefault(nm, len(names)))
                names.append(nm)
            elif tf is Const or tf is Known:
                toks.append(0)
                nums.append(f.value)
            else:
                _walk(f, toks, nums, names, first)
    elif t is Var:
        nm = e.name
        toks.append(1)
        toks.append(first.setdefault(nm, len(names)))
        names.append(nm)
    elif t is Const or t is Known:
        v = e.value
        if type(v) is not float:
            raise _No
        toks.append(0)
        nums.append(v)
    else:
        raise _No


class _Node:
    """One position of a shape: kind c (number), v (unknown), add, mul or zero."""

    __slots__ = ("kind", "i", "same", "kids")

    def __init__(self, kind, i=0, same=0, kids=()):
        self.kind, self.i, self.same, self.kids = kind, i, same, kids


def _parse(key):
    """The position tree of a shape key (each position its own node)."""
    pos = [0]
    count = [0, 0]  # numbers, names so far

    def node():
        k = key[pos[0]]
        pos[0] += 1
        if k == 0:
            count[0] += 1
            return _Node("c", count[0] - 1)
        if k == 1:
            same = key[pos[0]]
            pos[0] += 1
            count[1] += 1
            return _Node("v", count[1] - 1, same)
        if k == 4:
            return _Node("zero")
        n = key[pos[0]]
        pos[0] += 1
        return _Node("add" if k == 2 else "mul", kids=[node() for _ in range(n)])

    root = node()
    return root, count[1]


class _Src:
    """Generated lines; `prefix` names the temporaries (several trees' code in one
    function: `block_kinds`)."""

    def __init__(self, prefix: str = ""):
        self.lines: list[str] = []
        self.k = 0
        self.prefix = prefix

    def tmp(self, expr: str) -> str:
        self.k += 1
        name = f"{self.prefix}t{self.k}"
        self.lines.append(f"    {name} = {expr}")
        return name

    def function(self, head: str, ns: dict):
        code = f"def {head}:\n" + "\n".join(self.lines or ["    pass"]) + "\n"
        exec(compile(code, "<rowcode>", "exec"), ns)
        return ns[head.split("(")[0]]


# ---- bounds.derivatives_and_size -------------------------------------------------------
def _gs_function(key, value: bool = False):
    """f(c, n, values, out, w) -> size: `bounds._grad_size(e, w, values, out)`; with
    `value`, -> (`expr.evaluate(e, values)`, size): `_val_function`'s value from the
    same temporaries (the same expressions: the same floats)."""
    s = _Src()
    root, size, val = emit_gs(s, key)
    if value:
        s.lines.append(f"    return {val(root)}, {size}")
        return s.function("vgs(c, n, values, out, w)", {"fsum": math.fsum})
    s.lines.append(f"    return {size}")
    return s.function("gs(c, n, values, out, w)", {"fsum": math.fsum})


def _add_out(i: int, same: int, w: str, c: str, n: str) -> str:
    """`emit_gs`'s line adding a slope to the walk's dict (the walk's own statement)."""
    return f"    out[{n}[{i}]] = out.get({n}[{i}], 0.0) + {w}"


def emit_gs(s: _Src, key, c: str = "c", n: str = "n", x: str = "x", add=_add_out):
    """Emit `_gs_function`'s walk of the shape `key` into `s`, its numbers read from `c`,
    names from `n`, values into locals named `x`...; `add(i, same, w, c, n)` is each
    slope's line. (root, size expression, val: a position's value expression)."""
    root, nvars = _parse(key)
    for j in range(nvars):  # every unknown outside a zero product is read by the walk
        s.lines.append(f"    {x}{j} = values[{n}[{j}]]")
    vals: dict = {}

    def val(nd) -> str:  # expr.evaluate of a position (once: it is pure)
        if nd.kind == "c":
            return f"{c}[{nd.i}]"
        if nd.kind == "v":
            return f"{x}{nd.i}"
        if nd.kind == "zero":
            return "0.0"
        got = vals.get(id(nd))
        if got is None:
            parts = [val(k) for k in nd.kids]
            got = s.tmp("fsum([" + ", ".join(parts) + "])" if nd.kind == "add" else
                        "1.0" + "".join(" * " + p for p in parts))
            vals[id(nd)] = got
        return got

    def gs(nd, w: str) -> str:
        if nd.kind == "c":
            return f"abs({c}[{nd.i}])"
        if nd.kind == "v":
            s.lines.append(add(nd.i, nd.same, w, c, n))
            return f"abs({x}{nd.i})"
        if nd.kind == "zero":
            return "0.0"
        if nd.kind == "add":
            return s.tmp("sum([" + ", ".join(gs(k, w) for k in nd.kids) + "])")
        vs = [val(k) for k in nd.kids]
        sizes = []
        for i, k in enumerate(nd.kids):
            if k.kind == "c":
                sizes.append(f"abs({c}[{k.i}])")
                continue
            wk = s.tmp(w + "".join(" * " + v for j, v in enumerate(vs) if j != i))
            sizes.append(gs(k, wk))
        return s.tmp("1.0" + "".join(" * " + z for z in sizes))

    return root, gs(root, "w"), val


def _val_function(key):
    """f(c, n, values) -> `expr.evaluate(e, values)`."""
    root, nvars = _parse(key)
    s = _Src()
    for j in range(nvars):
        s.lines.append(f"    x{j} = values[n[{j}]]")

    def val(nd) -> str:
        if nd.kind == "c":
            return f"c[{nd.i}]"
        if nd.kind == "v":
            return f"x{nd.i}"
        if nd.kind == "zero":
            return "0.0"
        parts = [val(k) for k in nd.kids]
        return s.tmp("fsum([" + ", ".join(parts) + "])" if nd.kind == "add" else
                     "1.0" + "".join(" * " + p for p in parts))

    s.lines.append(f"    return {val(root)}")
    return s.function("val(c, n, values)", {"fsum": math.fsum})




def kept(cache: dict, key, make):
    """cache[key], made by make(key) the first time; the cache is emptied once it holds
    LIMIT entries (a file of many shapes must not grow it without bound)."""
    if key not in cache:
        if len(cache) >= LIMIT:
            cache.clear()
        cache[key] = make(key)
    return cache[key]


def _compiled(cache: dict, key, make):
    """The compiled function for `key`, made once the shape was met COMPILE_AFTER times
    (a shape met a few times, as in small files, is cheaper to walk than to compile);
    None before."""
    f = cache.get(key)
    if f is None:
        f = compiled_after(cache, _SEEN, key, make, COMPILE_AFTER, LIMIT,
                           seen_key=(id(cache), key))
    return f


def _val_of(key):
    f = _VAL.get(key)
    return f if f is not None else _compiled(_VAL, key, _val_function)


def _evaluate_parts(e, values):
    """`expr.evaluate` with each small subtree by its shape's compiled function (raises
    _No where the tree holds anything else: powers, functions, traced numbers)."""
    sh = shape_of(e)
    if sh is not None:
        f = _val_of(sh[0])
        return f(sh[1], sh[2], values) if f is not None else walk_value(e, values)
    t = type(e)
    if t is Add:
        return math.fsum([_evaluate_parts(x, values) for x in e.terms])
    if t is Mul:
        fs = e.factors
        for f in fs:
            if (type(f) is Const or type(f) is Known) and type(f.value) is not float:
                raise _No
        for f in fs:
            if (type(f) is Known or type(f) is Const) and f.value == 0.0:
                return 0.0
        r = 1.0
        for f in fs:
            r *= _evaluate_parts(f, values)
        return r
    raise _No


def evaluate(e, values):
    """`expr.evaluate(e, values)`, a large tree by its compiled parts (any failure, and
    anything else, by `expr.evaluate` itself: the same value or the same exception)."""
    if ENABLED and not _PLAIN[0]:
        try:
            return _evaluate_parts(e, values)
        except (_No, KeyError, ValueError, ZeroDivisionError, OverflowError, RecursionError):
            pass
    return _expr.evaluate(e, values)


def derivatives_and_size(e, values, shaped=None):
    """`bounds.derivatives_and_size(e, values)` by the shape's compiled walk, or None
    where it has none or the walk fails (the caller walks the tree then: its failures
    are handled as it handles them). `shaped`: `shape(e)` if already taken."""
    sh = (shape_of(e) if shaped is None else shaped) if ENABLED else None
    if sh is None:
        return None
    key, nums, names = sh
    f = _gs_of(key)
    if f is None:
        return None
    out: dict = {}
    try:
        return out, f(nums, names, values, out, 1.0)
    except (KeyError, ValueError, ZeroDivisionError, OverflowError):
        return None


def _gs_of(key):
    f = _GS.get(key)
    return f if f is not None else _compiled(_GS, key, _gs_function)


def grad_size_big(e, values, walk):
    """`bounds.derivatives_and_size` of a large tree (a scene's total energy): its sums
    and products walked as `bounds._grad_size` walks them, each small subtree by its
    shape's compiled walk. None where any part fails (the caller walks it all then)."""
    if not ENABLED or _PLAIN[0]:
        return None
    out: dict = {}

    def gs(e, w):
        sh = shape_of(e)
        if sh is not None:
            f = _gs_of(sh[0])
            return f(sh[1], sh[2], values, out, w) if f is not None else \
                walk(e, w, values, out)
        t = type(e)
        if t is Add:
            return sum([gs(x, w) for x in e.terms])
        if t is Mul:
            fs = e.factors
            for f in fs:
                if (type(f) is Const or type(f) is Known) and type(f.value) is not float:
                    raise _No
            if any((type(f) is Const or type(f) is Known) and f.value == 0.0 for f in fs):
                return 0.0
            vals = [_evaluate_parts(f, values) for f in fs]
            r = 1.0
            for i, f in enumerate(fs):
                if type(f) is Const or type(f) is Known:
                    r *= abs(f.value)
                    continue
                k = w
                for j, v in enumerate(vals):
                    if j != i:
                        k *= v
                r *= gs(f, k)
            return r
        raise _No  # powers and functions of large trees: the plain walk

    try:
        return out, gs(e, 1.0)
    except (_No, KeyError, ValueError, ZeroDivisionError, OverflowError, RecursionError):
        return None
    finally:  # gs refers to itself: without this the cycle keeps `values` and `out`
        del gs  # alive until a cyclic collection (paused during a solve)


_VGS: dict = {}  # value, derivatives and size in one walk, by shape (`value_grad_size`)


def _vgs_function(key):
    return _gs_function(key, True)


def value_grad_size(e, values, walk, big_sum=None):
    """(`evaluate(e, values)`, *`grad_size_big(e, values, walk)`) of a large tree (a
    scene's energy, an energy lost: an answer's value and its bound) with each small
    term walked once by its shape's compiled walk, not once for the value and once for
    the bound; None where the tree has a shape of its own or anything else the two
    walks take otherwise (a product of two large factors, a power), or anything fails
    (the caller takes the two walks then: the same numbers, or their failures).
    `big_sum(terms, w, values, out, walk_term)`: (values, sizes) of a long sum's terms,
    their slopes added to `out` as this walk adds them, or None (terms_columns)."""
    if not ENABLED or _PLAIN[0] or shape_of(e) is not None:
        return None
    out: dict = {}
    try:
        v, z = _vgs(e, 1.0, values, out, walk, big_sum)
    except (_No, KeyError, ValueError, ZeroDivisionError, OverflowError, RecursionError):
        return None
    return v, out, z


def _vgs(e, w, values, out, walk, big_sum=None):
    """(value, size) of `e` with its derivatives times w added to `out`: the walks of
    `_evaluate_parts` and `grad_size_big`'s gs, in one."""
    sh = shape_of(e)
    if sh is not None:
        key, nums, names = sh
        f = _VGS.get(key)
        if f is None:
            f = _compiled(_VGS, key, _vgs_function)
        if f is not None:
            return f(nums, names, values, out, w)
        fv = _val_of(key)  # not compiled yet: as the two walks take it
        v = fv(nums, names, values) if fv is not None else walk_value(e, values)
        fg = _gs_of(key)
        return v, (fg(nums, names, values, out, w) if fg is not None else
                   walk(e, w, values, out))
    t = type(e)
    if t is Add:
        if big_sum is not None and len(e.terms) >= 256:  # an energy of many bodies
            got = big_sum(e.terms, w, values, out,
                          lambda x: _vgs(x, w, values, out, walk, big_sum))
            if got is not None:
                return math.fsum(got[0]), sum(got[1])
        vs = []
        zs = []
        for x in e.terms:
            v, z = _vgs(x, w, values, out, walk, big_sum)
            vs.append(v)
            zs.append(z)
        return math.fsum(vs), sum(zs)
    if t is Mul:  # numbers times one large factor (-(T2)): its weight is known first
        fs = e.factors
        for f in fs:
            if (type(f) is Const or type(f) is Known) and type(f.value) is not float:
                raise _No
        for f in fs:
            if (type(f) is Known or type(f) is Const) and f.value == 0.0:
                return 0.0, 0.0
        free = [i for i, f in enumerate(fs) if type(f) is not Const and type(f) is not Known]
        if len(free) != 1:
            raise _No
        i = free[0]
        k = w
        for j, f in enumerate(fs):
            if j != i:
                k *= f.value
        v, z = _vgs(fs[i], k, values, out, walk, big_sum)
        value = size = 1.0
        for j, f in enumerate(fs):
            if j == i:
                value *= v
                size *= z
            else:
                value *= f.value
                size *= abs(f.value)
        return value, size
    raise _No


# ---- expr._affine_float ----------------------------------------------------------------
def _affine_function(key, inside):
    """f(c, n, values) -> (coef, const): `expr._affine_float(e, block, values)` where
    `inside[j]` says whether unknown j is in the block. Coefficient dicts are followed
    at compile time (which unknowns repeat is part of the key); the numbers run as the
    walk runs them, lookups and NonLinear included, in its order."""
    s = _Src()
    try:
        coef, const = emit_affine(s, key, inside)
        items = ", ".join(f"n[{i}]: {v}" for _same, v, i in coef)
        s.lines.append(f"    return {{{items}}}, {const}")
    except _Stop:
        pass
    return s.function("aff(c, n, values)", {"NonLinear": NonLinear})


def emit_affine(s: _Src, key, inside, nums: str = "c", names: str = "n"):
    """Emit `_affine_function`'s walk of the shape `key` into `s` (numbers from `nums`,
    names from `names`): (coef, const), coef a list of [same, expression, position] in the
    walk's insertion order; raises _Stop after emitting `raise NonLinear()`."""
    root, _ = _parse(key)

    def aff(nd):
        """(coef: list of [same, expr] in insertion order, const expr); code emitted."""
        if nd.kind == "c":
            return [], f"{nums}[{nd.i}]"
        if nd.kind == "zero":
            return [], "0.0"
        if nd.kind == "v":
            if inside[nd.i]:
                return [[nd.same, "1.0", nd.i]], "0.0"
            return [], s.tmp(f"values[{names}[{nd.i}]]")
        if nd.kind == "add":
            coef: list = []
            const = "0.0"
            for x in nd.kids:
                c, k = aff(x)
                const = s.tmp(f"{const} + {k}")
                for same, v, i in c:
                    hit = next((e for e in coef if e[0] == same), None)
                    if hit is None:
                        coef.append([same, s.tmp(f"0.0 + {v}"), i])
                    else:
                        hit[1] = s.tmp(f"{hit[1]} + {v}")
            return coef, const
        coef, const = [], "1.0"
        for f in nd.kids:
            c, k = aff(f)
            if c and coef:
                s.lines.append("    raise NonLinear()")
                raise _Stop
            if c:
                coef = [[same, s.tmp(f"{v} * {const}"), i] for same, v, i in c]
                const = s.tmp(f"{k} * {const}")
            else:
                coef = [[same, s.tmp(f"{v} * {k}"), i] for same, v, i in coef]
                const = s.tmp(f"{const} * {k}")
        return coef, const

    return aff(root)


class _Stop(Exception):
    pass


def affine(e, block, values, shaped=None):
    """`expr.affine(e, block, values)` by the shape's compiled walk where it has one."""
    walk = _expr.affine  # read at the call, as the import here did (tests patch it)
    sh = (shape_of(e) if shaped is None else shaped) if ENABLED else None
    if sh is None:
        return walk(e, block, values)
    key, nums, names = sh
    k = (key, tuple([nm in block for nm in names]))
    f = _AFF.get(k)  # compiled already: the common case, without `_compiled`'s call
    if f is None:
        f = _compiled(_AFF, k, _affine_of)
    return f(nums, names, values) if f is not None else walk(e, block, values)


def _affine_of(k):
    return _affine_function(*k)


MANY = 16  # a sum of this many terms is named from its terms' shapes


def variables_into(e, into: set, walk) -> None:
    """`walk(e, into)` (expr.variables): a sum of many terms by its terms' shapes (kept
    for the solve's later walks of the same terms: an answer's energy shares them). A
    shape names the unknowns `variables` finds: both leave out a product with a zero
    number, and a shape holds nothing else; `walk` for the terms that are no shape."""
    if ENABLED and _ON[0] and not _PLAIN[0] and type(e) is Add and len(e.terms) >= MANY:
        for x in e.terms:
            sh = shape_of(x)
            if sh is not None:
                into.update(sh[2])
            elif type(x) is Mul:  # -(a sum of many terms), as `variables` walks it
                if not any((type(f) is Const or type(f) is Known) and f.value == 0.0
                           for f in x.factors):
                    for f in x.factors:
                        variables_into(f, into, walk)
            else:
                walk(x, into)
        return
    walk(e, into)
