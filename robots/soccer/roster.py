"""Soccer players by name, with parameters: ``deliberation:level=half``, ``samba``, ``ekm``, ``schema``.

A player is a parameter dataclass and a ``build(params, field=…, robot=…, spec=…)`` that returns a
:class:`~robots.controllers.base.Controller` whose step takes a :class:`robots.soccer.play.Play`. The command
line spells players as ``ekm compare`` spells architectures (:func:`robots.controllers.spec.parse_architectures`):
``NAME[:k=v[,k=v…]]``, several separated by commas; every unknown name, parameter or bad value is an
:class:`~ekm.errors.InputError` with one line naming it.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, replace
from typing import Any, Callable

from ekm.errors import InputError
from robots.controllers.spec import parse_named, parse_one, spell, typed_params


@dataclass(frozen=True)
class Player:
    """A named player: its parameter class, its builder and a one-line summary."""

    name: str
    params: type
    build: Callable[..., Any]
    summary: str


_PLAYERS = (
    ("deliberation", "deliberation", "SoccerDeliberationParams",
     "reactive deliberation: Table 4's behaviours bid for Table 3's action schemas (Sahota §4.2); level=half|none "
     "are the LCI Cup's half-wit and no-wit"),
    ("samba", "samba", "SoccerSambaParams",
     "Samba for Soccer: action maps for the ball, the goals and the opponent, combined and arbitrated (Riekki ch. 5)"),
    ("ekm", "striker", "EkmParams",
     "the trained indirect EKM with neural-field avoidance, to the point behind the ball on the line to the goal "
     "(ch. 5)"),
    ("schema", "striker", "SchemaParams",
     "motor schemas to the point behind the ball on the line to the goal (Arkin ch. 4.4)"),
)


def _players() -> dict[str, Player]:
    import importlib

    out = {}
    for name, module, params, summary in _PLAYERS:
        m = importlib.import_module(f"robots.soccer.players.{module}")
        out[name] = Player(name, getattr(m, params), m.build, summary)
    return out


_CACHE: dict[str, Player] = {}


def players() -> dict[str, Player]:
    """Every player by name, in the order ``ekm players`` lists them."""
    if not _CACHE:
        _CACHE.update(_players())
    return _CACHE


@dataclass(frozen=True)
class PlayerSpec:
    """A player with resolved parameters; ``str(spec)`` spells every parameter, :attr:`label` only the changed."""

    name: str
    params: Any

    def __str__(self) -> str:
        return spell(self.name, self.params)

    @property
    def label(self) -> str:
        """Only the parameters that differ from the defaults (``deliberation:level=half``, or just ``samba``)."""
        return spell(self.name, self.params, players()[self.name].params())

    def with_params(self, **overrides) -> "PlayerSpec":
        return PlayerSpec(self.name, replace(self.params, **overrides))

    def build(self, field, robot):
        """The ready :class:`~robots.controllers.base.Controller` for ``field`` and ``robot`` — built once per
        process for each (player, field, robot): a controller is pure (every game starts from its ``init()``),
        so every game shares it, and its jitted step compiles once."""
        return _built(self, field, robot)


@functools.lru_cache(maxsize=64)
def _built(spec: PlayerSpec, field, robot):
    return players()[spec.name].build(spec.params, field=field, robot=robot, spec=str(spec))


def parse_players(text: str) -> list[PlayerSpec]:
    """Read ``P1[:k=v,...],P2,...``; raises :class:`InputError` on any fault (module docstring)."""
    return parse_named(text, "player", players(), make_player)


def parse_player(text: str) -> PlayerSpec:
    """Exactly one player (``ekm match A B``)."""
    return parse_one(text, "player", parse_players)


def make_player(name: str, values: dict[str, str]) -> PlayerSpec:
    """The :class:`PlayerSpec` of ``name`` with parameters given as text (``{"level": "half"}``)."""
    known_players = players()
    if name not in known_players:
        raise InputError(f"player {name!r}: unknown (choose from {', '.join(known_players)}; ekm players describes "
                         f"them)")
    return PlayerSpec(name, typed_params("player", name, known_players[name].params, values))
