"""momentum: rigid-body impulse, momentum and impact problems, solved step by step."""
from __future__ import annotations


def _version() -> str:
    try:
        from importlib.metadata import PackageNotFoundError, version

        return version("momentum-cli")
    except PackageNotFoundError:  # running from a source tree
        return "0.1.0"


__version__ = _version()
