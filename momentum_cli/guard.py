"""The guards around a whole command run: standard output that cannot be written,
interrupts and signals, mapped to exit codes. In: the run (a callable that ends in
SystemExit). Used by __main__.main (fast path, else typer) and cli.main (typer).
"""
from __future__ import annotations

import os
import sys

from .diagnostics import ExitCode


def _on_signal(signum, _frame) -> None:
    """SIGTERM or SIGHUP: end the worker processes and this one now, with 128 + signal
    (a pool waiting for its workers would not stop promptly)."""
    outputs = sys.modules.get("momentum_cli.outputs")
    if outputs is not None:
        outputs.remove_pending()  # no half-written temporary file is left behind
    mp = sys.modules.get("multiprocessing")
    if mp is not None:
        for child in mp.active_children():
            try:
                child.kill()
            except OSError:
                pass
    forked = sys.modules.get("momentum_cli.two_process")  # a report's second process
    if forked is not None:
        forked.kill_children()
    os._exit(128 + signum)


def _usable_environment() -> None:
    """Terminal sizes that are not positive whole numbers (`COLUMNS=0`) are ignored, so
    that rich does not draw into zero columns; signals end the run promptly."""
    import signal

    for var in ("COLUMNS", "LINES"):
        v = os.environ.get(var)
        if v is not None and not (v.strip().isdigit() and int(v) > 0):
            del os.environ[var]
    for name in ("SIGTERM", "SIGHUP"):
        if hasattr(signal, name):
            try:
                signal.signal(getattr(signal, name), _on_signal)
            except (ValueError, OSError):
                pass


_KEPT: list | None = None  # a one-shot process's big results, never freed (one_shot)


def one_shot() -> None:
    """This process runs one command and ends (the `momentum` command, not a caller of
    the package): a big result may be kept to its end and left unfreed."""
    global _KEPT
    _KEPT = []


def keep_until_exit(obj) -> bool:
    """In a one-shot process, hold `obj` to the end, which then comes by os._exit
    (`guarded`): freeing a big solution's 10^6 objects costs a quarter of a second a
    process about to end need not spend. False (nothing held) anywhere else."""
    if _KEPT is None:
        return False
    import gc

    _KEPT.append(obj)
    gc.freeze()  # no collection walks it again (its objects were made with gc paused)
    return True


def _leave_if_kept(code) -> None:
    """End now, with `code`, when a one-shot run kept a big result: the streams flushed,
    no interpreter teardown (no atexit work is registered by a solve). If a stream
    cannot be flushed, the normal exit says so as before."""
    if not _KEPT:
        return
    try:
        for stream in (sys.stdout, sys.stderr):
            stream.flush()
    except BaseException:  # noqa: B036 (OutputGone too: the normal exit handles it)
        return
    os._exit(_exit_status(code))


def _exit_status(code) -> int:
    """The process's exit status for SystemExit(code), as the interpreter gives it (a
    text is said on standard error and gives 1)."""
    if code is None:
        return 0
    if isinstance(code, int):
        return code
    try:
        sys.stderr.write(f"{code}\n")
        sys.stderr.flush()
    except Exception:  # the stream may be gone: nothing more can be said on it
        pass
    return 1


def _end_now_if_workers_killed(code) -> None:
    """After the worker pool was killed (run._end_workers), exit with os._exit: a
    normal exit joins the pool's manager thread, which can wait forever for a result
    a killed worker was half-way through writing."""
    run_module = sys.modules.get("momentum_cli.run")
    if run_module is None or not getattr(run_module, "WORKERS_KILLED", False):
        return
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except Exception:  # the stream may be gone: nothing more can be said on it
            pass
    os._exit(_exit_status(code))


def guarded(run) -> None:
    """Call `run` (the command); see _guarded_run. Whatever way it ends, a run whose
    worker pool was killed leaves through os._exit (_end_now_if_workers_killed), and so
    does a one-shot run that kept a big result (_leave_if_kept)."""
    try:
        _guarded_run(run)
    except SystemExit as exc:
        _end_now_if_workers_killed(exc.code)
        _leave_if_kept(exc.code)
        raise
    _end_now_if_workers_killed(0)
    _leave_if_kept(0)


def _guarded_run(run) -> None:
    """Call `run` (the command) with exit codes for output that cannot be written (a
    broken pipe ends quietly with 141, like other tools; a full disk or a closed
    standard output is one line and 3), interrupts and signals."""
    from .outputs import (GuardedStream, OutputFailed, OutputGone, silence_stdout,
                          stdout_is_closed)

    if stdout_is_closed():
        sys.stderr.write("momentum: error: standard output is closed\n")
        sys.exit(int(ExitCode.INTERNAL))
    _usable_environment()
    import warnings

    # scipy's and numpy's warnings (rtol clamped, overflow in a trial step) are not the
    # user's business: what matters reaches them as located diagnostics
    warnings.simplefilter("ignore")
    sys.stdout = GuardedStream(sys.stdout)
    try:
        try:
            run()
        finally:
            sys.stdout.flush()
    except KeyboardInterrupt:
        # like SIGTERM: end the workers and this process now; a normal exit would join
        # the pool's threads, where a late interrupt prints a traceback
        try:
            sys.stdout.flush()
            sys.stderr.flush()
        except (OSError, ValueError, OutputGone, OutputFailed):
            pass
        _on_signal(int(ExitCode.INTERRUPTED) - 128, None)
    except OutputGone:
        silence_stdout()
        sys.exit(141)
    except OutputFailed as exc:
        silence_stdout()
        sys.stderr.write(f"momentum: error: cannot write to standard output: {exc.reason}\n")
        sys.exit(int(ExitCode.INTERNAL))
