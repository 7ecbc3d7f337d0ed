"""Everything a user can add — architectures, soccer players, world families, robots — kept one way: a
:class:`Registry` per kind, made in one call beside the kind's class (docs/design.md §1, "How to add a thing").

A thing of any kind is a frozen dataclass with a ``name`` and a one-line ``summary`` (:class:`Architecture
<robots.controllers.spec.Architecture>`, :class:`Player <robots.soccer.roster.Player>`, :class:`Family
<robots.generator.Family>`, :class:`RobotParams <robots.params.RobotParams>`). A registry holds, in this order,
the package's own (built in), those of installed packages — the entry-point group ``ekm.<kinds>``, each entry
point naming a thing or a function without arguments that returns one, loaded once on first use — and those
added in this process with
:meth:`Registry.register`. A built-in name cannot be taken; registering a name again replaces what was added
under it. ``ekm.register_<kind>`` adds one, ``ekm <kinds>`` lists them (:mod:`ekm.api.catalogue`).

Worker processes learn what was added in the parent from their jobs: :func:`added_here` is what a job
carries, :func:`adopt` registers it in the worker.
"""

from __future__ import annotations

import re
from typing import Any, Callable, Iterable

from ekm.errors import InputError

#: A name: lower-case letters, digits, ``-`` and ``_``, starting with a letter.
NAME = re.compile(r"[a-z][a-z0-9_-]*")

#: Every registry made, in the order made.
KINDS: list[Registry] = []


class Registry:
    """The things of one ``kind`` (``"architecture"``), listed by ``ekm <plural>``, added by the entry-point group
    ``ekm.<plural>``. ``cls``: the class every thing is an instance of; ``built_in()``: the package's own, in the
    order they are listed (called once, on first use, so that nothing is imported before it is needed);
    ``check(thing)``: the kind's own checks, raising :class:`InputError` in one line."""

    def __init__(self, kind: str, plural: str, cls: type, built_in: Callable[[], Iterable[Any]],
                 check: Callable[[Any], None] | None = None):
        self.kind, self.plural, self.cls = kind, plural, cls
        self.group = f"ekm.{plural}"
        self._built_in_fn, self._check = built_in, check
        self._built_in: dict[str, Any] | None = None
        self._added: dict[str, Any] = {}
        self._from_entry_points: set[str] = set()
        self._loaded = False
        KINDS.append(self)

    def built_in(self) -> dict[str, Any]:
        """The package's own, by name."""
        if self._built_in is None:
            self._built_in = {thing.name: thing for thing in self._built_in_fn()}
        return self._built_in

    def register(self, thing):
        """Add ``thing`` under its name (or replace what was added before under it), checked as the built-in ones
        are; returns it."""
        if not isinstance(thing, self.cls):
            raise InputError(f"register_{self.kind}: expected {_a(self.cls.__name__)}, got {type(thing).__name__}")
        if not NAME.fullmatch(thing.name or ""):
            raise InputError(f"{self.kind} {thing.name!r}: a name is lower-case letters, digits, '-' and '_', "
                             f"starting with a letter")
        if thing.name in self.built_in():
            raise InputError(f"{self.kind} {thing.name!r}: the name of a built-in {self.kind}")
        if self._check is not None:
            self._check(thing)
        self._added[thing.name] = thing
        self._from_entry_points.discard(thing.name)
        return thing

    def all(self) -> dict[str, Any]:
        """Every thing by name: the built-in ones, then those of installed packages, then those added here."""
        if not self._loaded:
            self._loaded = True
            self._load_entry_points()
        return {**self.built_in(), **self._added}

    def names(self) -> list[str]:
        return list(self.all())

    def __iter__(self):
        return iter(self.names())

    def __len__(self) -> int:
        return len(self.all())

    def __contains__(self, name) -> bool:
        return name in self.all()

    def __getitem__(self, name: str):
        """The thing called ``name``, or an :class:`InputError` that names the known ones."""
        known = self.all()
        if name not in known:
            from robots.spelling import did_you_mean

            raise InputError(f"{self.kind} {name!r}: unknown{did_you_mean(name, known)} (choose from "
                             f"{', '.join(known)}; ekm {self.plural} describes them)")
        return known[name]

    def origin(self, name: str) -> str:
        """``"built in"``, ``"entry point"`` (an installed package's) or ``"added"`` (in this process)."""
        self.all()
        if name in self.built_in():
            return "built in"
        return "entry point" if name in self._from_entry_points else "added"

    def added_here(self) -> tuple:
        """The things added with :meth:`register` in this process (not through entry points)."""
        return tuple(t for name, t in self._added.items() if name not in self._from_entry_points)

    def _load_entry_points(self) -> None:
        from importlib.metadata import entry_points

        for ep in entry_points(group=self.group):
            where = f"entry point {ep.name!r} ({ep.value}) of group {self.group}"
            try:
                found = ep.load()
                thing = found() if callable(found) and not isinstance(found, self.cls) else found
            except Exception as exc:
                raise InputError(f"{where}: cannot load ({type(exc).__name__}: {exc})") from None
            if not isinstance(thing, self.cls):
                raise InputError(f"{where}: names {type(thing).__name__}, not an ekm {self.cls.__name__}")
            if thing.name in self._added:
                continue  # registered in this process already (a worker given it by its job)
            try:
                self.register(thing)
            except InputError as exc:
                raise InputError(f"{where}: {exc}") from None
            self._from_entry_points.add(thing.name)


def _a(noun: str) -> str:
    return f"an {noun}" if noun[0] in "AEIOU" else f"a {noun}"


def added_here() -> tuple:
    """Everything added with ``register`` in this process, of every kind: what a job carries to its worker."""
    return tuple(t for registry in KINDS for t in registry.added_here())


def adopt(things: Iterable[Any]) -> None:
    """Register in this process (a worker) each of ``things`` (what :func:`added_here` gave the parent) that its
    kind's registry does not hold yet."""
    for thing in things:
        registry = next(r for r in KINDS if isinstance(thing, r.cls))
        if thing.name not in registry.all():
            registry.register(thing)


def check_params(kind: str, name: str, params) -> None:
    """Refuse, in one line, a ``params`` that is not a frozen dataclass type whose every field has a default (the
    parameters of an architecture or a player, spelt ``NAME:k=v``)."""
    import dataclasses

    if not (dataclasses.is_dataclass(params) and isinstance(params, type)):
        raise InputError(f"{kind} {name}: params must be a dataclass (its parameters), got {params!r}")
    try:
        hash(params())
    except TypeError as exc:
        raise InputError(f"{kind} {name}: params must be a frozen dataclass whose every field has a default "
                         f"({exc})") from None


def check_callable(kind: str, name: str, field: str, value) -> None:
    """Refuse, in one line, a ``field`` of a thing that is not callable."""
    if not callable(value):
        raise InputError(f"{kind} {name}: {field} must be callable")
