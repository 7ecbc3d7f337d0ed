"""Soccer players by name, with parameters: ``deliberation:level=half``, ``samba``, ``ekm``, ``schema``.

A player is a parameter dataclass and a ``build(params, field=…, robot=…, spec=…)`` that returns a
:class:`~robots.controllers.base.Controller` whose step takes a :class:`robots.soccer.play.Play`, kept in
:data:`PLAYERS` (the package's, an installed package's through the entry-point group ``ekm.players``, or one
added with ``ekm.register_player``: :mod:`robots.registry`). The command line spells players as it spells
architectures (:mod:`robots.spelling`).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import Any, Callable

from robots.registry import Registry, check_callable, check_params
from robots.spelling import Spec


@dataclass(frozen=True)
class Player:
    """A named player: its parameter class, its builder and a one-line summary.

    ``params`` is a frozen dataclass whose every field has a default; a field's ``metadata`` may hold ``help``
    (one line, with the unit) and ``choices``. ``build(params, field=…, robot=…, spec=…)`` returns a
    :class:`~robots.controllers.base.Controller` whose ``step(state, play)`` gets a
    :class:`~robots.soccer.play.Play` — the game in the player's own frame: it always attacks the goal at
    x = ``field.length`` — and returns ``(state, (left, right) wheel speeds in m/s)``.
    """

    name: str
    params: type
    build: Callable[..., Any]
    summary: str


def _built_in() -> tuple[Player, ...]:
    from robots.soccer.players import deliberation, samba, striker

    return (
        Player("deliberation", deliberation.SoccerDeliberationParams, deliberation.build,
               "reactive deliberation: Table 4's behaviours bid for Table 3's action schemas (Sahota §4.2); "
               "level=half|none are the LCI Cup's half-wit and no-wit"),
        Player("samba", samba.SoccerSambaParams, samba.build,
               "Samba for Soccer: action maps for the ball, the goals and the opponent, combined and arbitrated "
               "(Riekki ch. 5)"),
        Player("ekm", striker.EkmParams, striker.build,
               "the trained indirect EKM with neural-field avoidance, to the point behind the ball on the line to "
               "the goal (ch. 5)"),
        Player("schema", striker.SchemaParams, striker.build,
               "motor schemas to the point behind the ball on the line to the goal (Arkin ch. 4.4)"),
    )


def _check(player: Player) -> None:
    check_params("player", player.name, player.params)
    check_callable("player", player.name, "build", player.build)


#: Every player ``ekm match``, ``ekm tournament`` and ``ekm players`` know (:class:`robots.registry.Registry`).
PLAYERS = Registry("player", "players", Player, _built_in, _check)


class PlayerSpec(Spec):
    """A player with resolved parameters; ``str(spec)`` spells every parameter, :attr:`label` only the changed."""

    registry = PLAYERS

    def build(self, field, robot):
        """The ready :class:`~robots.controllers.base.Controller` for ``field`` and ``robot`` — built once per
        process for each (player, field, robot): a controller is pure (every game starts from its ``init()``),
        so every game shares it, and its jitted step compiles once."""
        return _built(self, field, robot)


@functools.lru_cache(maxsize=64)
def _built(spec: PlayerSpec, field, robot):
    return PLAYERS[spec.name].build(spec.params, field=field, robot=robot, spec=str(spec))


#: Read ``P1[:k=v,...],P2,...`` into :class:`PlayerSpec` s (the command line's spelling, :mod:`robots.spelling`).
parse_players = PlayerSpec.parse
#: Exactly one player (``ekm match A B``).
parse_player = PlayerSpec.parse_one
