"""A batch routed to workers (run_pool) prints what each file solved alone prints.

Files of a batch are routed by family to one-process pools (run_pool.Router); where a
file is solved must never change what is printed. Checked byte for byte (stdout, stderr,
exit code; --plain and --json) over every example and generated number-only variants
(numbers scaled, zeroed, negated, made huge: regime changes, singular blocks, bad
values), plus files that do not parse, are not UTF-8 or do not exist, against the same
call with --traceback (each file solved alone, in order, in one process).
"""
from __future__ import annotations

import random
import re
import subprocess
import sys
from pathlib import Path

import pytest

from momentum_cli import run_pool
from momentum_cli.run import PARALLEL_MIN

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = sorted((ROOT / "examples").glob("*.mom"))
NUMBER = re.compile(r"(?<=[=(,] )(\d+\.?\d*)(?=[ ,)\n])")


def variant(text: str, rng: random.Random) -> str:
    """Some given numbers changed: scaled (a regime may switch), zeroed or negated (a
    block may turn singular, a value become bad), or made huge."""
    def new(m):
        if rng.random() > 0.35:
            return m.group(1)
        x = float(m.group(1))
        return f"{rng.choice([x * rng.uniform(0.3, 3), 0.0, -x, x * 1e9, x * 1.5]):.5g}"
    return NUMBER.sub(new, text)


def batch_files(tmp_path: Path) -> list[str]:
    rng = random.Random(13)
    paths = []
    texts = [p.read_text(encoding="utf-8") for p in EXAMPLES]
    for k, (p, text) in enumerate(zip(EXAMPLES, texts)):
        out = tmp_path / f"{k:03d}_{p.name}"
        out.write_text(text, encoding="utf-8")
        paths.append(out)
    for k in range(60):  # variants, interleaved with other families
        j = rng.randrange(len(texts))
        out = tmp_path / f"v{k:03d}_{EXAMPLES[j].name}"
        out.write_text(variant(texts[j], rng), encoding="utf-8")
        paths.append(out)
    bad = tmp_path / "bad_syntax.mom"
    bad.write_text("body b: rod(mass = 1 m, length = 1 m)\n", encoding="utf-8")
    latin = tmp_path / "latin1.mom"
    latin.write_bytes(b'problem "caf\xe9"\n')
    empty = tmp_path / "empty.mom"
    empty.write_text("", encoding="utf-8")
    paths[10:10] = [bad, latin, tmp_path / "missing.mom", empty]
    rng.shuffle(paths)
    assert len(paths) >= PARALLEL_MIN
    return [str(p) for p in paths]


@pytest.mark.parametrize("fmt", ["--plain", "--json"])
def test_a_routed_batch_prints_what_each_file_alone_prints(tmp_path, fmt):
    paths = batch_files(tmp_path)
    args = [sys.executable, "-m", "momentum_cli", "solve", fmt, *paths]
    par = subprocess.run(args, capture_output=True, text=True, timeout=600)
    ser = subprocess.run(args + ["--traceback"], capture_output=True, text=True, timeout=600)
    assert par.returncode == ser.returncode == 2  # the missing file: a usage error
    assert par.stdout == ser.stdout
    assert par.stderr == ser.stderr
    assert "Traceback" not in par.stderr


def simulate(texts, workers: int, seed: int):
    """Run Router as routed does, with chunks finishing in a random order and each
    worker importing HEAVY when it solves a file that may integrate; returns the chunks
    per worker and each worker's imports."""
    rng = random.Random(seed)
    r = run_pool.Router(texts, workers)
    flying, out = [], {w: [] for w in range(workers)}
    loaded = [set() for _ in range(workers)]
    done: set = set()
    nxt = 0
    while nxt < len(texts):
        while nxt in done:
            nxt += 1
        for w in range(workers):
            while sum(1 for x, _ in flying if x == w) < run_pool.AHEAD:
                chunk = r.pick(w, nxt + run_pool.WINDOW)
                if not chunk:
                    break
                flying.append((w, chunk))
        if nxt >= len(texts):
            break
        assert flying, "stalled"
        w, chunk = flying.pop(rng.randrange(len(flying)))
        before = tuple(sorted(loaded[w]))
        if any(r.hint[i] for i in chunk):
            loaded[w] |= set(run_pool.HEAVY)
        r.learned(w, chunk, before, tuple(sorted(loaded[w])))
        out[w].append(chunk)
        done.update(chunk)
    return r, out, loaded


@pytest.mark.parametrize("seed", range(5))
def test_the_router_hands_out_every_file_once_in_chunks_of_one_family(seed):
    rng = random.Random(seed)
    texts = [p.read_text(encoding="utf-8") for p in EXAMPLES]
    batch = [texts[rng.randrange(len(texts))].replace("1", str(rng.randrange(1, 9)), 1)
             for _ in range(700)]
    r, out, loaded = simulate(batch, 2, seed)
    seen = sorted(i for chunks in out.values() for c in chunks for i in c)
    assert seen == list(range(len(batch)))
    for chunks in out.values():
        for c in chunks:
            assert c == sorted(c) and len(c) <= run_pool.CHUNK
            assert len({run_pool.family(batch[i]) for i in c}) == 1
    # the files that may integrate all went to one worker: only it imported scipy
    assert any(run_pool.may_integrate(t) for t in batch)
    assert [bool(x) for x in loaded] == [True, False]


def test_a_family_is_its_text_but_for_digits():
    a = 'problem "P (variant 3)"\nbody a: particle(mass = 2.5 kg)\n'
    b = 'problem "P (variant 41)"\nbody a: particle(mass = 7.75 kg)\n'
    c = 'problem "P (variant 3)"\nbody a: particle(mass = 2.5 g)\n'
    assert run_pool.family(a) == run_pool.family(b) != run_pool.family(c)
    assert run_pool.may_integrate("let x = 1\n  burn r 1 -> 2:\n")
    assert not run_pool.may_integrate("# burn r 1 -> 2\nimpact 1 -> 2:\n")
    assert not run_pool.may_integrate("let gains = 1\n")  # a word, not the statement
    assert run_pool.family("let a = 1 # café\n") == run_pool.family("let a = 22 # café\n")
    assert run_pool.family("let a = 1 # café\n") != run_pool.family("let a = 1 # cafe\n")


# ---- families of one structure that differ only in numbers ----------------------------
# Each entry: an example, and (text, numbers) pairs: every number put where `text`'s {}
# is, one file per number, the rest of the file unchanged. The numbers are chosen so
# that a friction regime switches (stick <-> slide), a block turns singular (a mass or
# a closing speed of 0), a root branch changes or disappears (a swing past the top, not
# enough energy), or the input is bad (a negative mass or coefficient).
FAMILIES = {
    "wall_oblique_stick.mom": [
        ("friction {}", ["0.3", "0.05", "0", "1", "-0.2", "0.15", "0.1"]),
        ("let beta = {} deg", ["20", "60", "0", "89", "45"]),
        ("mass = {} kg", ["0.2", "0", "-1", "1e9"]),
    ],
    "rod_rough_floor_newton.mom": [
        ("friction {}", ["0.5", "0.05", "0", "2", "0.2"]),
        ("rod.v = ({} m/s, -2 m/s)", ["1.2", "-1.2", "0", "9", "-30"]),
        ("restitution {} newton", ["0.9", "0", "1", "1.5"]),
    ],
    "ball_bounce_rebound.mom": [
        ("let h = {} m", ["2", "0", "-1", "1e9", "0.001"]),
        ("restitution {}, smooth", ["0.8", "0", "1", "-0.5"]),
    ],
    "find_e_no_energy_lost.mom": [
        ("a: particle(mass = {} kg)", ["2", "3", "0", "1e-9", "-2"]),
        ("a.v = ({} m/s, 0)", ["5", "0", "-5", "1e6"]),
    ],
    "pendulum_struck_ball_flies_off.mom": [
        ("ball.v = ({} m/s, 0)", ["6", "60", "0", "-6", "20", "2"]),
        ("let L = {} m", ["1.2", "0", "100"]),
    ],
}


def family_files(tmp_path: Path) -> list[str]:
    paths = []
    for name, spots in FAMILIES.items():
        text = (ROOT / "examples" / name).read_text(encoding="utf-8")
        for k, (spot, numbers) in enumerate(spots):
            first = spot.format(numbers[0])
            assert text.count(first) == 1, (name, first)
            for j, x in enumerate(numbers):
                out = tmp_path / f"{name[:-4]}_{k}_{j}.mom"
                out.write_text(text.replace(first, spot.format(x)), encoding="utf-8")
                paths.append(out)
    rng = random.Random(5)
    rng.shuffle(paths)  # the families interleaved, as a batch of several problem sets
    assert len(paths) >= PARALLEL_MIN
    return [str(p) for p in paths]


@pytest.mark.parametrize("fmt", ["--plain", "--json"])
def test_number_variants_of_one_structure_print_what_each_alone_prints(tmp_path, fmt):
    paths = family_files(tmp_path)
    args = [sys.executable, "-m", "momentum_cli", "solve", fmt, *paths]
    par = subprocess.run(args, capture_output=True, text=True, timeout=600)
    ser = subprocess.run(args + ["--traceback"], capture_output=True, text=True, timeout=600)
    assert par.returncode == ser.returncode == 1  # some variants do not solve
    assert par.stdout == ser.stdout
    assert par.stderr == ser.stderr
    assert "Traceback" not in par.stderr
    if fmt == "--plain":  # the variants do go different ways
        out = par.stdout + par.stderr
        for seen in ("stick held", "sliding", "error:", "no real solution"):
            assert seen in out, seen
