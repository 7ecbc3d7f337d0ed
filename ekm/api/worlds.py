"""Worlds in Python: :func:`world` (one, by name or file), :func:`worlds` (``ekm worlds``) and
:func:`generate` (``ekm worlds --generate``)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from ekm.api.checks import choice, number, whole
from ekm.api.result import Result
from ekm.errors import InputError

_PROG = "ekm worlds"


def world(name_or_path):
    """A named world (``ekm.worlds()`` lists them), a world file (JSON, docs/design.md §2) or a generated world
    spelt ``FAMILY:SEED[:DIFFICULTY]`` (``"maze:7"``, see :func:`generate`), every key checked:
    a :class:`robots.worldfile.World` (sizes and positions in metres, angles in radians). A bad file
    raises :class:`ekm.errors.InputError` naming the file, the key and what is wrong.

    Example::

        w = ekm.world("concave-obstacle")
        w.size, w.start, w.goal     # (1.2, 0.8), (0.15, 0.4, 0.0): x, y in m, heading in rad; (1.05, 0.4)
    """
    from robots.worldnames import load_world

    if hasattr(name_or_path, "counts"):  # already a World
        return name_or_path
    return load_world(name_or_path)


@dataclass(frozen=True)
class Worlds(Result):
    """Worlds listed or checked by :func:`worlds`: ``items`` the :class:`robots.worldfile.World` of each.
    ``to_dict()`` is ``ekm worlds --json``; ``save_plots(DIR)`` is ``--plot DIR``."""

    items: tuple

    def __len__(self) -> int:
        return len(self.items)

    def __getitem__(self, i):
        return self.items[i]

    def _dict(self) -> dict:
        from ekm.provenance import provenance

        return {"worlds": [w.counts() for w in self.items], **provenance(jax=False)}

    def save_plots(self, directory) -> list[Path]:
        """Draw each world to scale to ``directory/NAME.png`` (created; each PNG written atomically) — or, for
        one world and a path ending in ``.png``, ``.svg`` or ``.pdf``, to that file; returns the paths written."""
        import re

        from ekm.api.checks import PLOT_SUFFIXES, plot_path
        from robots.plot import plot_world, save_figure

        if str(directory).lower().endswith(PLOT_SUFFIXES):
            if len(self.items) != 1:
                raise InputError(f"--plot {directory}: a plot file holds one world, and there are {len(self.items)}; "
                                 f"give a directory")
            out = plot_path(directory, "--plot")
            try:
                return [save_figure(plot_world(self.items[0]).figure, out)]
            except OSError as exc:
                raise InputError(f"--plot {out}: cannot write ({exc.strerror or exc})") from None
        out = Path(directory)
        files = {}
        for w in self.items:
            name = re.sub(r"[^A-Za-z0-9._-]", "_", w.name) + ".png"
            if name in files:
                raise InputError(f"--plot {directory}: {files[name].source} and {w.source} would both be drawn to {name}")
            files[name] = w
        try:
            out.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise InputError(f"--plot {directory}: cannot create the directory ({exc.strerror or exc})") from None
        written = []
        for name, w in files.items():
            try:
                written.append(save_figure(plot_world(w).figure, out / name))
            except OSError as exc:
                raise InputError(f"--plot {out / name}: cannot write ({exc.strerror or exc})") from None
        return written


def worlds(check=None) -> Worlds:
    """The named worlds, or (``check``: a list of world files or names) those worlds, every one validated.

    Returns :class:`Worlds`, whose ``to_dict()`` is ``ekm worlds [--check FILE ...] --json``.

    Example::

        [w.name for w in ekm.worlds()]            # the eight named worlds
        ekm.worlds(check=["my-lab.json"])         # InputError naming the first problem, if any
    """
    from robots.worldnames import named_worlds

    if isinstance(check, (str, Path)):
        check = [check]
    return Worlds(tuple(world(p) for p in (check if check else named_worlds())))


def generate(family: str, seed: int, difficulty: float | None = None):
    """A generated world of ``family`` (``ekm worlds --help`` lists the families) from ``seed`` (int >= 0) at
    ``difficulty`` (in [0, 1], 0 easy; None: drawn from the seed, so a range of seeds spans the levels).

    Returns the :class:`robots.worldfile.World`, named by its spelling (``"maze:7"``, or ``"maze:7:0.6"``
    with a difficulty), so ``ekm.world(w.name)`` and ``--world maze:7`` make it again, bit for bit. Its
    ``difficulty`` holds the level and the measures of a route search independent of the planner (the
    world always has a route): ``narrowest_passage_m``, ``route_length_m``, ``straight_m``, ``route_ratio``,
    ``turns``, ``traps``, ``movers``. Bad arguments raise :class:`ekm.errors.InputError` worded as the
    command line words them.

    Example::

        w = ekm.generate("maze", 7)
        w.name, w.difficulty.level, w.difficulty.route_length_m     # "maze:7", 0.0..1.0, metres
        robots.worldfile.save_world(w, "maze-7.json")               # what --out writes
    """
    from robots.generator import FAMILIES, family_of
    from robots.generator import generate as make

    if family_of(family) is None:  # a family, or a combination A+B (large+traffic)
        choice(family, tuple(FAMILIES), "--generate", _PROG)
    seed = whole(seed, "--seed", _PROG, strict=False)
    if difficulty is not None:
        difficulty = number(difficulty, "--difficulty", _PROG, strict=False)
        if difficulty > 1.0:
            raise InputError(f"{_PROG}: argument --difficulty: must be in [0, 1], got {difficulty:g}")
    return make(family, seed, difficulty)
