"""Maps that ship with the package, so that ``ekm run`` and ``ekm compare`` need no training step.

Both were made by the project's own command line with its defaults (training seed 0, 5 trials of
100,000 steps; ch. 6.1 figures in the README)::

    ekm train --mapping indirect --out ekm/data/indirect-signed.npz
    ekm train --mapping indirect --chart polar --out ekm/data/indirect-polar.npz

They were trained before training's slip-noise draws (:func:`training.online.draw_noise`) and the last
bits of its arithmetic were changed to make training faster: ``ekm train`` with the same defaults now
makes maps of the same quality (README), not the same bits. They are kept, so that every scenario figure
in the README and docs still comes from the maps that ship.

Each architecture drives the chart it does best with (``DEFAULT_CHART`` of its module in
:mod:`robots.controllers`); ``--map`` replaces it with any map file.
"""

from __future__ import annotations

import dataclasses
import functools
from importlib import resources

from ekm.config import CHARTS


def default_map(chart: str):
    """The shipped indirect map file (a ``Traversable``) trained in ``chart`` (``"signed"`` or ``"polar"``)."""
    if chart not in CHARTS:
        raise ValueError(f"no shipped map for chart {chart!r} (charts: {', '.join(CHARTS)})")
    return resources.files("ekm.data").joinpath(f"indirect-{chart}.npz")


def load_default_map(chart: str):
    """:func:`ekm.mapfile.load_maps` of :func:`default_map`, read and checked once per process, since
    ``ekm compare`` drives a shipped map in every run. The maps are JAX arrays, which cannot change; the
    metadata is a fresh copy on each call."""
    saved = _load_default_map(chart)
    return dataclasses.replace(saved, meta=dict(saved.meta))


@functools.cache
def _load_default_map(chart: str):
    from ekm.mapfile import load_maps

    with resources.as_file(default_map(chart)) as path:
        return load_maps(path)
