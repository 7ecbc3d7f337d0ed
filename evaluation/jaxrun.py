"""The scenario runner on the JAX engine: many runs of one architecture in one batch (docs/guide/jaxworld.md).

:func:`evaluation.scenario.run_scenario` runs one robot in the pymunk world, a Python loop calling one jitted step a
tick. Here one batch holds one architecture's runs over many (world, seed) pairs, and a tick of all of them is one
``vmap`` inside one jitted ``lax.scan``. Each tick does for every run what the pymunk runner's ``episode`` does:

0. if a known timed event has changed the planner's map since the last tick, **wait** for the host to replan (the
   tick is not taken; it runs once the new plan is in);
1. pass the checkpoints already within reach or seen past (``pass_checkpoints``: within 5 mm, or near one whose
   successor the robot sees; every ``look_every`` ticks the last of ``look_ahead`` later ones it sees, or, when a
   known wall comes between it and its checkpoint, the latest of ``look_back`` earlier ones looked past that it sees);
2. sense (the IR with its noise, :func:`robots.jaxworld.engine.sense`) and hand the controller its
   :class:`~robots.controllers.base.Observation` (the declared movers as markers, :func:`robots.jaxworld.moving.markers`); after a recovery the robot turns on the spot instead, for at most
   ``turn_s``, until the route is ahead (the controller is not stepped on those ticks);
3. stop at the goal: within 5 mm of it, a command that rounds to zero, or ``settle_s`` spent there, ends the run
   after one period of a zero command;
4. drive one period (:func:`robots.jaxworld.engine.step`); a sub-step within 5 mm of the checkpoint reaches it;
5. the trap monitor (:mod:`evaluation.jaxmonitor`, :class:`~evaluation.monitor.TrapMonitor`'s rule): trapped, the
   run ends — or, with recovery, **waits** for the host; and, with recovery, a checkpoint the IR shows blocked
   (:func:`evaluation.scenario.blocked_checkpoint`, :func:`blocked`) **waits** for the host's replan round what the
   robot sensed.

The runs go through in blocks of :data:`BLOCK` (:func:`advance`), a block with no run left skipped. The planner
stays on the host (the imperative shell, :func:`run_batch`): plans are made before the batch; the scan runs in
chunks of ``chunk_ticks``; between chunks the host takes every waiting run through the pymunk runner's
recovery — what its IR saw joins the planner's map and a new plan is made from where it stands
(:func:`evaluation.scenario.recovery`) — writes the new checkpoints and map into the batch's arrays,
and the batch goes on. A run that waits loses no simulated time, only the rest of its chunk of wall time. Batches
(an architecture's worlds of one :func:`kind`) run :data:`THREADS` at a time (:func:`in_threads`): one compiles or
plans while another's scan runs; a run's record does not depend on which batch runs beside it.

The records are :class:`~evaluation.scenario.RunRecord`'s, built from every live tick's outputs exactly as the
pymunk runner builds them (poses at every sub-step, the commands, the plans, contact episodes), so outcomes, motion
measures and results files are the same; ``checkpoint_log``, ``trap_log`` and ``hits`` (what ``ekm run --plot``
marks) are not kept. Noise: slip ξ ~ U(-1, 1) and IR ξ ~ N(0, 1) from the run's key, ``jax.random.key(seed)`` split every
tick — the same distributions as the pymunk world's NumPy streams, not the same draws. Times are float32 (k dt).

Worlds with movers or timed events run in batches of their own (:func:`run_batch` groups them), stepped with
``dynamic`` (:func:`robots.jaxworld.engine.step`), their markers padded to a power of two rows (a padding marker
stands still far away, :data:`robots.jaxworld.moving.FAR`), so that batches of still worlds pay nothing for movers
and a handful of shapes serves every mover count. A moving goal (Samba's scenario) is chased as the pymunk runner
chases it: the goal's place at each tick is the controller's target (with its velocity), and a sub-step that
brings the robot's centre within the capture radius of where the goal then is catches it.
"""

from __future__ import annotations

import math
import threading
from concurrent.futures import FIRST_EXCEPTION, ThreadPoolExecutor, wait
from dataclasses import dataclass, field, replace
from functools import partial
from typing import Any, NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from evaluation import jaxmonitor
from evaluation.scenario import (DOUBT, MOVER_MARGIN, PlanChange, RunRecord, ScenarioConfig, explained_within,
                                 first_plan, mover_radius, recovery, replan_from, split_step, time_limit_for,
                                 turn_on_the_spot)
from robots import kinematics
from robots.controllers.base import Observation, hit_points
from robots.jaxworld import engine, moving
from robots.jaxworld.collide import gaps
from robots.jaxworld.scene import Paths, Scene, has_dynamics, paths_of, scene_of, shape_of, sizes, stack
from robots.jaxworld.task import sees, sees_next, sight_need
from robots.params import RobotParams, SensorSet

#: A run's status: ticking, waiting for the host to replan (recovery, a known event, a blocked checkpoint), or ended
#: — and how (every status from ARRIVED on).
RUNNING, WAITING, EVENT, BLOCKED, ARRIVED, TRAPPED, TIMEOUT, NO_ROUTE, CAUGHT = 0, 1, 2, 3, 4, 5, 6, 7, 8
ENDED = {ARRIVED: "stopped at the goal", TRAPPED: "trapped", TIMEOUT: "time limit",
         NO_ROUTE: "no route after a change of the map", CAUGHT: "caught the moving goal"}

#: Runs stepped together as one ``vmap`` (the blocks of :func:`advance`).
BLOCK = 16

#: Batches run at once, each in a thread of its own (:func:`in_threads`).
THREADS = 2

#: Ticks of one chunk of the scan (4.1 s of 0.128 s ticks): how long a run that needs a new plan may wait for it.
CHUNK_TICKS = 32


@dataclass(frozen=True)
class Setup:
    """What every run of a batch shares (static under ``jit``): the robot and its IR ring, the period's sub-steps
    ``n`` and slip draws ``k``, the scenario's rules (:class:`~evaluation.scenario.ScenarioConfig`), the trap
    monitor's, and the controller's step as :func:`~evaluation.scenario.split_step` splits it (``func``,
    ``static``); whether the worlds have movers or timed events (``dynamic``), the markers' rows (``markers``),
    and whether their goals move (``chase``)."""

    params: RobotParams
    sensors: SensorSet
    n: int
    k: int
    config: ScenarioConfig
    rule: jaxmonitor.MonitorRule
    func: Any
    static: tuple
    dynamic: bool = False
    markers: int = 0
    chase: bool = False

    @property
    def visible(self) -> bool:
        """Whether the plans' checkpoints see each other (the ``visible`` rule): only then are they passed early."""
        return self.config.checkpoints == "visible"


class Route(NamedTuple):
    """One run's arrays that the host sets (a leading batch axis in a batch): ``scene`` every shape of its world,
    ``sight`` the planner's map (known shapes and what recovery added), ``checkpoints`` ``(K, 2)`` (goal at
    ``last``, padded by repeating it), ``ticks`` its time limit in ticks, ``may_recover`` whether a trap waits for a
    new plan (else it ends the run), ``radii`` ``(M,)`` the markers' radii of its movers (-1: padding),
    ``goal_path`` the path of its goal if it moves (:class:`~robots.jaxworld.scene.Paths` of one row)."""

    scene: Scene
    sight: Scene
    checkpoints: Any
    last: Any
    ticks: Any
    may_recover: Any
    radii: Any
    goal_path: Paths


class RunState(NamedTuple):
    """One run's state between ticks: the engine's, the controller's (``control``), the PRNG ``key``, ``tick``s
    taken, the checkpoint ``index`` headed for and the ``target_id`` the controller sees, whether it stood within the
    goal's tolerance last tick (``settled``) and ``since`` when (s), until when it turns after a recovery
    (``turn_until``, s), the trap monitor, ``status`` (:data:`RUNNING` …), checkpoints ``passed`` (the goal too),
    the time (s) of the tick it stopped at the goal (``stop_t``) and of its last tick (``last_t``: a known event
    since then replans), and the first and last checkpoint the look ahead took it past (``looked_past`` ``(2,)``
    int32, empty when first > last: :class:`~evaluation.scenario.Course`'s) and the target its blocked checkpoint found
    no route round (``unblockable``, -1: none)."""

    engine: engine.EngineState
    control: Any
    key: Any
    tick: Any
    index: Any
    target_id: Any
    settled: Any
    since: Any
    turn_until: Any
    monitor: jaxmonitor.MonitorState
    status: Any
    passed: Any
    stop_t: Any
    last_t: Any
    looked_past: Any
    unblockable: Any


class TickOut(NamedTuple):
    """What one tick leaves for the record: ``live`` (the run was ticking), the ``pose`` ``(3,)`` and ``ir``
    ``(m,)`` it sensed, the ``command`` ``(2,)`` sent and whether it was the architecture's or recovery's
    (``commanded``; not on the stop at the goal), the sub-step ``trace`` ``(n, 3)``, contact episodes so far, the
    ``markers`` ``(k, 5)`` it was given and the ``goal`` ``(2,)`` it headed for."""

    live: Any
    pose: Any
    ir: Any
    command: Any
    commanded: Any
    trace: Any
    collisions: Any
    markers: Any
    goal: Any


def _where(flag, new, old):
    return jax.tree.map(lambda a, b: jnp.where(flag, a, b), new, old)


def pass_checkpoints(setup: Setup, route: Route, pos, index, tick, past):
    """Step 1 (:func:`evaluation.scenario.pass_checkpoints`) of one run: ``(index, passed, back, past)`` after the
    checkpoints within ``checkpoint_tolerance`` of ``pos`` or, with visible checkpoints, near and seen past
    (:func:`pass_near`), then the look of every ``look_every``-th tick (:func:`look`); ``passed`` counts the
    checkpoints passed, ``back`` whether it turned back, ``past`` ``(2,)`` the first and last looked past."""
    near, need = pass_near(setup, route, pos, index)
    index_, ahead, back, past = look(setup, route, pos, near, tick, past, need)
    return index_, near - index + ahead, back, past


def pass_near(setup: Setup, route: Route, pos, index):
    """``(index, need)``: the checkpoint headed for after those within ``checkpoint_tolerance`` of ``pos`` or, with
    visible checkpoints, near and seen past; and the slack a line from ``pos`` must keep to count as seen
    (:func:`~robots.jaxworld.task.sight_need`; None without visible checkpoints)."""
    config, radius, cps = setup.config, setup.params.radius, route.checkpoints
    need = sight_need(pos, route.sight, radius) if setup.visible else None  # once: the map's gaps from pos

    def passes(i):
        within = jnp.linalg.norm(pos - cps[i]) < config.checkpoint_tolerance
        if setup.visible:
            within = within | sees_next(pos, cps, i, route.sight, radius, config.pass_radius, need)
        return (i < route.last) & within

    return jax.lax.while_loop(passes, lambda i: i + 1, index), need


def look(setup: Setup, route: Route, pos, index, tick, past, need):
    """The look of a ``look_every``-th tick (a no-op on the others): ``(index, ahead, back, past)`` — the last of the
    ``look_ahead`` checkpoints after ``index`` seen from ``pos`` (``ahead`` of them passed; ``past`` ``(2,)`` the
    first and last looked past), then, when the robot's disc would touch a known shape on the straight way to the
    checkpoint, the latest of the ``look_back`` before it that were looked past and that it sees (``back``)."""
    config, radius, cps = setup.config, setup.params.radius, route.checkpoints
    looking = (tick % config.look_every == 0) if setup.visible else jnp.bool_(False)
    start = index
    if setup.visible and config.look_ahead:
        ahead = jnp.minimum(index + jnp.arange(1, config.look_ahead + 1), route.last)
        seen = jax.vmap(lambda q: sees(pos, q, route.sight, radius, need))(cps[ahead])
        later = jnp.max(jnp.where(seen, ahead, index))  # the farthest seen
        later = jnp.where(looking & (index < route.last), later, index)
        skipped = later > index
        first = jnp.where(past[0] <= past[1], jnp.minimum(past[0], index), index)
        past = jnp.where(skipped, jnp.stack([first, later - 1]), past)
        index = later
    passed = index - start
    back = jnp.bool_(False)
    if setup.visible and config.look_back:
        lowest = jnp.maximum(past[0], index - config.look_back)
        behind = index - jnp.arange(1, config.look_back + 1)  # the latest first
        open_ = (behind >= lowest) & (behind <= past[1])
        seen = jax.vmap(lambda q: sees(pos, q, route.sight, radius, need))(cps[jnp.maximum(behind, 0)])
        crossed = ~sees(pos, cps[index], route.sight, radius, jnp.minimum(0.0, need))  # as _seen_earlier
        back = looking & crossed & jnp.any(open_ & seen)
        index = jnp.where(back, behind[jnp.argmax(open_ & seen)], index)
    return index, passed, back, past


def passing(setup: Setup, routes: Route, state: RunState):
    """Step 1 for a block of runs (leading axis B): :func:`pass_checkpoints` of each, its ``(index, passed, back,
    past)``, with the look (its sight lines, most of the step's work) worked out only on ticks where some run of
    the block looks (``lax.cond`` outside the ``vmap``: runs started together look on the same ticks)."""
    pos = state.engine.robot.pose[:, :2]
    near, need = jax.vmap(partial(pass_near, setup))(routes, pos, state.index)

    def looked(_):
        index, ahead, back, past = jax.vmap(partial(look, setup))(routes, pos, near, state.tick, state.looked_past,
                                                                   need)
        return index, near - state.index + ahead, back, past

    def still(_):
        return near, near - state.index, jnp.zeros_like(near, bool), state.looked_past

    config = setup.config
    if not (setup.visible and (config.look_ahead or config.look_back)):
        return still(None)
    due = jnp.any((state.tick % config.look_every == 0) & (state.status == RUNNING))
    return jax.lax.cond(due, looked, still, None)


def tick(setup: Setup, route: Route, state: RunState, arrays, passed_to) -> tuple[RunState, TickOut]:
    """One 0.128 s tick of one run (the module docstring's steps) after step 1, ``passed_to`` (its ``(index,
    passed, back, past)``, :func:`pass_checkpoints`, which :func:`passing` works out for a block of runs at once); a
    run not :data:`RUNNING` stays as it is."""
    p, config, dynamic = setup.params, setup.config, setup.dynamic
    key, k_ir, k_slip = jax.random.split(state.key, 3)
    t = state.engine.k.astype(jnp.float32) * p.dt
    scene = route.scene
    changed = jnp.any(scene.event_known & (state.last_t < scene.event_at)
                      & (scene.event_at <= t + moving.EVENT_SLACK)) if dynamic else jnp.bool_(False)
    pose = state.engine.robot.pose
    pos = pose[:2]
    index, passed, back, past = passed_to
    monitor = jaxmonitor.aim(state.monitor, index, t, index != state.index)
    target_id = state.target_id + passed + back
    final = index == route.last
    goal = route.checkpoints[index]
    velocity = jnp.zeros(2, jnp.float32)
    if setup.chase:  # the goal where it is now, and its velocity
        goal = jnp.where(final, moving.positions(route.goal_path, t)[0], goal)
        velocity = jnp.where(final, moving.velocities(route.goal_path, t)[0], velocity).astype(jnp.float32)

    noise = jax.random.normal(k_ir, (len(setup.sensors.angles),))
    ir = engine.sense(state.engine, scene, setup.sensors, noise, p, dynamic)
    target = kinematics.egocentric(pose, goal, xp=jnp)
    markers = moving.markers(scene, t, route.radii)[:setup.markers] if dynamic else jnp.zeros((0, 5), jnp.float32)
    obs = Observation(t=t, ir=ir.astype(jnp.float32), target=target.astype(jnp.float32), target_id=target_id,
                      final=final, pose=pose, target_velocity=velocity, markers=markers)
    turning = (t < state.turn_until) & (jnp.abs(target[0]) > config.turn_tolerance)
    control, wanted = setup.func(state.control, obs, **arrays, **dict(setup.static))
    control = _where(turning, state.control, control)
    command = jnp.where(turning, turn_on_the_spot(target[0], p, jnp), jnp.asarray(wanted, jnp.float32))
    turn_until = jnp.where(turning, state.turn_until, 0.0)

    inside = final & (jnp.linalg.norm(pos - goal) < config.checkpoint_tolerance) & (not setup.chase)
    since = jnp.where(inside & state.settled, state.since, t)
    stop = inside & (kinematics.is_stop_command(command, p, jnp) | (t - since >= config.settle_s - 1e-9))

    slip = jax.random.uniform(k_slip, (setup.k, 2), minval=-1.0, maxval=1.0)
    eng, trace = engine.step(state.engine, scene, jnp.where(stop, 0.0, command), slip, p, setup.n, dynamic)
    t_end = eng.k.astype(jnp.float32) * p.dt
    near = ~stop & ~final & jnp.any(jnp.linalg.norm(trace[:, :2] - goal, axis=1) < config.checkpoint_tolerance)
    index = index + near
    heading_for = route.checkpoints[index]
    caught, caught_t = jnp.bool_(False), t
    if setup.chase:  # a sub-step within the capture radius of where the goal is then catches it
        sub_t = t + p.dt * jnp.arange(1, setup.n + 1, dtype=jnp.float32)
        goals = jax.vmap(lambda s: moving.positions(route.goal_path, s)[0])(sub_t)
        hit = jnp.linalg.norm(trace[:, :2] - goals, axis=1) < (p.radius if config.capture_radius is None
                                                                else config.capture_radius)
        caught, caught_t = final & jnp.any(hit), sub_t[jnp.argmax(hit)]
        heading_for = jnp.where(final, moving.positions(route.goal_path, t_end)[0], heading_for)
    monitor = jaxmonitor.aim(monitor, index, t_end, near)
    watched, trapped = jaxmonitor.update(monitor, t_end, jnp.linalg.norm(eng.robot.pose[:2] - heading_for),
                                         eng.robot.pose[:2], setup.rule)
    watch = ~stop & ~near & ~caught
    monitor = _where(watch, watched, monitor)
    trapped = watch & trapped
    stuck = watch & ~final & (target_id != state.unblockable) & blocked(setup, route, pose, ir, markers, goal)
    status = jnp.where(stop, ARRIVED, jnp.where(caught, CAUGHT, jnp.where(trapped, jnp.where(route.may_recover,
                                                                                             WAITING, TRAPPED),
                                                                          jnp.where(stuck, BLOCKED, RUNNING))))
    ticks = state.tick + 1
    status = jnp.where((status == RUNNING) & (ticks >= route.ticks), TIMEOUT, status).astype(jnp.int32)

    new = RunState(engine=eng, control=control, key=key, tick=ticks, index=index, target_id=target_id + near,
                   settled=inside, since=since, turn_until=turn_until, monitor=monitor, status=status,
                   passed=state.passed + passed + near + stop + caught,
                   stop_t=jnp.where(stop, t, jnp.where(caught, caught_t, state.stop_t)), last_t=t, looked_past=past,
                   unblockable=state.unblockable)
    live = (state.status == RUNNING) & ~changed
    out = TickOut(live=live, pose=pose, ir=ir, command=command, commanded=~stop, trace=trace,
                  collisions=eng.collisions, markers=markers, goal=goal)
    held = state._replace(status=jnp.where((state.status == RUNNING) & changed, EVENT, state.status).astype(jnp.int32))
    return _where(live, new, held), out


def blocked(setup: Setup, route: Route, pose, ir, markers, checkpoint):
    """:func:`evaluation.scenario.blocked_checkpoint` of one run's tick: whether a still point its IR ``ir`` saw from
    ``pose`` within ``sensed_near`` lies within the robot's radius of the ``checkpoint`` ``(2,)`` even with the
    reading's doubt, unexplained by the planner's map ``route.sight``. False where the scenario's rules replan on no
    such thing (no recovery)."""
    config, p, sensors = setup.config, setup.params, setup.sensors
    if not (config.recover and config.blocked):
        return jnp.bool_(False)
    pts, seen = hit_points(pose, ir, sensors.angles, p.radius, xp=jnp)
    if setup.dynamic:  # a point on a declared mover is the mover (:func:`evaluation.scenario.sensed_points`)
        gap = jnp.linalg.norm(pts[:, None, :] - markers[None, :, :2], axis=-1)
        seen = seen & ~jnp.any(gap <= markers[None, :, 4] + MOVER_MARGIN, axis=-1)
    doubt = DOUBT * sensors.noise * jnp.where(seen, ir, 0.0)
    seen = seen & (ir <= config.sensed_near)
    gap = jnp.where(seen, jnp.linalg.norm(pts - checkpoint, axis=1) + doubt, jnp.inf)
    k = jnp.argmin(gap)
    clear = jnp.min(gaps(pts[k], route.sight)[0])
    return (gap[k] < p.radius) & (clear > explained_within(ir[k], config.sensed_radius, sensors.noise,
                                                             sensors.resolution_m, jnp))


@partial(jax.jit, static_argnames=("setup", "block", "length"), donate_argnums=(3,))
def advance(setup: Setup, block: int, routes: Route, state: RunState, arrays, length: int = CHUNK_TICKS):
    """``length`` ticks of every run of a batch (leading axis B, a multiple of ``block``, on ``routes``, ``state``
    and ``arrays``): the new state and every tick's :class:`TickOut` ``(B, length, ...)``.

    The runs go through in blocks of ``block`` — ``lax.map`` over blocks, each block's ticks one ``lax.scan`` of a
    ``vmap`` — for two reasons: a block's arrays stay in cache, where one ``vmap`` of hundreds of runs is several
    times slower on a CPU (docs/performance.md, the world in JAX); and a block none of whose runs is
    :data:`RUNNING` is skipped (``lax.cond``), so the host, which puts the open runs first, pays only for the
    blocks that hold them while a batch's last runs finish."""
    one = jax.vmap(partial(tick, setup))

    def go(x):
        route, s, arr = x
        s, outs = jax.lax.scan(lambda c, _: one(route, c, arr, passing(setup, route, c)), s, None, length=length)
        return s, jax.tree.map(lambda a: jnp.swapaxes(a, 0, 1), outs)

    def run(x):
        shapes = jax.eval_shape(go, x)[1]
        return jax.lax.cond(jnp.any(x[1].status == RUNNING), go,
                            lambda y: (y[1], jax.tree.map(lambda d: jnp.zeros(d.shape, d.dtype), shapes)), x)

    b = state.tick.shape[0]
    blocks = jax.tree.map(lambda a: a.reshape((b // block, block) + a.shape[1:]), (routes, state, arrays))
    state, outs = jax.lax.map(run, blocks)
    return jax.tree.map(lambda a: a.reshape((b,) + a.shape[2:]), (state, outs))


def _bucket(n: int) -> int:
    """The padded size that holds ``n``: the next power of two (few shapes, so few compilations)."""
    return 1 << max(0, int(n) - 1).bit_length()


def _sight_world(known, t: float = 0.0, avoided: tuple = ()):
    """The planner's map at ``t`` as shapes the JAX engine can measure: the known world less its unforeseen and
    moving obstacles, with the shapes of the known events due by ``t`` and the movers' lanes a plan keeps off
    (``avoided``; :meth:`~robots.worldfile.World.known_shapes`, :func:`evaluation.scenario.sight_of`)."""
    added = tuple(s for e in known.events if e.known and e.at_s <= t for s in e.add)
    return replace(known, unforeseen=(), moving=(), events=(), obstacles=known.obstacles + added + tuple(avoided))


#: Capsules a batch's planner maps keep free for the discs recovery adds (a trap typically adds tens): a map that
#: outgrows its padding makes the batch compile again.
ROOM = 128


#: Checkpoint slots kept free for a new plan longer than the first (recovery): likewise.
SLOTS = 8


def _scenes(worlds: list, room: int = 0, movers: int = 1) -> Scene:
    """The scenes of ``worlds`` stacked, padded to one shape with ``room`` capsules to spare, their number rounded up
    to a power of two (few shapes, few compilations), with ``movers`` path slots at least."""
    need = np.max([sizes(w) for w in worlds], axis=0)
    shape = (_bucket(need[0] + room), int(need[1]), int(need[2]), max(int(need[3]), movers), int(need[4]))
    return stack([scene_of(w, shape) for w in worlds])


def _padded(checkpoints: list, slots: int) -> np.ndarray:
    return np.stack([np.concatenate([c, np.repeat(c[-1:], slots - len(c), axis=0)]) for c in checkpoints]) \
        .astype(np.float32)


@dataclass
class Run:
    """One run's host side: its world, seed and body (the controller: robot and sensors), the plan it follows and
    the planner's map (``known``, as it stands at ``map_t``: known events by then on it), recoveries so far, the
    record being written, and every tick's sensing on which the IR saw something (``sensed``: (t, pose, readings, markers), as :func:`evaluation.scenario.sensed_points`
    takes it)."""

    world: Any
    seed: int
    body: Any
    plan: Any
    known: Any
    rec: RunRecord
    ticks: int
    recoveries: int = 0
    replans: int = 0
    trapped_why: str = "trapped"
    collisions: int = 0
    map_t: float = 0.0
    sensed: list = field(default_factory=list)
    poses: list = field(default_factory=list)
    times: list = field(default_factory=list)


def start_run(world, body, seed: int, config: ScenarioConfig, spec: str, plans: dict | None = None) -> Run:
    """A run's host side at t = 0: its first plan and time limit (raises :class:`~ekm.errors.InputError` for a start
    the robot does not fit or no route). ``plans``: first plans already made, by (world, robot, config), kept
    there — a comparison runs every architecture in the same worlds, and a plan depends on nothing else."""
    from planner.checkpoints import path_length

    robot = body.robot
    key = (world, robot, config)
    current = plans.get(key) if plans is not None else None
    if current is None:
        current = first_plan(world, robot, config)
        if plans is not None:
            plans[key] = current
    rec = RunRecord(world=world, architecture=spec, seed=seed, period=robot.avoid_period, robot=robot)
    rec.plans.append(PlanChange(0.0, "start", current.checkpoints.copy(), avoided=current.avoided))
    limit = time_limit_for(config, path_length(np.asarray(world.start[:2]), current.checkpoints), robot.max_wheel_speed)
    rec.time_limit_s = limit
    return Run(world, seed, body, current, world, rec, math.ceil(limit / robot.avoid_period - 1e-9),
               poses=[np.asarray(world.start, float)], times=[0.0])


def _taken(run: Run, outs: TickOut, i: int, setup: Setup) -> None:
    """Append run ``i``'s live ticks of one chunk's outputs ``outs`` (NumPy, ``(B, ticks, ...)``) to its record —
    a prefix of the chunk: a run leaves :data:`RUNNING` at most once in a chunk."""
    live = np.flatnonzero(outs.live[i])
    if not len(live):
        return
    dt, n = setup.params.dt, setup.n
    t0 = run.times[-1]
    starts = t0 + n * dt * np.arange(len(live))  # each tick's time
    poses, irs, commands = outs.pose[i, live].astype(float), outs.ir[i, live].astype(float), outs.command[i, live]
    commanded, collisions = outs.commanded[i, live], outs.collisions[i, live]
    markers = outs.markers[i, live, :len(run.world.moving)]  # the world's own rows, as the pymunk runner keeps them
    if run.world.moving_goal:
        run.rec.goal_path = np.vstack([run.rec.goal_path, outs.goal[i, live].astype(float)])
    for j in np.flatnonzero(np.isfinite(irs).any(axis=1)):
        run.sensed.append((starts[j], poses[j], irs[j], markers[j]))
    run.rec.commands.extend((starts[j], float(commands[j, 0]), float(commands[j, 1]))
                            for j in np.flatnonzero(commanded))
    trace = outs.trace[i, live].astype(float)
    run.poses.extend(trace.reshape(-1, 3))
    run.times.extend(t0 + dt * np.arange(1, len(live) * n + 1))
    for j in np.flatnonzero(commanded & (collisions > np.concatenate([[run.collisions], collisions[:-1]]))):
        new = int(collisions[j]) - (run.collisions if j == 0 else int(collisions[j - 1]))
        end = starts[j] + n * dt
        run.rec.collision_log.extend([(end, float(trace[j, -1, 0]), float(trace[j, -1, 1]))] * new)
    if commanded[-1]:  # as the pymunk runner's drive logs them: not on the stop at the goal
        run.collisions = int(collisions[-1])


def finish_run(run: Run, status: int, state: RunState) -> RunRecord:
    """The record of a run that ended with ``status`` in ``state`` (one run's, NumPy): the outcome measured on its
    traces as :func:`evaluation.scenario.finish` measures it, the controller's state its ``final_state``."""
    rec = run.rec
    rec.ended = run.trapped_why if status == TRAPPED else ENDED[status]
    rec.arrived, rec.trapped = status in (ARRIVED, CAUGHT), status == TRAPPED
    rec.replans, rec.recoveries = run.replans, run.recoveries
    rec.poses, rec.times = np.asarray(run.poses), np.asarray(run.times)
    rec.time_s = float(state.stop_t) if rec.arrived else float(rec.times[-1])
    rec.path_m = float(np.linalg.norm(np.diff(rec.poses[:, :2], axis=0), axis=1).sum())
    rec.collisions, rec.contact_s = int(state.engine.collisions), float(state.engine.contact_s)
    rec.checkpoints_reached = int(state.passed)
    rec.final_distance_m = float(np.linalg.norm(rec.poses[-1, :2] - np.asarray(run.world.goal_at(rec.times[-1]))))
    rec.reached = rec.arrived and rec.collisions == 0
    rec.final_state = state.control
    return rec


def recover(run: Run, pose, t: float, config: ScenarioConfig):
    """The pymunk runner's recovery (:func:`evaluation.scenario.watch`) for a run whose monitor fired at ``t`` with
    the robot at ``pose``: its checkpoints after the new plan, or None (it ends trapped: no recovery left, or no
    route round what it sensed)."""
    if not config.recover or run.recoveries >= config.max_recoveries:
        return None
    run.recoveries += 1
    body = run.body
    found = recovery(run.plan, run.known, run.sensed, body, pose[:2], t, config)
    if found is None:
        run.trapped_why = "trapped (no route around the sensed obstacle)"
        return None
    return _adopted(run, t, "recovery", *found)


def _adopted(run: Run, t: float, reason: str, current, known, added) -> np.ndarray:
    """Run ``run`` on the plan ``current`` made at ``t`` for ``reason`` round what ``added`` put on the map ``known``
    (recorded as a :class:`PlanChange`): its checkpoints."""
    run.rec.plans.append(PlanChange(t, reason, current.checkpoints.copy(), added, current.avoided))
    run.plan, run.known, run.replans, run.map_t = current, known, run.replans + 1, t
    return current.checkpoints


def unblock(run: Run, pose, t: float, config: ScenarioConfig):
    """The pymunk runner's replan round a blocked checkpoint (:func:`evaluation.scenario.watch`) for a run whose IR
    showed it at ``t`` with the robot at ``pose``: its checkpoints on the new plan, or None (what it sensed leaves no
    route: the checkpoint stays)."""
    found = recovery(run.plan, run.known, run.sensed, run.body, pose[:2], t, config, near_only=True)
    return None if found is None else _adopted(run, t, "blocked checkpoint", *found)


def after_event(run: Run, pose, t: float, config: ScenarioConfig):
    """The pymunk runner's replan after a known event (:func:`evaluation.scenario.after_events`) for a run whose
    map changed by ``t``, the robot at ``pose``: its checkpoints on the new plan, or None (no route)."""
    current = replan_from(run.plan, run.known, np.asarray(pose[:2], float), t, run.body.robot, config)
    if current is None:
        return None
    run.rec.plans.append(PlanChange(t, "event", current.checkpoints.copy(), avoided=current.avoided))
    run.plan, run.replans, run.map_t = current, run.replans + 1, t
    return current.checkpoints


def setup_for(body, func, static, config: ScenarioConfig) -> Setup:
    """The :class:`Setup` of a batch driven by ``body`` (a controller: robot and sensors) with the step
    ``func``/``static``."""
    robot = body.robot
    n = robot.substeps(robot.avoid_period)
    rule = jaxmonitor.MonitorRule(config.trap_after, config.trap_progress, config.trap_ground, config.trap_loop)
    return Setup(params=robot, sensors=body.sensors, n=n, k=robot.noise_shape(robot.avoid_period)[0], config=config,
                 rule=rule, func=func, static=static)


#: The fewest markers' rows of a batch of worlds with movers: fewer shapes to compile (1 to 4 movers share one).
MIN_MARKERS = 4


def kind(world) -> tuple[bool, int, bool]:
    """The batch a world runs in: whether it has movers or timed events, its markers' rows (its movers rounded
    up to a power of two, at least :data:`MIN_MARKERS`; 0 without movers), and whether its goal moves."""
    return (has_dynamics(world), (max(MIN_MARKERS, _bucket(len(world.moving))) if world.moving else 0),
            world.moving_goal)


def run_batch(runs: list[Run], controls: list, arrays: list, setup: Setup, on_done, chunk_ticks: int = CHUNK_TICKS,
              between=lambda: None, threads: int = THREADS) -> None:
    """Drive ``runs`` (started by :func:`start_run`) to their ends, in one batch for each :func:`kind` of world
    (:func:`batches`), ``threads`` of them at once (:func:`in_threads`): ``controls[i]`` the controller's fresh state
    and ``arrays[i]`` its step's array keywords (:func:`~evaluation.scenario.split_step`) for run ``i``.
    ``on_done(i, record)`` receives each run's :class:`RunRecord` as it ends (at the end of the chunk it ended in,
    from the thread of its batch); ``between()`` is called between chunks (Ctrl-C). The imperative shell of the
    module docstring."""
    in_threads(batches(runs, controls, arrays, setup, on_done, chunk_ticks, between), threads)


def batches(runs: list[Run], controls: list, arrays: list, setup: Setup, on_done, chunk_ticks: int = CHUNK_TICKS,
            between=lambda: None) -> list:
    """:func:`run_batch`'s work as one callable for each :func:`kind` of world among ``runs``: each drives its runs
    to their ends in one batch."""
    groups: dict = {}
    for i, r in enumerate(runs):
        groups.setdefault(kind(r.world), []).append(i)
    return [partial(_run_group, [runs[i] for i in members], [controls[i] for i in members],
                    [arrays[i] for i in members], replace(setup, dynamic=dynamic, markers=rows, chase=chase),
                    lambda k, rec, members=members: on_done(members[k], rec), chunk_ticks, between)
            for (dynamic, rows, chase), members in sorted(groups.items())]


def in_threads(tasks: list, threads: int = THREADS) -> None:
    """Call each of ``tasks`` (no arguments), ``threads`` at a time, in their order. Once one raises (a
    KeyboardInterrupt from ``between`` included) none is started any more; when the running ones have returned, the
    first failed task's exception (in the tasks' order) is raised. Why threads: XLA compiles a program, and runs a
    scan, without Python's lock, so one batch's compiling (on one core) or host work goes on beside another's scan
    (measured in docs/performance.md)."""
    if threads <= 1 or len(tasks) <= 1:
        for task in tasks:
            task()
        return
    with ThreadPoolExecutor(max_workers=threads) as pool:
        futures = [pool.submit(task) for task in tasks]
        try:
            wait(futures, return_when=FIRST_EXCEPTION)
        finally:  # a task failed, or Ctrl-C here: start no more; the pool's exit waits for the running ones
            for f in futures:
                f.cancel()
    for f in futures:
        if not f.cancelled():
            f.result()


def _radii(world, m: int) -> np.ndarray:
    """The markers' radii ``(m,)`` of ``world``'s movers, -1 for the padding rows."""
    radii = np.full(m, -1.0, np.float32)
    radii[:len(world.moving)] = [mover_radius(mv.shape) for mv in world.moving]
    return radii


def _run_group(runs: list[Run], controls: list, arrays: list, setup: Setup, on_done, chunk_ticks: int,
               between) -> None:
    """:func:`run_batch` for runs of one :func:`kind`, ``setup`` set for it."""
    config = setup.config
    b = len(runs)
    # blocks of two runs at least: XLA compiles a vmap of one run as unbatched code, whose float rounding differs
    # in the last bit from the batched code every wider block shares, so a lone run would end otherwise than the
    # same run in a batch (a run is a function of its job alone, docs/design.md §5)
    blk = min(BLOCK, max(b, 2))
    slots = runs + [runs[0]] * (-b % blk)  # padding to whole blocks: copies of run 0 that never run
    controls, arrays = controls + [controls[0]] * (len(slots) - b), arrays + [arrays[0]] * (len(slots) - b)
    ids = np.where(np.arange(len(slots)) < b, np.arange(len(slots)), -1)
    may = config.recover and config.max_recoveries > 0
    extent = np.max([r.world.size for r in runs], axis=0)
    grid = jaxmonitor.grid_size(extent, config.trap_ground)
    cps = [np.asarray(r.plan.checkpoints, np.float32) for r in slots]
    room = ROOM if may else 0
    scene = _scenes([r.world for r in slots], movers=max(setup.markers, 1))
    m = shape_of(scene)[3]
    routes = Route(scene=scene, sight=_scenes([_sight_world(r.known, r.map_t, r.plan.avoided) for r in slots], room),
                   checkpoints=_padded(cps, _bucket(max(len(c) for c in cps) + (SLOTS if may else 0))),
                   last=np.array([len(c) - 1 for c in cps], np.int32),
                   ticks=np.array([r.ticks for r in slots], np.int32), may_recover=np.full(len(slots), may),
                   radii=np.stack([_radii(r.world, m) for r in slots]),
                   goal_path=stack([paths_of([r.world.goal] if r.world.moving_goal else [], 1) for r in slots]))
    starts = jnp.asarray(np.stack([r.world.start for r in slots]), jnp.float32)
    eng = jax.vmap(partial(engine.reset, params=setup.params))(starts, jax.tree.map(jnp.asarray, routes.scene))
    joined = partial(jax.tree.map, lambda *a: jnp.stack(a))
    zeros = partial(jnp.zeros, len(slots))
    state = RunState(engine=eng, control=joined(*controls),
                     key=jax.vmap(jax.random.PRNGKey)(jnp.array([r.seed for r in slots])), tick=zeros(jnp.int32),
                     index=zeros(jnp.int32), target_id=zeros(jnp.int32), settled=zeros(bool),
                     since=zeros(jnp.float32), turn_until=zeros(jnp.float32),
                     monitor=jax.tree.map(lambda a: jnp.broadcast_to(a, (len(slots),) + a.shape), jaxmonitor.init(grid)),
                     status=jnp.asarray(np.where(ids >= 0, RUNNING, TIMEOUT), jnp.int32), passed=zeros(jnp.int32),
                     stop_t=zeros(jnp.float32), last_t=zeros(jnp.float32),
                     looked_past=jnp.tile(jnp.array([0, -1], jnp.int32), (len(slots), 1)),
                     unblockable=jnp.full(len(slots), -1, jnp.int32))
    arrays = joined(*arrays)
    open_ = ids >= 0
    while open_.any():
        state, outs = advance(setup, blk, routes, state, arrays, chunk_ticks)
        outs = jax.tree.map(np.asarray, outs)
        status = np.asarray(state.status)
        for k in np.flatnonzero(open_):
            _taken(slots[k], outs, k, setup)
        waiting = np.flatnonzero(open_ & ((status == WAITING) | (status == EVENT) | (status == BLOCKED)))
        if len(waiting):
            routes, state = _replans(slots, waiting, routes, state, setup)
            status = np.asarray(state.status)
        ended = np.flatnonzero(open_ & (status >= ARRIVED))
        if len(ended):
            host = jax.tree.map(np.array, state)  # a copy: the next chunk reuses the state's buffers
        for k in ended:
            one = jax.tree.map(lambda a: a[k], host)
            on_done(int(ids[k]), finish_run(slots[k], int(status[k]), one))
            open_[k] = False
        if len(ended):  # the open runs first, so that whole blocks of ended ones are skipped
            order = np.argsort(~open_, kind="stable")
            routes, state, arrays = jax.tree.map(lambda a: a[order], (routes, state, arrays))
            slots, ids, open_ = [slots[k] for k in order], ids[order], open_[order]
        between()


def _replans(runs: list, waiting, routes: Route, state: RunState, setup: Setup):
    """New plans for every run in ``waiting`` — recovery (:data:`WAITING`, :func:`recover`), a known event
    (:data:`EVENT`, :func:`after_event`) or a blocked checkpoint (:data:`BLOCKED`, :func:`unblock`) — into ``routes``
    with their maps, the runs' states restarted on them (index 0, a new target, the monitor reset; after a recovery or
    a blocked checkpoint a turn to face the route) — or ended (trapped; no route), or, for a blocked checkpoint with no
    route round it, going on as they were."""
    config = setup.config
    poses = np.asarray(state.engine.robot.pose)
    ks = np.asarray(state.engine.k)
    status = np.asarray(state.status).copy()
    new = {}
    act = {WAITING: recover, EVENT: after_event, BLOCKED: unblock}
    for i in waiting:
        t = float(np.float32(ks[i]) * np.float32(setup.params.dt))
        new[int(i)] = (t, int(status[i]), act[int(status[i])](runs[i], poses[i], t, config))
    cps = [np.asarray(r.plan.checkpoints, np.float32) for r in runs]
    slots = max(routes.checkpoints.shape[1], _bucket(max(len(c) for c in cps)))
    routes = routes._replace(sight=_grown(routes.sight, runs, [i for i, (_, _, c) in new.items() if c is not None]),
                             checkpoints=_padded(cps, slots), last=np.array([len(c) - 1 for c in cps], np.int32))
    index, target_id, turn_until, last_t, past, unblockable = (np.asarray(a).copy() for a in (
        state.index, state.target_id, state.turn_until, state.last_t, state.looked_past, state.unblockable))
    ticks = np.asarray(state.tick)
    when, at = np.zeros(len(runs), bool), np.zeros(len(runs), np.float32)
    for i, (t, why, checkpoints) in new.items():
        going_on = TIMEOUT if ticks[i] >= routes.ticks[i] else RUNNING
        if checkpoints is None:
            if why == BLOCKED:
                unblockable[i], status[i] = target_id[i], going_on
            else:
                status[i] = NO_ROUTE if why == EVENT else TRAPPED
            continue
        when[i], at[i] = True, t
        index[i], target_id[i], past[i] = 0, target_id[i] + 1, (0, -1)
        if why == EVENT:
            last_t[i] = t  # the tick at t runs next, on the new plan, and does not replan again
        else:
            turn_until[i] = t + config.turn_s
        status[i] = going_on
    monitor = jaxmonitor.reset(state.monitor, jnp.asarray(at), jnp.asarray(when))
    may = routes.may_recover.copy()
    for r_i, r in enumerate(runs):
        may[r_i] = config.recover and r.recoveries < config.max_recoveries
    routes = routes._replace(may_recover=may)
    state = state._replace(status=jnp.asarray(status), index=jnp.asarray(index), target_id=jnp.asarray(target_id),
                           turn_until=jnp.asarray(turn_until, jnp.float32), last_t=jnp.asarray(last_t, jnp.float32),
                           monitor=monitor, looked_past=jnp.asarray(past, jnp.int32),
                           unblockable=jnp.asarray(unblockable, jnp.int32))
    return routes, state


def _grown(sight: Scene, runs: list, changed: list) -> Scene:
    """The batch's ``sight`` with the maps of the ``changed`` runs made again; every run's again, to a larger
    shape, when one of them no longer fits."""
    shape = shape_of(sight)
    try:
        rows = {i: scene_of(_sight_world(runs[i].known, runs[i].map_t, runs[i].plan.avoided), shape) for i in changed}
    except ValueError:  # recovery's discs outgrew the padding
        return _scenes([_sight_world(r.known, r.map_t, r.plan.avoided) for r in runs], ROOM)
    leaves, tree = jax.tree.flatten(sight)
    leaves = [np.array(a) for a in leaves]
    for i, scene in rows.items():
        for leaf, row in zip(leaves, jax.tree.leaves(scene)):
            leaf[i] = row
    return jax.tree.unflatten(tree, leaves)


def run_jobs(job_list: list, on_done=None, *, done: dict | None = None, chunk_ticks: int = CHUNK_TICKS) -> list[dict]:
    """The records of a comparison's jobs (:class:`evaluation.compare.Job`) on the JAX engine, in the jobs' order
    (:func:`evaluation.batch.kept`'s ``run``): one batch per architecture (and map, robot, learning rule, config)
    over all its worlds and seeds. ``done``: ``{index: record}`` already made, not run again; ``on_done(index,
    record)`` as each run ends. A job that cannot start — its world has movers, events or a moving goal, no route,
    a start the robot does not fit — is a failed record (:func:`evaluation.compare.failed_record`), as on pymunk."""
    from ekm import interrupts
    from evaluation.compare import _world, failed_record, failure, job_driver, job_record, world_family
    from evaluation.scenario import driven

    records: list = [None] * len(job_list)
    for i, record in (done or {}).items():
        records[i] = record
    lock = threading.Lock()

    def finish(i: int, record: dict) -> None:
        with lock:  # batches end runs from their threads
            records[i] = record
            if on_done:
                on_done(i, record)

    groups: dict = {}
    for i, job in enumerate(job_list):
        if records[i] is None:
            groups.setdefault((job.architecture, job.map_path, job.robot, job.learn, job.config, job.added), []).append(i)
    plans: dict = {}
    tasks: list = []
    for members in groups.values():
        runs, drivers, batch = [], [], []
        for i in members:
            job, world = job_list[i], None
            try:
                d = job_driver(job)
                world = _world(job.world)
                runs.append(start_run(world, d.controller, job.seed, job.config, d.controller.spec, plans))
            except Exception as exc:
                finish(i, failed_record(job, failure(job, exc), world.name if world is not None else None,
                                        world_family(world) if world is not None else None))
                continue
            drivers.append(d)
            batch.append(i)
        if not batch:
            continue
        parts = [split_step(d.controller.step) for d in drivers]
        if parts[0] is None or any(p is None or p[0] is not parts[0][0] or p[2] != parts[0][2] for p in parts):
            for i in batch:
                finish(i, failed_record(job_list[i], f"{job_list[i].world}: engine jax: the architecture's step is not "
                                        f"one jitted function with its maps as keywords; use the pymunk engine"))
            continue
        setup = setup_for(drivers[0].controller, parts[0][0], parts[0][2], job_list[batch[0]].config)

        def ended(k: int, rec: RunRecord, batch=batch, drivers=drivers) -> None:
            finish(batch[k], job_record(job_list[batch[k]], driven(rec, drivers[k])))

        tasks += batches(runs, [d.controller.init() for d in drivers], [p[1] for p in parts], setup, ended,
                         chunk_ticks, between=interrupts.check)
    in_threads(tasks)
    return records


def run_scenarios(runs, controller, config: ScenarioConfig = ScenarioConfig(),
                  chunk_ticks: int = CHUNK_TICKS, between=lambda: None) -> list[RunRecord]:
    """:func:`evaluation.scenario.run_scenario` for many runs of one ``controller`` at once: ``runs`` a list of
    ``(world, seed)``; their :class:`RunRecord` in that order (raises what :func:`start_run` raises for a run that
    cannot start). The controller's step must be one jitted function with keywords
    (:func:`~evaluation.scenario.split_step`), as every shipped architecture's is. ``between()`` is called between
    chunks (:func:`run_batch`)."""
    from ekm.errors import InputError

    parts = split_step(controller.step)
    if parts is None:
        raise InputError(f"engine jax: the step of {controller.name} is not a partial of one function with keywords")
    func, arrays, static = parts
    plans: dict = {}
    started = [start_run(world, controller, seed, config, controller.spec, plans) for world, seed in runs]
    records: list = [None] * len(started)
    run_batch(started, [controller.init()] * len(started), [arrays] * len(started),
              setup_for(controller, func, static, config), records.__setitem__, chunk_ticks, between=between)
    return records
