"""Named things with parameters, spelt as the command line spells them: ``NAME[:k=v[,k=v…]]``, several separated by
commas (``fusion:beta=0.6,sensors=long,fields``; a ``k=v`` after a comma continues the item before it).

A :class:`Spec` is a registered thing (:mod:`robots.registry`) with its parameters resolved: an architecture's
(:class:`robots.controllers.spec.ArchitectureSpec`) or a soccer player's (:class:`robots.soccer.roster.PlayerSpec`).
Every unknown name, unknown parameter or bad value is an :class:`~ekm.errors.InputError` with one line naming
it, before anything runs.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace
from typing import Any, ClassVar

from ekm.errors import InputError


@dataclass(frozen=True)
class Spec:
    """A thing of :attr:`registry` with resolved parameters; ``str(spec)`` spells every parameter
    (``fusion:sensors=short,…``), :attr:`label` only those that differ from the defaults."""

    name: str
    params: Any
    registry: ClassVar = None  # the kind's robots.registry.Registry, set by each subclass

    def __str__(self) -> str:
        return spell(self.name, self.params)

    @property
    def label(self) -> str:
        """Only the parameters that differ from the defaults (``fusion:beta=0.6``, or just ``fusion``)."""
        return spell(self.name, self.params, self.registry[self.name].params())

    def with_params(self, **overrides):
        """The same thing with some parameters replaced (values already typed)."""
        try:
            return type(self)(self.name, replace(self.params, **overrides))
        except (TypeError, ValueError) as exc:
            raise InputError(f"{self.registry.kind} {self.name}: {exc}") from None

    @classmethod
    def make(cls, name: str, values: dict[str, str]):
        """The spec of ``name`` with parameters given as text (``{"beta": "0.6"}``)."""
        kind = cls.registry.kind
        return cls(name, typed_params(kind, name, cls.registry[name].params, values))

    @classmethod
    def parse(cls, text: str) -> list:
        """Read ``N1[:k=v,...],N2,...`` (the module docstring); raises :class:`InputError` on any fault."""
        return parse_named(text, cls.registry.kind, cls.registry.all(), cls.make)

    @classmethod
    def parse_one(cls, text: str):
        """Exactly one item (``ekm run --architecture``, ``ekm match A B``)."""
        return parse_one(text, cls.registry.kind, cls.parse)


def _show(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"  # as the command line spells them (:func:`_typed` reads either)
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


def did_you_mean(name, names) -> str:
    """``"; did you mean 'fields'?"`` — the known name closest to a misspelt ``name`` (:mod:`difflib`'s ratio at
    least 0.6) — or "" when none is close: what every "unknown" line of a name adds (architectures, players,
    families, learning rules, worlds, robots)."""
    import difflib

    close = difflib.get_close_matches(str(name), [str(n) for n in names], n=1, cutoff=0.6)
    return f"; did you mean {close[0]!r}?" if close else ""


def parse_one(text: str, what: str, parse):
    """Exactly one item of ``parse(text)`` (``ekm run --architecture``, ``ekm match A B``)."""
    items = parse(text)
    if len(items) != 1:
        raise InputError(f"{what} {text!r}: expected one {what}, got {len(items)}")
    return items[0]


def _pair(what: str, name: str, kv: str) -> tuple[str, str]:
    key, sep, value = kv.partition("=")
    if not sep or not key.strip() or not value.strip():
        raise InputError(f"{what} {name}: {kv!r} is not k=v")
    return key.strip(), value.strip()


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


def describe_fields(cls) -> list[dict]:
    """Every field of the parameter dataclass ``cls`` as ``{name, type, default, choices, help}``."""
    out = []
    for f in fields(cls):
        kind = f.type if isinstance(f.type, str) else f.type.__name__
        out.append({"name": f.name, "type": kind, "default": _show(f.default),
                    "choices": list(f.metadata.get("choices", ())) or None, "help": f.metadata.get("help", "")})
    return out
