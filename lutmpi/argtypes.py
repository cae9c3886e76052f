"""Number types of command-line options: a value argparse refuses with a usage error (exit
status 2, the option named) instead of a NaN or a zero that fails minutes later with a
traceback, or is silently ignored."""

from __future__ import annotations

import argparse
import math
from collections.abc import Callable


def _number(text: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not math.isfinite(v):
        raise argparse.ArgumentTypeError(f"expected a finite number, got {text!r}")
    return v


def finite(text: str) -> float:
    """A finite number."""
    return _number(text)


def positive(text: str) -> float:
    """A finite number > 0."""
    v = _number(text)
    if not v > 0.0:
        raise argparse.ArgumentTypeError(f"expected a number > 0, got {text!r}")
    return v


def nonnegative(text: str) -> float:
    """A finite number >= 0."""
    v = _number(text)
    if not v >= 0.0:
        raise argparse.ArgumentTypeError(f"expected a number >= 0, got {text!r}")
    return v


def within(bound: float) -> Callable[[str], float]:
    """A finite number of magnitude at most ``bound``."""
    def check(text: str) -> float:
        v = _number(text)
        if abs(v) > bound:
            raise argparse.ArgumentTypeError(f"expected a number in [-{bound:g}, {bound:g}], "
                                             f"got {text!r}")
        return v

    return check
