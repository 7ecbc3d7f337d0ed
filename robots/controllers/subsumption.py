"""Subsumption (Brooks 1986; Arkin, *Behavior-Based Robotics*, §4.3): layered behaviours with a fixed
priority, coordinated only by suppression and inhibition, each emitting one of a small set of responses.

**The responses** (Arkin §3.3: discrete encoding, "a prespecified set of possible responses"), each a
forward speed and a turn rate (:func:`~robots.controllers.discrete.wheels`):

======== ============================ ========================================
index    response                     (v m/s, ω rad/s) with the defaults
======== ============================ ========================================
0        ``stop``                     (0, 0)
1        ``cruise``                   (``cruise`` 0.16, 0)
2        ``slow``                     (``slow`` 0.04, 0)
3        ``creep``                    (``creep`` 0.008, 0): one Khepera speed unit
4, 5     ``arc-left``, ``arc-right``  (``arc_speed`` 0.08, ±``arc_turn`` 1.0)
6, 7     ``spin-left``, ``spin-right`` (0, ±``spin`` 1.5)
8        ``back``                     (−``back`` 0.04, 0)
======== ============================ ========================================

**The layers**, in Brooks's order of competence (Fig. 4.5: avoid-objects, explore, back-out-of-tight-
situations; Mataric's foraging robot, §4.3.4: wandering, avoiding, homing), each an augmented finite-state
machine whose memory is its own timers and counters (state :class:`SubsumptionState`); all read the same
obstacle points, this tick's IR hits and those remembered (:func:`~robots.controllers.discrete.sense`):

0. **avoid**: *runaway* — a sensed point in the corridor the body sweeps within ``near`` ahead
   (:func:`~robots.controllers.discrete.in_the_way`, half-width body radius + ``margin``) turns the robot
   on the spot away from the side that senses more (``spin-right`` on a tie); a declared mover closing on
   the robot within ``flee`` on a line that meets the body (within ``flee_lane`` of it) takes precedence: the
   robot gets out of the mover's line (``cruise``, ``back`` or a spin towards the way out, :func:`flee`) — and
   this runaway suppresses back out too (an extension, issue 35: backing out, the robot backed into the line
   of a mover circling its goal); a declared mover in that corridor within ``keep_back`` that flee does not answer
   (going on ahead, or across) makes it ``stop`` while go-to-checkpoint speaks — let it go on before following it (an
   extension, issue 35: a mover shuttling along a corridor turned back on the robot following close behind it,
   and the runaway's spin came too late; measured in ``docs/reproduce/every-kind.md``); *collide* — a point in that corridor within ``halt``
   **inhibits** forward motion: whatever response reaches the wheels loses its forward speed (Brooks's
   collide → halt). Go-to-checkpoint **suppresses** runaway's reach (an input of the layer below, as
   Brooks's wander suppresses avoid's heading) to what lies before the checkpoint — what is beyond it is no
   threat — while collide's is never suppressed;
1. **wander**: ``cruise``, ``arc-left`` or ``arc-right``, drawn at random every ``persistence`` s;
2. **go to checkpoint** **suppresses** wander: ``spin`` towards the checkpoint u_p = (α, d) when
   |α| > ``spin_above`` (or > ``fine`` within ``slow_within``), ``arc`` towards it when |α| >
   ``straight_within``, else ``cruise``, ``slow`` within ``slow_within``, ``creep`` within ``creep_within`` and
   ``stop`` within ``stop_within`` of the goal. It goes silent — and wander drives — for ``wander_s`` when it
   has come no ``progress`` closer to its checkpoint for ``patience`` s (Mataric's robots wander when no
   attractor is sensed; here an unreachable one is as good as none). With the default 30 s the runner's
   trap monitor (20 s) replans first: wander's new ground hid traps from it when goto gave up after 8 s;
3. **back out** **suppresses** everything below after ``attempts`` avoid episodes without progress towards
   the checkpoint (Mataric: "after three attempts, back up and turn"): ``back`` for ``back_s`` (``stop`` while
   something is right behind), then ``spin`` away from the side that senses more for ``turn_s``.

Avoid sits above go-to-checkpoint in the suppression chain (as avoiding sits above homing in Mataric's
robot): ``out = flee ▷ backout ▷ avoid ▷ goto ▷ wander``, with ``a ▷ b`` = a's response when a speaks, else
b's (suppression), then the collide inhibition. Exactly one behavioural rule drives at any time (Arkin §4.3.4).

**Randomness and purity**: wander's PRNG key is in the state, seeded from ``seed``, with the robot's pose
folded in at each draw, as the motor schemas' noise (:mod:`~robots.controllers.schema`).

Parameters were chosen on generated worlds (tuning seeds), never on the named ones
(``docs/reproduce/discrete.md``).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cache, partial
from typing import NamedTuple

import jax
import jax.numpy as jnp

from robots.controllers import memory as mem
from robots.controllers.base import Controller, Observation, avoid_option, on_ring, ring
from ekm.angles import wrap
from robots.controllers.discrete import in_the_way, sense, way_out, wheels
from robots.params import KHEPERA, RobotParams

#: Response names, by index (the table of the module docstring).
RESPONSES = ("stop", "cruise", "slow", "creep", "arc-left", "arc-right", "spin-left", "spin-right", "back")
STOP, CRUISE, SLOW, CREEP, ARC_LEFT, ARC_RIGHT, SPIN_LEFT, SPIN_RIGHT, BACK = range(len(RESPONSES))
#: Layer names, lowest competence first; ``Tick.layer`` is an index into it (−1: none spoke).
LAYERS = ("avoid", "wander", "goto", "backout")


@dataclass(frozen=True)
class SubsumptionParams:
    """The responses' speeds, the layers' distances (m, from the body surface unless said) and times (s)."""

    sensors: str = field(default="long", metadata={"help": "IR ring: long (12 around, 17.5 cm) or short "
                                                           "(8 Khepera sensors, 5 cm)", "choices": ("short", "long")})
    cruise: float = field(default=0.16, metadata={"help": "response cruise: m/s straight on"})
    slow: float = field(default=0.04, metadata={"help": "response slow: m/s straight on"})
    creep: float = field(default=0.008, metadata={"help": "response creep: m/s straight on"})
    arc_speed: float = field(default=0.08, metadata={"help": "responses arc-left/right: m/s forward"})
    arc_turn: float = field(default=1.0, metadata={"help": "responses arc-left/right: rad/s turn"})
    spin: float = field(default=1.5, metadata={"help": "responses spin-left/right: rad/s on the spot"})
    back: float = field(default=0.04, metadata={"help": "response back: m/s backwards"})
    near: float = field(default=0.04, metadata={"help": "avoid: m ahead of the body within which a point in its "
                                                        "corridor makes it turn away"})
    margin: float = field(default=0.012, metadata={"help": "avoid: m added to the body radius for the corridor's "
                                                           "half-width"})
    flee: float = field(default=0.08, metadata={"help": "avoid: m between the bodies within which a declared "
                                                        "mover closing on the robot makes it get out of its line"})
    flee_lane: float = field(default=0.012, metadata={"help": "avoid: m beside a closing mover's line within which "
                                                              "the body is in its way (farther, it passes clear)"})
    keep_back: float = field(default=0.08, metadata={
        "help": "avoid: m ahead within which a declared mover in the corridor the body sweeps (one flee does not "
                "answer: going on, or across) makes it stop until the mover has gone on (0: never)"})
    halt: float = field(default=0.01, metadata={"help": "avoid (collide): m ahead within which forward motion is "
                                                        "inhibited"})
    spin_above: float = field(default=0.6, metadata={"help": "goto: rad off the checkpoint above which it spins"})
    straight_within: float = field(default=0.1, metadata={"help": "goto: rad off the checkpoint within which it "
                                                                  "drives straight"})
    fine: float = field(default=0.2, metadata={"help": "goto: rad off the checkpoint above which it spins when within "
                                                       "slow_within"})
    slow_within: float = field(default=0.05, metadata={"help": "goto: m from the checkpoint within which it drives "
                                                               "slow"})
    creep_within: float = field(default=0.012, metadata={"help": "goto: m from the checkpoint within which it creeps"})
    stop_within: float = field(default=0.003, metadata={"help": "goto: m from the goal within which it stops"})
    patience: float = field(default=30.0, metadata={"help": "goto: s without coming progress closer before it "
                                                           "goes silent"})
    progress: float = field(default=0.01, metadata={"help": "goto: m closer to the checkpoint that count as "
                                                            "progress"})
    wander_s: float = field(default=3.0, metadata={"help": "goto: s it stays silent (wander drives)"})
    persistence: float = field(default=2.048, metadata={"help": "wander: s between random draws"})
    attempts: int = field(default=3, metadata={"help": "backout: avoid episodes without progress that start it"})
    back_s: float = field(default=1.024, metadata={"help": "backout: s backing"})
    turn_s: float = field(default=1.024, metadata={"help": "backout: s spinning away afterwards"})
    seed: int = field(default=0, metadata={"help": "wander: seed of the PRNG key"})
    memory_s: float = mem.option("memory_s", 30.0)
    memory_points: int = mem.option("memory_points", 128)
    merge: float = mem.option("merge", 0.01)
    see_through: float = mem.option("see_through", 0.005, why="the points' radius, merge / 2, as the fields'")
    avoid: str = avoid_option("which remembered points it avoids: all or nearer (at the goal, none beyond it; an "
                              "extension)")

    def __post_init__(self):
        for name in ("cruise", "slow", "creep", "arc_speed", "arc_turn", "spin", "back", "near", "flee", "flee_lane",
                     "halt", "spin_above", "straight_within", "fine", "slow_within", "creep_within", "stop_within",
                     "patience", "progress", "wander_s", "persistence", "back_s", "turn_s", "memory_s", "merge",
                     "see_through"):
            if not getattr(self, name) > 0:
                raise ValueError(f"{name} must be > 0, got {getattr(self, name)}")
        for name in ("margin", "keep_back"):
            if not getattr(self, name) >= 0:
                raise ValueError(f"{name} must be >= 0, got {getattr(self, name)}")
        if not (isinstance(self.memory_points, int) and self.memory_points >= 1):
            raise ValueError(f"memory_points must be a whole number >= 1, got {self.memory_points}")
        if not (isinstance(self.attempts, int) and self.attempts >= 1):
            raise ValueError(f"attempts must be a whole number >= 1, got {self.attempts}")
        if not self.straight_within < self.spin_above:
            raise ValueError(f"straight_within must be < spin_above, got {self.straight_within} >= {self.spin_above}")

    def table(self):
        """The responses ``(9, 2)`` as (v m/s, ω rad/s), in the order of :data:`RESPONSES`."""
        return jnp.asarray([(0.0, 0.0), (self.cruise, 0.0), (self.slow, 0.0), (self.creep, 0.0),
                            (self.arc_speed, self.arc_turn), (self.arc_speed, -self.arc_turn),
                            (0.0, self.spin), (0.0, -self.spin), (-self.back, 0.0)], jnp.float32)


class SubsumptionState(NamedTuple):
    """The layers' timers and counters (times in s of run time), and the remembered IR points."""

    memory: mem.Memory
    key: jax.Array  # wander's PRNG key
    wander: jax.Array  # wander's current response
    wander_due: jax.Array  # when wander draws again
    target_id: jax.Array  # the checkpoint goto and backout measure progress to
    best: jax.Array  # the closest goto has come to it (m)
    best_t: jax.Array  # when it last came ``progress`` closer
    silent_until: jax.Array  # goto is silent (bored) until then
    avoiding: jax.Array  # avoid spoke last tick
    episodes: jax.Array  # avoid episodes since the last progress
    back_until: jax.Array  # backout backs until then …
    turn_until: jax.Array  # … then spins until then
    turn: jax.Array  # … in this direction (SPIN_LEFT or SPIN_RIGHT)


class Tick(NamedTuple):
    """One tick's layers: each one's response (−1: silent), the layer that drove, the response sent after
    the collide inhibition, and whether collide inhibited forward motion."""

    avoid: jax.Array
    wander: jax.Array
    goto: jax.Array
    backout: jax.Array
    layer: jax.Array
    response: jax.Array
    halted: jax.Array


@cache
def init(p: SubsumptionParams) -> SubsumptionState:
    f = partial(jnp.asarray, dtype=jnp.float32)
    return SubsumptionState(mem.empty(p.memory_points), jax.random.PRNGKey(p.seed), jnp.int32(CRUISE), f(-jnp.inf),
                            jnp.int32(-1), f(jnp.inf), f(0.0), f(-jnp.inf), jnp.bool_(False), jnp.int32(0),
                            f(-jnp.inf), f(-jnp.inf), jnp.int32(SPIN_RIGHT))


def away(points, seen):
    """The spin away from the side that senses more (``SPIN_RIGHT`` when the left senses more, or on a tie)."""
    left = jnp.sum(jnp.where(seen & (points[:, 1] > 0), 1.0, 0.0))
    right = jnp.sum(jnp.where(seen & (points[:, 1] < 0), 1.0, 0.0))
    return jnp.where(right > left, SPIN_LEFT, SPIN_RIGHT)


def avoid(points, seen, reach, p: SubsumptionParams, radius: float):
    """Layer 0: (runaway response or −1, collide: forward motion inhibited), for points in the corridor within
    ``reach`` ahead (``near``, or less where go-to-checkpoint suppresses it)."""
    way = in_the_way(points, seen, radius, p.margin, reach)
    close = in_the_way(points, seen, radius, p.margin, p.halt)
    return jnp.where(jnp.any(way), away(points, way), -1), jnp.any(close)


def flee(obs: Observation, points, seen, p: SubsumptionParams, radius: float):
    """Layer 0's runaway from the declared movers: −1, or the response that takes the robot out of the line of a
    mover closing on it within ``flee`` (body to body, :func:`~robots.controllers.discrete.way_out`) — ``cruise``
    when the way out lies within 45° of its heading, ``back`` when within 45° of straight behind (and nothing is
    there), else the spin towards it."""
    threat, out = way_out(obs, radius, p.flee, p.flee_lane)
    phi = wrap(jnp.arctan2(out[1], out[0]) - jnp.asarray(obs.pose, jnp.float32)[2])
    response = jnp.where(jnp.abs(phi) < jnp.pi / 4, CRUISE,
                         jnp.where((jnp.abs(phi) > 3 * jnp.pi / 4) & ~behind(points, seen, p, radius), BACK,
                                   jnp.where(phi > 0, SPIN_LEFT, SPIN_RIGHT)))
    return jnp.where(threat, response, -1)


def behind(points, seen, p: SubsumptionParams, radius: float):
    """Whether a point lies in the corridor the body would sweep backing ``halt`` + its radius."""
    return jnp.any(in_the_way(-points, seen, radius, p.margin, p.halt + radius))


def goto(target, final, p: SubsumptionParams):
    """Layer 2's rule: the response towards the checkpoint u_p = ``target`` (α, d)."""
    alpha, d = target[0], target[1]
    spin = jnp.where(alpha > 0, SPIN_LEFT, SPIN_RIGHT)
    arc = jnp.where(alpha > 0, ARC_LEFT, ARC_RIGHT)
    ahead = jnp.where(d > p.slow_within, CRUISE, jnp.where(d > p.creep_within, SLOW, CREEP))
    turn_above = jnp.where(d > p.slow_within, p.spin_above, p.fine)
    steer = jnp.where(jnp.abs(alpha) > turn_above, spin,
                      jnp.where((jnp.abs(alpha) > p.straight_within) & (d > p.slow_within), arc, ahead))
    return jnp.where(final & (d < p.stop_within), STOP, steer)


def layers(state: SubsumptionState, obs: Observation, angles, p: SubsumptionParams, radius: float,
           range_m: float) -> tuple[SubsumptionState, Tick]:
    """Every layer for one tick, suppression and inhibition (the module docstring)."""
    t = jnp.asarray(obs.t, jnp.float32)
    memory, points, seen = sense(state.memory, obs, angles, radius=radius, range_m=range_m, merge=p.merge,
                                 memory_s=p.memory_s, through=p.see_through, nearer=p.avoid == "nearer")

    # wander: a random response of (cruise, arc-left, arc-right), redrawn every ``persistence`` s
    key = state.key
    for bits in jax.lax.bitcast_convert_type(jnp.asarray(obs.pose, jnp.float32), jnp.uint32):
        key = jax.random.fold_in(key, bits)
    key, sub = jax.random.split(key)
    redraw = t >= state.wander_due - 1e-3
    drawn = jnp.asarray((CRUISE, ARC_LEFT, ARC_RIGHT))[jax.random.randint(sub, (), 0, 3)]
    wander = jnp.where(redraw, drawn, state.wander)

    # goto, with its boredom; progress is measured to the current checkpoint, afresh when it changes
    d = obs.target[1]
    new = obs.target_id != state.target_id
    best = jnp.where(new, jnp.inf, state.best)
    closer = d < best - p.progress
    best_t = jnp.where(new | closer, t, state.best_t)
    best = jnp.where(new | closer, d, best)
    bored = (t - best_t > p.patience) & (t >= state.silent_until)
    silent_until = jnp.where(bored, t + p.wander_s, state.silent_until)
    best_t = jnp.where(bored, t + p.wander_s, best_t)  # patience runs again once goto speaks
    best = jnp.where(bored, d, best)
    go = jnp.where(t < silent_until, -1, goto(obs.target, jnp.asarray(obs.final), p))

    # avoid, its reach suppressed by goto to what lies before the checkpoint (what is beyond it is no threat)
    reach = jnp.where(go >= 0, jnp.clip(d - radius, 0.0, p.near), p.near)
    run_away, collide = avoid(points, seen, reach, p, radius)
    escape = flee(obs, points, seen, p, radius)
    if p.keep_back > 0:  # a mover ahead, going on or across: let it go before following (it may turn back)
        k = memory.points.shape[0]  # the rows after are the declared movers' nearest points
        behind_one = jnp.any(in_the_way(points[k:], seen[k:], radius, p.margin, p.keep_back))
        escape = jnp.where((escape < 0) & behind_one & (go >= 0), STOP, escape)
    run_away = jnp.where(escape >= 0, escape, run_away)

    # backout: counts avoid episodes (rising edges) since the last progress
    speaking = run_away >= 0
    episodes = jnp.where(new | closer, 0, state.episodes) + (speaking & ~state.avoiding).astype(jnp.int32)
    start = (episodes >= p.attempts) & (t >= state.turn_until)
    back_until = jnp.where(start, t + p.back_s, state.back_until)
    turn_until = jnp.where(start, t + p.back_s + p.turn_s, state.turn_until)
    turn = jnp.where(start, away(points, seen), state.turn)
    episodes = jnp.where(start, 0, episodes)
    backout = jnp.where(t < back_until, jnp.where(behind(points, seen, p, radius), STOP, BACK),
                        jnp.where(t < turn_until, turn, -1))

    # suppression: flee ▷ backout ▷ avoid ▷ goto ▷ wander (the runaway from a mover above back out)
    chain = ((escape, 0), (backout, 3), (run_away, 0), (go, 2))
    response, layer = wander, jnp.int32(1)
    for out, index in reversed(chain):
        response = jnp.where(out >= 0, out, response)
        layer = jnp.where(out >= 0, index, layer)
    state = SubsumptionState(memory, jnp.where(redraw, key, state.key), wander,
                             jnp.where(redraw, t + p.persistence, state.wander_due).astype(jnp.float32),
                             jnp.asarray(obs.target_id, jnp.int32), best.astype(jnp.float32),
                             best_t.astype(jnp.float32), silent_until.astype(jnp.float32), speaking, episodes,
                             back_until.astype(jnp.float32), turn_until.astype(jnp.float32), turn)
    return state, Tick(run_away, wander, go, backout, layer, response, collide)


@partial(jax.jit, static_argnames=("p", "robot"))
def step(state: SubsumptionState, obs: Observation, angles, *, p: SubsumptionParams, robot: RobotParams):
    """One tick: the layers, then the response's wheel speeds, forward motion inhibited by collide."""
    sensors = ring(robot, p.sensors)
    state, tick = layers(state, obs, angles, p, robot.radius, sensors.range_m)
    v, omega = p.table()[tick.response]
    v = jnp.where(tick.halted, jnp.minimum(v, 0.0), v)
    return state, wheels(v, omega, robot)


def build(params: SubsumptionParams, ekm=None, cfg=None, robot: RobotParams = KHEPERA,
          spec: str = "subsumption") -> Controller:
    """Subsumption on ``robot`` (it drives no EKM: ``ekm`` and ``cfg`` are None)."""
    return on_ring("subsumption", spec, params, init, step, robot)
