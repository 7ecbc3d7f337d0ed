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


@dataclass(frozen=True)
class Architecture:
    """A named architecture: its parameter class, its builder, a one-line summary and the chart of the
    shipped map it drives when no map is given (:mod:`ekm.data`) — None for an architecture that drives
    no EKM (its ``build`` then gets ``ekm=None, cfg=None``)."""

    name: str
    params: type
    build: Callable[..., Any]
    summary: str
    default_chart: str | None


ARCHITECTURES: dict[str, Architecture] = {
    "fusion": Architecture("fusion", fusion.FusionParams, fusion.build,
                           "command fusion: indirect EKM + Braitenberg type-3C avoidance (ch. 4.5)", fusion.DEFAULT_CHART),
    "fields": Architecture("fields", neural_fields.FieldParams, neural_fields.build,
                           "dynamic neural fields: cooperative EKMs (ch. 5)", neural_fields.DEFAULT_CHART),
    "samba": Architecture("samba", samba.SambaParams, samba.build,
                          "Samba action maps: MAV(Goto, filtered Avoid), heaviest action (Riekki 1999)", None),
    "schema": Architecture("schema", motor_schemas.SchemaParams, motor_schemas.build,
                           "motor schemas: move-to-goal + avoid-obstacle + noise vectors, summed (Arkin ch. 4.4)", None),
}


@dataclass(frozen=True)
class ArchitectureSpec:
    """An architecture with resolved parameters; ``str(spec)`` spells every parameter (``fusion:sensors=short,…``)."""

    name: str
    params: Any

    def __str__(self) -> str:
        values = ",".join(f"{f.name}={_show(getattr(self.params, f.name))}" for f in fields(self.params))
        return f"{self.name}:{values}" if values else self.name

    @property
    def label(self) -> str:
        """Only the parameters that differ from the defaults (``fusion:beta=0.6``, or just ``fusion``)."""
        default = ARCHITECTURES[self.name].params()
        changed = [f"{f.name}={_show(getattr(self.params, f.name))}" for f in fields(self.params)
                   if getattr(self.params, f.name) != getattr(default, f.name)]
        return f"{self.name}:{','.join(changed)}" if changed else self.name

    def with_params(self, **overrides) -> "ArchitectureSpec":
        """The same architecture with some parameters replaced (values already typed)."""
        try:
            return ArchitectureSpec(self.name, replace(self.params, **overrides))
        except (TypeError, ValueError) as exc:
            raise InputError(f"architecture {self.name}: {exc}") from None

    @property
    def default_chart(self) -> str | None:
        """The chart of the shipped map this architecture drives when no map is given (None: it needs none)."""
        return ARCHITECTURES[self.name].default_chart

    @property
    def uses_map(self) -> bool:
        """Whether this architecture drives an EKM (command fusion and neural fields do)."""
        return self.default_chart is not None

    def build(self, ekm=None, cfg=None, robot=None):
        """The ready :class:`~robots.controllers.base.Controller` for one trial's indirect map ``ekm`` (None for
        an architecture that drives no map)."""
        if self.uses_map and (cfg is None or cfg.mapping != "indirect"):
            got = "no map" if cfg is None else f"a {cfg.mapping} map"
            raise InputError(f"architecture {self.name}: needs an indirect map (Eq. 4.5), got {got}")
        arch = ARCHITECTURES[self.name]
        kwargs = {} if robot is None else {"robot": robot}
        return arch.build(self.params, ekm, cfg, spec=str(self), **kwargs)


def _show(value) -> str:
    return repr(value) if isinstance(value, float) and not value.is_integer() else (
        f"{value:g}" if isinstance(value, float) else str(value))


def parse_architectures(text: str) -> list[ArchitectureSpec]:
    """Read ``A1[:k=v,...],A2,...`` (see the module docstring); raises :class:`InputError` on any fault."""
    if not text or not text.strip():
        raise InputError("architecture: empty (choose from " + ", ".join(ARCHITECTURES) + ")")
    groups: list[tuple[str, list[str]]] = []
    for token in (t.strip() for t in text.split(",")):
        if not token:
            raise InputError(f"architecture {text!r}: empty item between commas")
        head, sep, rest = token.partition(":")
        if sep or "=" not in token:
            groups.append((head.strip(), [rest.strip()] if rest.strip() else []))
            if sep and not rest.strip():
                raise InputError(f"architecture {token!r}: nothing after ':' (expected k=v)")
        elif groups:
            groups[-1][1].append(token)
        else:
            raise InputError(f"architecture {text!r}: parameter {token!r} before any architecture name")
    return [make_spec(name, dict(_pair(name, kv) for kv in kvs)) for name, kvs in groups]


def parse_architecture(text: str) -> ArchitectureSpec:
    """Exactly one architecture (``ekm run``)."""
    specs = parse_architectures(text)
    if len(specs) != 1:
        raise InputError(f"architecture {text!r}: expected one architecture, got {len(specs)}")
    return specs[0]


def _pair(name: str, kv: str) -> tuple[str, str]:
    key, sep, value = kv.partition("=")
    if not sep or not key.strip() or not value.strip():
        raise InputError(f"architecture {name}: {kv!r} is not k=v")
    return key.strip(), value.strip()


def make_spec(name: str, values: dict[str, str]) -> ArchitectureSpec:
    """The :class:`ArchitectureSpec` of ``name`` with parameters given as text (``{"beta": "0.6"}``)."""
    if name not in ARCHITECTURES:
        raise InputError(f"architecture {name!r}: unknown (choose from {', '.join(ARCHITECTURES)})")
    cls = ARCHITECTURES[name].params
    known = {f.name: f for f in fields(cls)}
    typed = {}
    for key, text in values.items():
        if key in typed:
            raise InputError(f"architecture {name}: parameter {key!r} given twice")
        if key not in known:
            raise InputError(f"architecture {name}: unknown parameter {key!r} (known: {', '.join(known)})")
        typed[key] = _typed(name, known[key], text)
    try:
        return ArchitectureSpec(name, cls(**typed))
    except ValueError as exc:
        raise InputError(f"architecture {name}: {exc}") from None


def _typed(name: str, f, text: str):
    kind = f.type if isinstance(f.type, str) else f.type.__name__
    choices = f.metadata.get("choices")
    where = f"architecture {name}: {f.name}"
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


def describe_parameters(name: str) -> list[tuple[str, str, str]]:
    """``(parameter, default, help)`` of every parameter of ``name`` (for ``--help`` texts and docs)."""
    return [(f.name, _show(f.default), f.metadata.get("help", "")) for f in fields(ARCHITECTURES[name].params)]
