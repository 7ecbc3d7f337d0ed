"""Generated worlds: a benchmark suite of families, each world made from a seed and a difficulty level.

The idea is the BARN navigation benchmark's (Perille et al. 2020): many worlds of graded difficulty, made
by a program rather than by hand, each checked to be solvable and labelled with measures of how hard it
is. ``generate("maze", 7)`` is one world; its name, ``"maze:7"``, is also how
:func:`robots.worldnames.load_world` (and so every ``--world`` option) spells it, so a worker process makes
the same world from the name alone, bit for bit.

- ``difficulty`` (the level D in [0, 1], 0 easy) scales each family's features (turns, traps, density,
  rooms, movers, blockers). Left out, it is drawn uniformly from the seed's generator, so a range of
  seeds spans the difficulties.
- Every world goes through :func:`robots.worldfile.parse_world`, the checker a user's file meets, and
  through :func:`robots.generator.reach.reach`, a grid search independent of the planner: a world without
  a route is never returned (its builder tries again with the next sub-seed). The world's ``difficulty``
  holds the search's measures.
- Coordinates are rounded to 0.1 mm, so the world file is tidy and a world is the same in any process.

A family is one :class:`~robots.generator.family.Family` in :data:`FAMILIES`: the package's are one module each
(``robots/generator/families/NAME.py``, its ``layout`` and its ``FAMILY``); a user's is added with
``ekm.register_family`` or the entry-point group ``ekm.families``. :mod:`robots.generator.build` turns a
layout into a world the same way for every family.
"""

from __future__ import annotations

import re
from ekm.errors import InputError
from robots.generator.family import Family
from robots.registry import NAME, Registry, check_callable


def _built_in() -> tuple[Family, ...]:
    from robots.generator.families import (blocked, clutter, corridor, doors, large, maze, movers, niches, pillars,
                                           shapes, slanted, traffic, traps)

    return tuple(m.FAMILY for m in (corridor, traps, clutter, maze, movers, blocked, niches, traffic, pillars, shapes,
                                    slanted, large, doors))


def _check(family: Family) -> None:
    check_callable("family", family.name, "layout", family.layout)


#: Every family ``ekm worlds --generate``, ``ekm compare --suite`` and ``ekm families`` know, in the order they are
#: listed (:class:`robots.registry.Registry`).
FAMILIES = Registry("family", "families", Family, _built_in, _check)

_SPELLING = re.compile(rf"({NAME.pattern}(?:\+{NAME.pattern})*):([^:]*)(?::([^:]*))?")


def family_of(name: str) -> Family | None:
    """The family ``name``: a registered one, or a combination ``"A+B[+C...]"`` — A's layout with the features of
    B (then C ...) laid over it by their ``overlay`` (``"large+traffic"``: a large world with traffic); None when a
    part is unknown or cannot be laid over."""
    parts = str(name).split("+")
    if not all(p in FAMILIES for p in parts):
        return None
    if len(parts) == 1:
        return FAMILIES[name]
    base, over = FAMILIES[parts[0]], [FAMILIES[p] for p in parts[1:]]
    if any(f.overlay is None for f in over):
        return None

    def layout(rng, level: float):
        made = base.layout(rng, level)
        for f in over:
            made = f.overlay(rng, level, made)
        return made

    return Family(name, layout, f"{base.summary}; with " + "; with ".join(f.summary for f in over))


def no_family(name: str) -> str:
    """Why :func:`family_of` finds no family ``name``, in one line: a part unknown (with the families), or one that
    cannot be laid over another's world (with those that can)."""
    from robots.spelling import did_you_mean

    parts = str(name).split("+")
    unknown = [p for p in parts if p not in FAMILIES]
    if unknown:
        return (f"unknown world family {unknown[0]!r}{did_you_mean(unknown[0], FAMILIES)} "
                f"(families: {', '.join(FAMILIES)})")
    fixed = next(p for p in parts[1:] if FAMILIES[p].overlay is None)
    return (f"{fixed} cannot be laid over another family's world (after a '+' only "
            f"{', '.join(n for n, f in FAMILIES.all().items() if f.overlay)})")


def unknown_family(text: str) -> str | None:
    """:func:`no_family` of ``text`` spelt as a generated world (``FAMILY:SEED[:D]``) whose family is none; None when
    ``text`` is not such a spelling or its family is known."""
    m = _SPELLING.fullmatch(str(text))
    return None if m is None or family_of(m.group(1)) is not None else no_family(m.group(1))


def spelling(family: str, seed: int, difficulty: float | None = None) -> str:
    """The name of a generated world: ``FAMILY:SEED`` or ``FAMILY:SEED:D`` (D as :func:`generate` rounds it)."""
    return f"{family}:{seed}" if difficulty is None else f"{family}:{seed}:{round(float(difficulty), 4):g}"


def parse_spelling(text: str) -> tuple[str, int, float | None] | None:
    """``"maze:7"`` -> ``("maze", 7, None)``, ``"maze:7:0.6"`` -> ``("maze", 7, 0.6)``; None when ``text`` is
    not of the form ``FAMILY:...`` with a known family. A known family with a bad seed or difficulty is an
    :class:`~ekm.errors.InputError` naming the spelling."""
    m = _SPELLING.fullmatch(str(text))
    if m is None or family_of(m.group(1)) is None:
        return None
    family, seed_text, level_text = m.groups()
    if not seed_text.isdigit() or not seed_text.isascii():
        raise InputError(f"{text}: the seed must be a whole number >= 0, got {seed_text!r}")
    if level_text is None:
        return family, int(seed_text), None
    try:
        level = float(level_text)
    except ValueError:
        level = None
    if level is None or not 0.0 <= level <= 1.0:
        raise InputError(f"{text}: the difficulty must be a number in [0, 1], got {level_text!r}")
    return family, int(seed_text), level


def generate(family: str, seed: int, difficulty: float | None = None):
    """The world of ``family`` made from ``seed`` at difficulty level ``difficulty`` (in [0, 1]; None: drawn
    from the seed), a :class:`robots.worldfile.World` named by its spelling, with its
    :class:`~robots.worldfile.Difficulty` filled in. Bad arguments raise :class:`~ekm.errors.InputError`."""
    import numbers

    chosen = family_of(family)
    if chosen is None:
        raise InputError(no_family(family))
    if isinstance(seed, bool) or not isinstance(seed, numbers.Integral) or seed < 0:
        raise InputError(f"{family}: the seed must be a whole number >= 0, got {seed!r}")
    if difficulty is not None and (isinstance(difficulty, bool) or not isinstance(difficulty, numbers.Real)
                                   or not 0.0 <= difficulty <= 1.0):
        raise InputError(f"{family}: the difficulty must be a number in [0, 1], got {difficulty!r}")
    from robots.generator.build import build

    return build(chosen, int(seed), None if difficulty is None else float(difficulty),
                 spelling(family, int(seed), difficulty))
