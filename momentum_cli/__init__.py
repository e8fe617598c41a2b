"""momentum: rigid-body impulse, momentum and impact problems, solved step by step."""
from __future__ import annotations


def __getattr__(name: str):
    # importlib.metadata costs ~40 ms: read the version only when it is asked for
    if name == "__version__":
        try:
            from importlib.metadata import PackageNotFoundError, version

            return version("momentum-cli")
        except PackageNotFoundError:  # running from a source tree
            return "0.1.0"
    raise AttributeError(name)
