"""Checks of the Python API's arguments, with the one-line messages the command line prints.

Every function of :mod:`ekm.api` checks what it is given before any long work starts and raises
:class:`ekm.errors.InputError`. It names an argument as the command line spells it (``steps`` is
``--steps``) and words the problem as the command line does, so that a script and a shell report the
same mistake with the same line: ``ekm.train(mapping="indirect", steps=0)`` raises
``ekm train: argument --steps: must be > 0, got 0``, which is what ``ekm train --steps 0`` prints.
The command line's argument types (:mod:`ekm.cli.args`) word their messages with the same helpers.
"""

from __future__ import annotations

import math
import numbers
from pathlib import Path

from ekm.errors import InputError


def sign_problem(value, strict: bool, shown: str | None = None) -> str | None:
    """``"must be > 0, got 0"`` (``strict``) or ``"must be >= 0, got -1"`` when ``value`` breaks the rule;
    ``shown``: how the value was spelt (the command line's text), by default ``str(value)``."""
    if value < 0 or (strict and value == 0):
        return f"must be {'>' if strict else '>='} 0, got {value if shown is None else shown}"
    return None


def invalid_choice(value, choices) -> str:
    """argparse's wording for a value not among ``choices``, with the closest of them
    (:func:`robots.spelling.did_you_mean`)."""
    from robots.spelling import did_you_mean

    return f"invalid choice: {value!r}{did_you_mean(value, choices)} (choose from {', '.join(map(repr, choices))})"


def _fail(prog: str, option: str, problem: str):
    raise InputError(f"{prog}: argument {option}: {problem}")


def whole(value, option: str, prog: str, *, strict: bool) -> int:
    """``value`` as an int > 0 (``strict``) or >= 0; anything else is an :class:`InputError`."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        _fail(prog, option, f"must be a whole number, got {value!r}")
    problem = sign_problem(value, strict)
    if problem:
        _fail(prog, option, problem)
    return int(value)


def number(value, option: str, prog: str, *, strict: bool) -> float:
    """``value`` as a finite float > 0 (``strict``) or >= 0."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        _fail(prog, option, f"must be a number, got {value!r}")
    if not math.isfinite(value):
        _fail(prog, option, f"must be finite, got {value}")
    problem = sign_problem(value, strict)
    if problem:
        _fail(prog, option, problem)
    return float(value)


def choice(value, choices, option: str, prog: str) -> str:
    """``value`` if it is one of ``choices``."""
    if value not in choices:
        _fail(prog, option, invalid_choice(value, choices))
    return value


#: The formats a plot is written in, by the file's suffix (matplotlib's): a PNG for the screen, SVG and PDF for papers.
PLOT_SUFFIXES = (".png", ".svg", ".pdf")


def output_path(text, option: str, suffix: str | tuple[str, ...]) -> Path:
    """Check an output path before long work starts: not a directory, a suffix of ``suffix`` (one or several),
    in a directory that exists — a missing one is refused, not made — and can be written."""
    import os

    suffixes = (suffix,) if isinstance(suffix, str) else tuple(suffix)
    wanted = " or ".join(filter(None, (", ".join(suffixes[:-1]), suffixes[-1])))
    path = Path(text)
    if path.is_dir():
        raise InputError(f"{option} {text}: is a directory, expected a {wanted} file")
    if path.suffix.lower() not in suffixes:
        raise InputError(f"{option} {text}: expected a file name ending in {wanted}")
    if not path.parent.is_dir():
        raise InputError(f"{option} {text}: no such directory {path.parent} (make it first)")
    if not os.access(path.parent, os.W_OK):
        raise InputError(f"{option} {text}: its directory is not writable")
    return path


def plot_path(text, option: str = "--plot") -> Path:
    """:func:`output_path` of a plot: PNG, SVG or PDF by its suffix (:data:`PLOT_SUFFIXES`)."""
    return output_path(text, option, PLOT_SUFFIXES)
