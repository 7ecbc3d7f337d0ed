"""Architectures by name, with parameters: ``fusion``, ``fields:form=thesis``, ``fusion:beta=0.6,sensors=long``.

Each architecture is a frozen parameter dataclass (its defaults are the architecture's best documented
variant, as ``ekm train`` runs the signed chart by default) and a ``build(params, map, cfg, robot)``
that returns a :class:`~robots.controllers.base.Controller`, kept in :data:`ARCHITECTURES` (the package's,
an installed package's through the entry-point group ``ekm.architectures``, or one added with
``ekm.register_architecture``: :mod:`robots.registry`). :func:`parse_architectures` reads the command line's
spelling (:mod:`robots.spelling`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable

from ekm.errors import InputError
from robots.controllers import fields as neural_fields
from robots.controllers import fusion
from robots.controllers import samba
from robots.controllers import schema as motor_schemas
from robots.controllers import damn, deliberation, subsumption
from robots.registry import Registry, check_callable, check_params
from robots.spelling import Spec


@dataclass(frozen=True)
class Architecture:
    """A named architecture: its parameter class, its builder, a one-line summary and the chart of the
    shipped map it drives when no map is given (:mod:`ekm.data`) — None for an architecture that drives
    no EKM (its ``build`` then gets ``ekm=None, cfg=None``). ``charts``: the charts of the maps it drives
    correctly (default: only ``default_chart``); a map of another chart is refused.

    ``encoding``: how it encodes its response (Arkin §3.3) — ``continuous`` (a command from a continuous
    function of what it senses), ``discrete`` (one of a prespecified set of responses) — or None (not said).

    ``params`` is a frozen dataclass whose every field has a default; a field's ``metadata`` may hold
    ``help`` (one line, with the unit) and ``choices`` (the allowed values of a text parameter).
    ``build(params, ekm, cfg, spec=…, robot=…)`` returns a :class:`~robots.controllers.base.Controller`.
    """

    name: str
    params: type
    build: Callable[..., Any]
    summary: str
    default_chart: str | None = None
    charts: tuple = ()
    encoding: str | None = None

    def __post_init__(self):
        if not self.charts and self.default_chart is not None:
            object.__setattr__(self, "charts", (self.default_chart,))


#: How an architecture may encode its response (:attr:`Architecture.encoding`).
ENCODINGS = ("continuous", "discrete", None)

#: The architectures of the package, in the order ``ekm architectures`` lists them.
BUILT_IN = (
    Architecture("fusion", fusion.FusionParams, fusion.build,
                 "command fusion: indirect EKM + Braitenberg type-3C avoidance (ch. 4.5)", fusion.DEFAULT_CHART,
                 encoding="continuous"),
    Architecture("fields", neural_fields.FieldParams, neural_fields.build,
                 "dynamic neural fields: cooperative EKMs (ch. 5)", neural_fields.DEFAULT_CHART,
                 charts=("signed", "polar"), encoding="continuous"),
    Architecture("samba", samba.SambaParams, samba.build,
                 "Samba action maps: MAV(Goto, filtered Avoid), heaviest action (Riekki 1999)", None,
                 encoding="discrete"),
    Architecture("schema", motor_schemas.SchemaParams, motor_schemas.build,
                 "motor schemas: move-to-goal + avoid-obstacle + noise vectors, summed (Arkin ch. 4.4)", None,
                 encoding="continuous"),
    Architecture("subsumption", subsumption.SubsumptionParams, subsumption.build,
                 "subsumption: layered behaviours, suppression and inhibition, 9 responses (Brooks; Arkin 4.3)",
                 None, encoding="discrete"),
    Architecture("damn", damn.DamnParams, damn.build,
                 f"DAMN: behaviours vote over {damn.DamnParams.turns} headings and {damn.DamnParams.speeds} speeds, "
                 "two winner-take-all arbiters (Rosenblatt; Arkin 4.5.5)", None, encoding="discrete"),
    Architecture("deliberation", deliberation.DeliberationParams, deliberation.build,
                 "reactive deliberation: behaviours bid for one action schema, the deliberator interrupts "
                 "(Sahota ch. 3)", None, encoding="discrete"),
)


def _check(arch: Architecture) -> None:
    """An added architecture's parameters, build, encoding and charts, checked as the built-in ones are."""
    from ekm.config import CHARTS

    check_params("architecture", arch.name, arch.params)
    check_callable("architecture", arch.name, "build", arch.build)
    if arch.encoding not in ENCODINGS:
        raise InputError(f"architecture {arch.name}: encoding must be one of {', '.join(map(str, ENCODINGS))}, "
                         f"got {arch.encoding!r}")
    for chart in (arch.default_chart, *arch.charts):
        if chart is not None and chart not in CHARTS:
            raise InputError(f"architecture {arch.name}: chart must be one of {', '.join(CHARTS)}, got {chart!r}")


#: Every architecture ``ekm run``, ``ekm compare`` and ``ekm architectures`` know (:class:`robots.registry.Registry`).
ARCHITECTURES = Registry("architecture", "architectures", Architecture, lambda: BUILT_IN, _check)


class ArchitectureSpec(Spec):
    """An architecture with resolved parameters; ``str(spec)`` spells every parameter (``fusion:sensors=short,…``)."""

    registry = ARCHITECTURES

    @property
    def default_chart(self) -> str | None:
        """The chart of the shipped map this architecture drives when no map is given (None: it needs none)."""
        return ARCHITECTURES[self.name].default_chart

    @property
    def uses_map(self) -> bool:
        """Whether this architecture drives an EKM (command fusion and neural fields do)."""
        return self.default_chart is not None

    def check_map(self, cfg, source: str = "the map") -> None:
        """Refuse, in one line, a map this architecture does not drive correctly: none, a direct one, or one
        of a chart it does not take (saying which it needs and how to train one)."""
        if cfg is None or cfg.mapping != "indirect":
            got = "no map" if cfg is None else f"a {cfg.mapping} map"
            raise InputError(f"architecture {self.name}: needs an indirect map (Eq. 4.5), got {got}")
        charts = ARCHITECTURES[self.name].charts
        if cfg.chart not in charts:
            need = charts[0]
            raise InputError(f"architecture {self.name}: drives a {' or '.join(charts)}-chart map and {source} is "
                             f"{cfg.chart}-chart; train one with: ekm train --mapping indirect --chart {need} "
                             f"--out {need}.npz (or give no --map: the shipped {need}-chart map)")

    def build(self, ekm=None, cfg=None, robot=None):
        """The ready :class:`~robots.controllers.base.Controller` for one trial's indirect map ``ekm`` (None for
        an architecture that drives no map)."""
        if self.uses_map:
            self.check_map(cfg)
        arch = ARCHITECTURES[self.name]
        kwargs = {} if robot is None else {"robot": robot}
        return arch.build(self.params, ekm, cfg, spec=str(self), **kwargs)


#: Read ``A1[:k=v,...],A2,...`` into :class:`ArchitectureSpec` s (the command line's spelling, :mod:`robots.spelling`).
parse_architectures = ArchitectureSpec.parse
#: Exactly one architecture (``ekm run``).
parse_architecture = ArchitectureSpec.parse_one
