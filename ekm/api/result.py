"""What every result of the Python API shares: ``to_dict()`` is the command line's ``--json`` output.

A result is a frozen dataclass. ``to_dict()`` gives plain JSON values (lists, not tuples; Python numbers,
not NumPy ones) in the key order the command prints them, so ``json.dumps(result.to_dict())`` is what
``ekm <command> --json`` writes for the same arguments.
"""

from __future__ import annotations

import json


def plain(obj):
    """``obj`` with tuples as lists and NumPy scalars and arrays as Python values (what JSON reads back)."""
    if isinstance(obj, dict):
        return {str(k): plain(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [plain(v) for v in obj]
    if hasattr(obj, "tolist"):  # NumPy and JAX arrays and scalars
        return plain(obj.tolist())
    return obj


class Result:
    """Mixin of the API's results: ``to_dict()`` from ``_dict()``, and ``to_json()``."""

    def _dict(self) -> dict:  # pragma: no cover - every result defines it
        raise NotImplementedError

    def to_dict(self) -> dict:
        """The command line's ``--json`` output for this result, as plain Python values."""
        return plain(self._dict())

    def to_json(self) -> str:
        """``to_dict()`` as the command line writes it (indented, no NaN)."""
        return json.dumps(self.to_dict(), indent=2, allow_nan=False)


def new_axes(ax, size=(6.0, 6.0)):
    """``ax``, or the axes of a new figure (not pyplot's: nothing global is touched) when it is None."""
    if ax is not None:
        return ax
    from matplotlib.figure import Figure

    return Figure(figsize=size, layout="constrained").add_subplot()
