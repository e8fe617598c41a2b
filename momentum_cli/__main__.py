"""`python -m momentum_cli` and the `momentum` command: a one-shot plain or JSON
`solve` by the fast path (fastpath.py, without typer), anything else by the typer
application (cli.py), both inside the same guards (guard.py).
"""
import os
import sys

from .guard import guarded, one_shot


def _run() -> None:
    from .fastpath import try_solve

    # MOMENTUM_NO_FASTPATH=1: always typer (the tests compare the two)
    if os.environ.get("MOMENTUM_NO_FASTPATH") or not try_solve(sys.argv[1:]):
        from .cli import app

        # a fixed name: usage lines and shell completion (`_MOMENTUM_COMPLETE`) say
        # `momentum` also under `python -m momentum_cli`
        app(prog_name="momentum")


def main() -> None:
    """Entry point of the `momentum` command (also `python -m momentum_cli`): a process
    that ends with the command (guard.one_shot)."""
    one_shot()
    guarded(_run)


if __name__ == "__main__":
    main()
