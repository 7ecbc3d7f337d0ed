"""Argument types and helpers shared by the ``ekm`` commands: checked numbers and points, output
paths checked before long work starts, stable JSON output, and when to show progress bars."""

from __future__ import annotations

import argparse
import json
import math
import sys

from ekm.errors import InputError


def _whole_number(text: str) -> int:
    try:
        return int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a whole number, got {text!r}") from None


def finite_float(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a number, got {text!r}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"must be finite, got {text}")
    return value


def _signed(parse, *, strict: bool):
    """An argparse type: ``parse`` the text, then require > 0 (``strict``) or >= 0."""

    def check(text: str):
        value = parse(text)
        if value < 0 or (strict and value == 0):
            raise argparse.ArgumentTypeError(f"must be {'>' if strict else '>='} 0, got {text}")
        return value

    return check


positive_int = _signed(_whole_number, strict=True)
nonneg_int = _signed(_whole_number, strict=False)
positive_float = _signed(finite_float, strict=True)
nonneg_float = _signed(finite_float, strict=False)


def xy_point(text: str) -> tuple[float, float]:
    """``"X,Y"`` in metres → ``(x, y)``."""
    parts = text.split(",")
    try:
        if len(parts) != 2:
            raise argparse.ArgumentTypeError("")
        return finite_float(parts[0]), finite_float(parts[1])
    except argparse.ArgumentTypeError:
        raise argparse.ArgumentTypeError(f"must be X,Y in metres (e.g. 0.1,0.3), got {text!r}") from None


def output_path(text: str, option: str, suffix: str):
    """Check an output path before long work starts: not a directory, the right suffix, a directory
    that exists (it is created) and can be written."""
    import os
    from pathlib import Path

    path = Path(text)
    if path.is_dir():
        raise InputError(f"{option} {text}: is a directory, expected a {suffix} file")
    if path.suffix.lower() != suffix:
        raise InputError(f"{option} {text}: expected a file name ending in {suffix}")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"{option} {text}: cannot create its directory ({exc.strerror or exc})") from None
    if not os.access(path.parent, os.W_OK):
        raise InputError(f"{option} {text}: its directory is not writable")
    return path


def provenance(jax: bool = True) -> dict:
    """What made a ``--json`` result, for reproducing it later: the package's version and, where JAX
    computed it, JAX's (read from the installed metadata, without importing JAX)."""
    from importlib.metadata import PackageNotFoundError, version

    from ekm import __version__

    out = {"ekm_version": __version__}
    if jax:
        try:
            out["jax_version"] = version("jax")
        except PackageNotFoundError:
            out["jax_version"] = None
    return out


def print_json(obj) -> None:
    """Write ``obj`` as the command's stable JSON output."""
    json.dump(obj, sys.stdout, indent=2, allow_nan=False)
    sys.stdout.write("\n")


def show_progress(args) -> bool:
    """Progress bars only on a terminal and never with ``--json``."""
    return not getattr(args, "json", False) and sys.stderr.isatty()
