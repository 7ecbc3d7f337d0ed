"""Worlds in Python: :func:`world` (one, by name or file) and :func:`worlds` (``ekm worlds``)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from ekm.api.result import Result
from ekm.errors import InputError


def world(name_or_path):
    """A named world (``ekm.worlds()`` lists them) or a world file (JSON, DESIGN §2), every key checked:
    a :class:`robots.worldfile.World` (sizes and positions in metres, angles in radians). A bad file
    raises :class:`ekm.errors.InputError` naming the file, the key and what is wrong.

    Example::

        w = ekm.world("concave-obstacle")
        w.size, w.start, w.goal     # (1.2, 0.8), (0.15, 0.4, 0.0): x, y in m, heading in rad; (1.05, 0.4)
    """
    from robots.worldfile import load_world

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
        """Draw each world to scale to ``directory/NAME.png`` (created; each PNG written atomically); returns
        the paths written."""
        import re

        from robots.plot import plot_world, save_figure

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
    from robots.worldfile import named_worlds

    if isinstance(check, (str, Path)):
        check = [check]
    return Worlds(tuple(world(p) for p in (check if check else named_worlds())))
