"""The worlds a user names (every ``--world`` and ``--worlds`` option): the named worlds shipped with the package, a
world file, or a generated world's spelling ``FAMILY:SEED[:D]``. Its own module, above both the world file's
checker (:mod:`robots.worldfile`) and the generator (:mod:`robots.generator`, which uses the checker), so
that neither imports the other's user."""

from __future__ import annotations

from importlib import resources
from pathlib import Path

from ekm.errors import InputError
from robots.worldfile import World, decode, parse_world, read_text


def named_worlds() -> list[str]:
    """Names of the worlds shipped with the package, sorted."""
    files = resources.files("robots.worlds").iterdir()
    return sorted(f.name[:-5] for f in files if f.name.endswith(".json"))


def load_world(name_or_path: str | Path) -> World:
    """Load a named world (``ekm worlds`` lists them), a world file, or a generated world spelt
    ``FAMILY:SEED`` or ``FAMILY:SEED:D`` (``maze:7``, ``maze:7:0.6``; :mod:`robots.generator`), validating
    every key.

    A generated world's name is its spelling, so ``load_world(world.name)`` makes it again, bit for bit:
    a worker process gets a generated world from its name alone.
    """
    text_source = str(name_or_path)
    path = Path(name_or_path)
    if path.suffix != ".json" and not path.exists() and text_source in named_worlds():
        text = resources.files("robots.worlds").joinpath(f"{text_source}.json").read_text()
        source = text_source
    else:
        if not path.exists() and path.suffix != ".json":
            from robots.generator import generate, parse_spelling, unknown_family

            spelt = parse_spelling(text_source)
            if spelt is not None:
                return generate(*spelt)
            why = unknown_family(text_source)
            if why is not None:
                raise InputError(f"{text_source}: {why}")
        if not path.is_file():
            from robots.spelling import did_you_mean

            names = ", ".join(named_worlds())
            close = did_you_mean(text_source, named_worlds())
            raise InputError(f"{text_source}: no such world file or named world{close} (named worlds: {names}; "
                             f"or a generated world, FAMILY:SEED[:DIFFICULTY])")
        text = read_text(path, text_source, "world")
        source = text_source
    return parse_world(decode(text, source), source)
