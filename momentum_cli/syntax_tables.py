"""The LALR parser as plain data, so that a run need not import lark at all.

In: lark's parser (syntax.parser: parse table, rules, contextual lexer, indenter). Out:
marshal-able tables for syntax_run.py, cached beside lark's pickle, every lexer regex
stored compiled (CPython's `_sre` code): no regex is compiled at start-up.
"""
from __future__ import annotations

import marshal
import os
import re
import sys

FORMAT = 2  # bump when the layout of the tables changes


def lark_version() -> str | None:
    """lark's version, read from its source without importing it (the import costs more
    than a whole small parse)."""
    from importlib.machinery import PathFinder

    try:
        spec = PathFinder.find_spec("lark")
        if spec is None or not spec.origin:
            return None
        with open(spec.origin, encoding="utf-8") as fh:
            m = re.search(r"""^__version__\b[^=\n]*=\s*["']([^"'\n]+)["']""", fh.read(), re.M)
    except (OSError, ImportError, ValueError):
        return None
    return m.group(1) if m else None


def identity(grammar: str) -> dict:
    """What the tables were built from: a cached copy is used only when all of it is equal
    (the compiled regex code belongs to one Python build)."""
    return {"format": FORMAT, "grammar": grammar, "python": sys.version,
            "lark": lark_version()}


def _sre_args(pattern: str, flags: int):
    """re.compile's arguments to `_sre.compile` for `pattern` (plain data), or None when
    this Python's regex compiler is not the one expected."""
    try:
        try:
            from re import _compiler, _parser
        except ImportError:  # Python 3.10
            import sre_compile as _compiler
            import sre_parse as _parser
        import _sre

        p = _parser.parse(pattern, flags)
        code = [int(c) for c in _compiler._code(p, flags)]
        groupindex = dict(p.state.groupdict)
        indexgroup = [None] * p.state.groups
        for k, i in groupindex.items():
            indexgroup[i] = k
        args = (pattern, int(flags | p.state.flags), code, p.state.groups - 1, groupindex,
                tuple(indexgroup))
        made, ref = _sre.compile(*args), re.compile(pattern, flags)
        if (made.pattern, made.flags, made.groups, made.groupindex) != \
                (ref.pattern, ref.flags, ref.groups, dict(ref.groupindex)):
            return None
        return args
    except Exception:  # any change in the private compiler: store the pattern only
        return None


def build(lark_parser, indenter) -> dict | None:
    """The tables of `lark_parser` (lalr, contextual lexer, `indenter` as postlex, trees
    with propagated positions, no placeholders); None when it uses a feature
    syntax_run does not reproduce (then lark parses every file)."""
    from lark.lexer import Scanner, _create_unless
    from lark.parsers.lalr_analysis import Shift

    frontend = lark_parser.parser
    lexer = frontend.lexer.lexer  # PostLexConnector -> ContextualLexer
    table = frontend.parser.parser.parse_table
    opts = lark_parser.options
    from lark import Tree

    if opts.parser != "lalr" or opts.maybe_placeholders or opts.propagate_positions is not True \
            or opts.lexer_callbacks or opts.g_regex_flags or opts.use_bytes or opts.regex \
            or opts.tree_class not in (None, Tree) or opts.keep_all_tokens:
        return None
    if list(table.start_states) != ["start"]:
        return None
    if any(t.pattern.flags for t in lexer.root_lexer.terminals):
        return None

    # rules, in the order the parse table first names them
    rules, rule_index = [], {}

    def rule_id(rule) -> int:
        if id(rule) not in rule_index:
            rule_index[id(rule)] = len(rules)
            rules.append(rule)
        return rule_index[id(rule)]

    states = {}
    for state, actions in table.states.items():
        row = {}
        for term, (action, arg) in actions.items():
            row[term] = arg if action is Shift else ~rule_id(arg)
        states[state] = row
    rule_rows = []
    for rule in rules:
        o = rule.options
        if o.keep_all_tokens:  # (empty_indices: only with maybe_placeholders)
            return None
        expand1 = bool(o.expand1 and not rule.alias)
        include = [(i, not sym.is_term and sym.name.startswith("_"))
                   for i, sym in enumerate(rule.expansion)
                   if not (sym.is_term and sym.filter_out)]
        if expand1 and any(e for _, e in include):
            return None  # `?rule` over an inlined `_rule`: not reproduced
        plain = len(include) == len(rule.expansion) and not any(e for _, e in include)
        name = rule.alias or o.template_source or rule.origin.name
        rule_rows.append((str(rule.origin.name), len(rule.expansion), str(name), expand1,
                          None if plain else tuple(include)))

    # lexers: one per distinct terminal set, as lark's ContextualLexer shares them
    lexers, lexer_index, state_lexer = [], {}, {}
    newline = set()
    for state, basic in lexer.lexers.items():
        if id(basic) not in lexer_index:
            if basic.user_callbacks or basic.g_regex_flags or basic.use_bytes:
                return None
            terms, callbacks = _create_unless(basic.terminals, basic.g_regex_flags, basic.re,
                                              basic.use_bytes)
            scanner = Scanner(terms, basic.g_regex_flags, basic.re, basic.use_bytes)
            mres = []
            for mre in scanner._mres:
                mres.append((mre.pattern, int(mre.flags), _sre_args(mre.pattern, mre.flags)))
            mres = marshal.dumps(tuple(mres))  # loaded when the lexer is first used
            unless = {}
            for name, cb in callbacks.items():
                if not hasattr(cb, "scanner"):
                    return None
                unless[name] = {t.pattern.value: t.name for t in cb.scanner.terminals}
                if len(unless[name]) != len(cb.scanner.terminals):
                    return None
            newline |= set(basic.newline_types)
            lexer_index[id(basic)] = len(lexers)
            lexers.append((mres, unless))
        state_lexer[state] = lexer_index[id(basic)]

    ind = indenter
    return {
        "states": states,
        "start": table.start_states["start"],
        "end": table.end_states["start"],
        "rules": tuple(rule_rows),
        "lexers": tuple(lexers),
        "state_lexer": state_lexer,
        "ignore": tuple(sorted(lexer.root_lexer.ignore_types)),
        "newline": tuple(sorted(newline)),
        "indenter": (ind.NL_type, tuple(ind.OPEN_PAREN_types), tuple(ind.CLOSE_PAREN_types),
                     ind.INDENT_type, ind.DEDENT_type, int(ind.tab_len)),
    }


def cache_name(grammar: str) -> str:
    """The cache file's name (its content says exactly what it was built from)."""
    import zlib

    v = sys.version_info
    return f"tables-{zlib.crc32(grammar.encode()):08x}-{v[0]}{v[1]}-{FORMAT}.marshal"


def load(data: bytes, grammar: str):
    """(True, the tables) stored in a cache file's bytes (None: lark parses this grammar
    itself), or (False, None) when they were built from anything else than this grammar,
    this Python and this lark."""
    try:
        stored = marshal.loads(data)
    except (EOFError, ValueError, TypeError):
        return False, None
    if not isinstance(stored, dict) or stored.get("identity") != identity(grammar):
        return False, None
    return True, stored.get("tables")


def dump(tables, grammar: str) -> bytes:
    return marshal.dumps({"identity": identity(grammar), "tables": tables})


def cache_path(folder: str | None, grammar: str) -> str | None:
    return os.path.join(folder, cache_name(grammar)) if folder else None
