"""What a family of generated worlds is (:class:`Family`): its own module, so that the families' modules, which
each make one, and the package, which lists them in :data:`robots.generator.FAMILIES`, import it without
importing each other."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable


@dataclass(frozen=True)
class Family:
    """A family of generated worlds: ``layout(rng, level)`` draws one world's document from a NumPy generator and a
    difficulty level in [0, 1] and returns a :class:`robots.generator.layout.Layout` (or raises
    :class:`~robots.generator.layout.Retry` to be called again with the next sub-seed); ``summary``: one line,
    what it makes. :func:`robots.generator.build.build` does the rest, the same for every family."""

    name: str
    layout: Callable[..., Any]
    summary: str
    #: ``overlay(rng, level, layout) -> Layout``: this family's features added to another family's layout, so that
    #: ``"large+traffic:7"`` is a large world with traffic (:func:`family_of`); None: the family cannot be laid over.
    overlay: Callable[..., Any] | None = None
