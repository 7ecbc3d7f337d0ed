"""Architectures by name, with parameters: ``fusion``, ``fields:form=thesis``, ``fusion:beta=0.6,sensors=long``.

Each architecture is a frozen parameter dataclass (its defaults are the architecture's best documented
variant, as ``ekm train`` runs the signed chart by default) and a ``build(params, map, cfg, robot)``
that returns a :class:`~robots.controllers.base.Controller`. :func:`parse_architectures` reads the
command line's spelling — architectures separated by commas, each ``NAME[:k=v[,k=v…]]``; a ``k=v`` after
a comma continues the architecture before it — and every unknown name, unknown parameter or bad value
is an :class:`~ekm.errors.InputError` with one line naming it, before anything runs.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace
from typing import Any, Callable

from ekm.errors import InputError
from robots.controllers import fields as neural_fields
from robots.controllers import fusion
from robots.controllers import samba
from robots.controllers import schema as motor_schemas
from robots.controllers import damn, deliberation, subsumption


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
ARCHITECTURES: dict[str, Architecture] = {
    "fusion": Architecture("fusion", fusion.FusionParams, fusion.build,
                           "command fusion: indirect EKM + Braitenberg type-3C avoidance (ch. 4.5)", fusion.DEFAULT_CHART,
                           encoding="continuous"),
    "fields": Architecture("fields", neural_fields.FieldParams, neural_fields.build,
                           "dynamic neural fields: cooperative EKMs (ch. 5)", neural_fields.DEFAULT_CHART,
                           charts=("signed", "polar"), encoding="continuous"),
    "samba": Architecture("samba", samba.SambaParams, samba.build,
                          "Samba action maps: MAV(Goto, filtered Avoid), heaviest action (Riekki 1999)", None,
                          encoding="discrete"),
    "schema": Architecture("schema", motor_schemas.SchemaParams, motor_schemas.build,
                           "motor schemas: move-to-goal + avoid-obstacle + noise vectors, summed (Arkin ch. 4.4)", None,
                           encoding="continuous"),
    "subsumption": Architecture("subsumption", subsumption.SubsumptionParams, subsumption.build,
                                "subsumption: layered behaviours, suppression and inhibition, 9 responses "
                                "(Brooks; Arkin 4.3)", None, encoding="discrete"),
    "damn": Architecture("damn", damn.DamnParams, damn.build,
                         "DAMN: behaviours vote over 9 turns and 6 speeds, two winner-take-all arbiters "
                         "(Rosenblatt; Arkin 4.5.5)", None, encoding="discrete"),
    "deliberation": Architecture("deliberation", deliberation.DeliberationParams, deliberation.build,
                                 "reactive deliberation: behaviours bid for one action schema, the deliberator "
                                 "interrupts (Sahota ch. 3)", None, encoding="discrete"),
}

#: The entry-point group through which an installed package adds architectures: each entry point names an
#: :class:`Architecture` (or a function without arguments that returns one).
ENTRY_POINTS = "ekm.architectures"

_ADDED: dict[str, Architecture] = {}
_FROM_ENTRY_POINTS: set[str] = set()
_LOADED = False


def register(arch: Architecture) -> Architecture:
    """Add ``arch`` under its name (or replace an architecture added before under that name), so that
    :func:`parse_architectures`, ``ekm run``, ``ekm compare`` and ``ekm architectures`` know it. Its
    parameters are checked as the built-in ones are; a built-in name cannot be taken."""
    import dataclasses
    import re

    if not isinstance(arch, Architecture):
        raise InputError(f"register_architecture: expected an Architecture, got {type(arch).__name__}")
    if not re.fullmatch(r"[a-z][a-z0-9_-]*", arch.name or ""):
        raise InputError(f"architecture {arch.name!r}: a name is lower-case letters, digits, '-' and '_', "
                         f"starting with a letter")
    if arch.name in ARCHITECTURES:
        raise InputError(f"architecture {arch.name!r}: the name of a built-in architecture")
    if not (dataclasses.is_dataclass(arch.params) and isinstance(arch.params, type)):
        raise InputError(f"architecture {arch.name}: params must be a dataclass (its parameters), "
                         f"got {arch.params!r}")
    try:
        defaults = arch.params()
        hash(defaults)
    except TypeError as exc:
        raise InputError(f"architecture {arch.name}: params must be a frozen dataclass whose every field has a "
                         f"default ({exc})") from None
    if not callable(arch.build):
        raise InputError(f"architecture {arch.name}: build must be callable")
    from ekm.config import CHARTS

    if arch.encoding not in ENCODINGS:
        raise InputError(f"architecture {arch.name}: encoding must be one of {', '.join(map(str, ENCODINGS))}, "
                         f"got {arch.encoding!r}")
    for chart in (arch.default_chart, *arch.charts):
        if chart is not None and chart not in CHARTS:
            raise InputError(f"architecture {arch.name}: chart must be one of {', '.join(CHARTS)}, got {chart!r}")
    _ADDED[arch.name] = arch
    return arch


def registry() -> dict[str, Architecture]:
    """Every architecture by name: the built-in ones, then those of installed packages' entry points
    (:data:`ENTRY_POINTS`, loaded once), then those added with :func:`register`."""
    global _LOADED
    if not _LOADED:
        _LOADED = True
        _load_entry_points()
    return {**ARCHITECTURES, **_ADDED}


def _load_entry_points() -> None:
    from importlib.metadata import entry_points

    for ep in entry_points(group=ENTRY_POINTS):
        where = f"entry point {ep.name!r} ({ep.value}) of group {ENTRY_POINTS}"
        try:
            found = ep.load()
            arch = found() if callable(found) and not isinstance(found, Architecture) else found
        except Exception as exc:
            raise InputError(f"{where}: cannot load ({type(exc).__name__}: {exc})") from None
        if not isinstance(arch, Architecture):
            raise InputError(f"{where}: names {type(arch).__name__}, not an ekm Architecture")
        if arch.name in _ADDED:
            continue  # registered in this process already (a worker given it by its job)
        try:
            register(arch)
        except InputError as exc:
            raise InputError(f"{where}: {exc}") from None
        _FROM_ENTRY_POINTS.add(arch.name)


def added_here() -> set[str]:
    """The names added with :func:`register` in this process (not through entry points)."""
    return set(_ADDED) - _FROM_ENTRY_POINTS


def added(name: str) -> Architecture | None:
    """The architecture added under ``name`` (not a built-in one), for a comparison's workers."""
    return _ADDED.get(name)


@dataclass(frozen=True)
class ArchitectureSpec:
    """An architecture with resolved parameters; ``str(spec)`` spells every parameter (``fusion:sensors=short,…``)."""

    name: str
    params: Any

    def __str__(self) -> str:
        return spell(self.name, self.params)

    @property
    def label(self) -> str:
        """Only the parameters that differ from the defaults (``fusion:beta=0.6``, or just ``fusion``)."""
        return spell(self.name, self.params, registry()[self.name].params())

    def with_params(self, **overrides) -> "ArchitectureSpec":
        """The same architecture with some parameters replaced (values already typed)."""
        try:
            return ArchitectureSpec(self.name, replace(self.params, **overrides))
        except (TypeError, ValueError) as exc:
            raise InputError(f"architecture {self.name}: {exc}") from None

    @property
    def default_chart(self) -> str | None:
        """The chart of the shipped map this architecture drives when no map is given (None: it needs none)."""
        return registry()[self.name].default_chart

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
        charts = registry()[self.name].charts
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
        arch = registry()[self.name]
        kwargs = {} if robot is None else {"robot": robot}
        return arch.build(self.params, ekm, cfg, spec=str(self), **kwargs)


def _show(value) -> str:
    return repr(value) if isinstance(value, float) and not value.is_integer() else (
        f"{value:g}" if isinstance(value, float) else str(value))


def spell(name: str, params, default=None) -> str:
    """``name:k=v,…`` with every parameter of ``params`` — or, given the ``default`` parameters, only those
    that differ from them (just ``name`` if none does): how the command line spells a named thing."""
    values = [f"{f.name}={_show(getattr(params, f.name))}" for f in fields(params)
              if default is None or getattr(params, f.name) != getattr(default, f.name)]
    return f"{name}:{','.join(values)}" if values else name


def parse_named(text: str, what: str, names, make) -> list:
    """Read ``N1[:k=v,...],N2,...`` — a ``k=v`` after a comma continues the item before it — into
    ``make(name, {k: v})`` for each item; ``what`` ("architecture", "player") names the kind in every error and
    ``names`` are the known ones, for the error of an empty text. Raises :class:`InputError` on any fault."""
    if not text or not text.strip():
        raise InputError(f"{what}: empty (choose from " + ", ".join(names) + ")")
    groups: list[tuple[str, list[str]]] = []
    for token in (t.strip() for t in text.split(",")):
        if not token:
            raise InputError(f"{what} {text!r}: empty item between commas")
        head, sep, rest = token.partition(":")
        if sep or "=" not in token:
            if sep and not rest.strip():
                raise InputError(f"{what} {token!r}: nothing after ':' (expected k=v)")
            groups.append((head.strip(), [rest.strip()] if rest.strip() else []))
        elif groups:
            groups[-1][1].append(token)
        else:
            raise InputError(f"{what} {text!r}: parameter {token!r} before any {what} name")
    items = []
    for name, kvs in groups:
        values: dict[str, str] = {}
        for key, value in (_pair(what, name, kv) for kv in kvs):
            if key in values:
                raise InputError(f"{what} {name}: parameter {key!r} given twice")
            values[key] = value
        items.append(make(name, values))
    return items


def parse_one(text: str, what: str, parse):
    """Exactly one item of ``parse(text)`` (``ekm run --architecture``, ``ekm match A B``)."""
    items = parse(text)
    if len(items) != 1:
        raise InputError(f"{what} {text!r}: expected one {what}, got {len(items)}")
    return items[0]


def parse_architectures(text: str) -> list[ArchitectureSpec]:
    """Read ``A1[:k=v,...],A2,...`` (see the module docstring); raises :class:`InputError` on any fault."""
    return parse_named(text, "architecture", registry(), make_spec)


def parse_architecture(text: str) -> ArchitectureSpec:
    """Exactly one architecture (``ekm run``)."""
    return parse_one(text, "architecture", parse_architectures)


def _pair(what: str, name: str, kv: str) -> tuple[str, str]:
    key, sep, value = kv.partition("=")
    if not sep or not key.strip() or not value.strip():
        raise InputError(f"{what} {name}: {kv!r} is not k=v")
    return key.strip(), value.strip()


def make_spec(name: str, values: dict[str, str]) -> ArchitectureSpec:
    """The :class:`ArchitectureSpec` of ``name`` with parameters given as text (``{"beta": "0.6"}``)."""
    known_architectures = registry()
    if name not in known_architectures:
        raise InputError(f"architecture {name!r}: unknown (choose from {', '.join(known_architectures)}; "
                         f"ekm architectures describes them)")
    return ArchitectureSpec(name, typed_params("architecture", name, known_architectures[name].params, values))


def typed_params(what: str, name: str, cls, values: dict[str, str]):
    """``cls(**values)`` with each text value read as its field's type (float, int, bool, one of its choices);
    an unknown parameter, a bad value or one ``cls`` refuses is one :class:`InputError` line naming it."""
    known = {f.name: f for f in fields(cls)}
    typed = {}
    for key, text in values.items():
        if key not in known:
            raise InputError(f"{what} {name}: unknown parameter {key!r} (known: {', '.join(known)})")
        typed[key] = _typed(name, known[key], text, what)
    try:
        return cls(**typed)
    except ValueError as exc:
        raise InputError(f"{what} {name}: {exc}") from None


def _typed(name: str, f, text: str, what: str = "architecture"):
    kind = f.type if isinstance(f.type, str) else f.type.__name__
    choices = f.metadata.get("choices")
    where = f"{what} {name}: {f.name}"
    if choices:
        if text not in choices:
            raise InputError(f"{where}: must be one of {', '.join(choices)}, got {text!r}")
        return text
    if kind == "float":
        try:
            value = float(text)
        except ValueError:
            raise InputError(f"{where}: must be a number, got {text!r}") from None
        if not math.isfinite(value):
            raise InputError(f"{where}: must be finite, got {text!r}")
        return value
    if kind == "int":
        try:
            return int(text)
        except ValueError:
            raise InputError(f"{where}: must be a whole number, got {text!r}") from None
    if kind == "bool":
        if text.lower() in ("1", "true", "yes", "on"):
            return True
        if text.lower() in ("0", "false", "no", "off"):
            return False
        raise InputError(f"{where}: must be true or false, got {text!r}")
    return text


def describe_parameters(name: str) -> list[dict]:
    """Every parameter of ``name`` as ``{name, type, default, choices, help}`` (``ekm architectures``, docs)."""
    return describe_fields(registry()[name].params)


def describe_fields(cls) -> list[dict]:
    """Every field of the parameter dataclass ``cls`` as ``{name, type, default, choices, help}``."""
    out = []
    for f in fields(cls):
        kind = f.type if isinstance(f.type, str) else f.type.__name__
        out.append({"name": f.name, "type": kind, "default": _show(f.default),
                    "choices": list(f.metadata.get("choices", ())) or None, "help": f.metadata.get("help", "")})
    return out
