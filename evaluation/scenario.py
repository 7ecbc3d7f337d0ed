"""The scenario runner: one robot, one world, one architecture, one seed (docs/design.md §5, §6; thesis ch. 6.2).

The imperative shell around a pure controller (:mod:`robots.controllers`): the pymunk world
(:class:`robots.world.PymunkWorld` — walls, unforeseen, moving and event obstacles, contact, IR, the
robot's motor and sensor noise), the slippery-cell planner (:mod:`planner`) and a trap monitor
(:mod:`evaluation.monitor`). Every 0.128 s tick (the obstacle-avoidance period of ch. 6.2):

1. if a known event changed the planner's map since the last tick, replan from where the robot is
   (Fig. 6.5) and hand the controller the new first checkpoint;
2. sense, and give the controller one :class:`~robots.controllers.base.Observation`: the IR readings,
   the current checkpoint as u_p = (α, d), the declared moving objects;
3. send its command for one period and read the sub-step trace: a checkpoint counts as reached the
   first time the robot's centre is within 5 mm of it (ch. 6.2.1), on the 16 ms sub-steps;
4. at the goal the robot must stop (ch. 6.2.1): the run ends when, with the centre within 5 mm of the
   goal, the controller's command rounds to zero (Eq. 6.1's "motor control c = 0"), or the centre has
   stayed within the 5 mm for ``settle_s`` (one 1.024 s target-reaching period) — a precise map
   often keeps nudging at the millimetre scale instead of sending an exact zero (README, "Capped
   targets"), and then the executive halts the motors; a robot passing through the goal does not
   stay within 5 mm for a second. A moving goal (Samba's scenario) is reached when it comes under
   the robot's body (centre within the body radius);
5. the trap monitor (:mod:`evaluation.monitor`) reports ``trapped`` when the robot has come no closer to
   its checkpoint and reached no new ground for a set time (thesis 7.1.1, cognizant failure); with
   ``recover`` (the default), the obstacle points the robot has sensed so far that the map does not
   explain join the planner's map (:func:`recovery`, :func:`with_sensed`), the route is replanned around them
   (around the near readings alone, or none, where they close every way) from where the robot is, and the robot turns on the spot to face the new route before its architecture takes
   over again (a trap is a balance between going on and backing off; a disc turning on the spot
   touches nothing new, and facing the new route breaks the balance); with recovery, a checkpoint the IR shows no
   robot can stand at (an unforeseen obstacle within the robot's radius of it, :func:`blocked_checkpoint`) is
   replanned round the near readings at once, no recovery spent.

The plan is :func:`planner.plan`'s with the config's checkpoint rule (``visible`` by default, ``thesis``
for ch. 3.2.3 as written) and its cell, refined automatically where a narrow place holds no free cell.

A run **reaches** the goal when the robot stops there without a single collision on the way: every
contact episode of its body with anything (wall, obstacle, mover) is counted and never hidden, and the
time spent in contact is reported. A run is a pure function of (world, controller, seed): the world's
noise streams are seeded, the controller is pure, and nothing else is random.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field, replace

import numpy as np

from ekm.errors import InputError
from evaluation.monitor import TrapMonitor
from planner import DEFAULT_CELL, RULES, map_changed, plan, replan, visibility
from planner.bitmap import padded_obstacles
from robots.controllers.base import Controller, Observation, hit_points
from robots.geometry import Circle, bounds
from robots.kinematics import egocentric, is_stop_command
from robots.world import PymunkWorld
from robots.worldfile import World


@dataclass(frozen=True)
class ScenarioConfig:
    """How a run is judged. Defaults: ch. 6.2.1's 5 mm checkpoints; the rest is this package's choice."""

    checkpoint_tolerance: float = 0.005  # m: a checkpoint (and the goal) is reached within 5 mm (ch. 6.2.1)
    settle_s: float = 1.024  # s within the goal's tolerance after which the robot counts as stopped there
    capture_radius: float | None = None  # m: a moving goal is caught within this; None = the body radius
    time_limit: float | None = None  # s of simulated time; None: follows the route (:func:`time_limit_for`)
    trap_after: float = 20.0  # s without progress (closer, or new ground) before the monitor says trapped
    trap_progress: float = 0.01  # m: coming this much closer to the checkpoint than ever before is progress
    trap_ground: float = 0.05  # m: side of the squares of ground; entering one never visited is progress
    trap_loop: float | None = 1.5  # m driven on ground visited before without coming closer: a loop (None: off)
    recover: bool = True  # on a trap, add the sensed obstacle to the map and replan (thesis 7.1.1)
    max_recoveries: int = 5  # traps recovered from before a run gives up
    blocked: bool = True  # with recover: replan at once round a checkpoint the IR shows no robot can stand at
    sensed_radius: float = 0.005  # m: an obstacle point added to the map on recovery: a disc of the IR's τ
    sensed_near: float = 0.05  # m: where all it sensed leaves no route, recovery plans round the readings this near
    cell: float = DEFAULT_CELL  # m: the planner's bitmap cell (halved while no route exists, if ``refine``)
    refine: bool = True  # refine the cell where the map's narrow places hold no route at ``cell``
    checkpoints: str = "visible"  # the planner's checkpoint rule: visible (default) or thesis (ch. 3.2.3)
    lane_margin: float | None = 0.01  # m: the planner keeps the robot this far beside a declared mover's lane
    #                                   (planner.lanes; None, or thesis checkpoints: as before issue 35)
    lane_detour: float = 1.3  # ... where that makes the route at most this much longer
    start_reach: float = 0.06  # m: a replan may start this far from the robot (pressed into a new cushion)
    pass_radius: float = 0.1  # m: visible checkpoints: within this of one whose successor it sees, the robot
    #                           moves on to the successor
    look_every: int = 4  # ticks: visible checkpoints: this often the robot looks for a later checkpoint it sees
    look_ahead: int = 3  # ... among this many after the current one, and moves on to the last it sees
    look_back: int = 3  # ... and when a known wall comes between it and its checkpoint, turns back to the latest
    #                     of this many before it that the look ahead took it past and that it sees (0: never)
    turn_s: float = 3.0  # s: after a recovery the robot turns on the spot to face the new route for at most this
    turn_tolerance: float = 0.2  # rad: ... until the first checkpoint is within this of straight ahead

    def __post_init__(self):
        if self.checkpoints not in RULES:
            raise InputError(f"scenario: checkpoints must be one of {', '.join(RULES)}, got {self.checkpoints!r}")
        if self.time_limit is not None and not (isinstance(self.time_limit, (int, float))
                                                and math.isfinite(self.time_limit) and self.time_limit > 0):
            raise InputError(f"scenario: time_limit must be a positive number or None, got {self.time_limit!r}")
        for name in ("checkpoint_tolerance", "settle_s", "trap_after", "trap_progress", "trap_ground",
                     "sensed_radius", "sensed_near", "cell", "start_reach", "pass_radius", "turn_s", "turn_tolerance"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise InputError(f"scenario: {name} must be a positive number, got {value!r}")
        if self.trap_loop is not None and not self.trap_loop > 0:
            raise InputError(f"scenario: trap_loop must be > 0 or None, got {self.trap_loop!r}")
        if self.capture_radius is not None and not self.capture_radius > 0:
            raise InputError(f"scenario: capture_radius must be > 0, got {self.capture_radius!r}")
        if self.look_every < 1 or self.look_ahead < 0 or self.look_back < 0:
            raise InputError(f"scenario: look_every must be >= 1 and look_ahead and look_back >= 0, got "
                             f"{self.look_every}, {self.look_ahead}, {self.look_back}")
        if self.max_recoveries < 0:
            raise InputError(f"scenario: max_recoveries must be >= 0, got {self.max_recoveries}")
        if self.lane_margin is not None and not (isinstance(self.lane_margin, (int, float))
                                                 and math.isfinite(self.lane_margin) and self.lane_margin >= 0):
            raise InputError(f"scenario: lane_margin must be a number >= 0 or None, got {self.lane_margin!r}")
        if not (isinstance(self.lane_detour, (int, float)) and self.lane_detour >= 1):
            raise InputError(f"scenario: lane_detour must be >= 1, got {self.lane_detour!r}")

    @property
    def lanes(self) -> tuple[float, float] | None:
        """The planner's ``lanes`` argument (:func:`planner.plan`): ``(lane_margin, lane_detour)``; None when
        ``lane_margin`` is None or with the thesis's checkpoints, whose set-up plans on the a-priori map alone."""
        if self.lane_margin is None or self.checkpoints == "thesis":
            return None
        return float(self.lane_margin), float(self.lane_detour)


#: s: the shortest default time limit (the package's fixed limit before issue 35: the named worlds' routes all take
#: less than a tenth of it at top speed, so their runs are judged as before).
TIME_FLOOR_S = 120.0
#: The default time limit is this many times the planned route's time at the robot's top speed.
TIME_PER_ROUTE = 10.0


def time_limit_for(config: ScenarioConfig, route_m: float, top_speed: float) -> float:
    """The run's time limit (s): ``config.time_limit`` when given, else
    ``max(TIME_FLOOR_S, TIME_PER_ROUTE × route_m / top_speed)`` — ``route_m`` the planned route's length (m, start to
    goal along the checkpoints), ``top_speed`` the robot's c* (m/s). A fixed limit starves long routes (a 6 m route
    takes 38 s at 0.16 m/s and a robot at half speed twice that) and is slack on short ones; ten times the optimal
    time is past the BARN score's 8x clip, so a run within the limit can still score."""
    if config.time_limit is not None:
        return float(config.time_limit)
    return max(TIME_FLOOR_S, TIME_PER_ROUTE * route_m / top_speed)


#: The reasons of the plans that add what the robot sensed to the planner's map (:class:`PlanChange`).
SENSED = ("recovery", "blocked checkpoint")


@dataclass(frozen=True)
class PlanChange:
    """A plan the robot followed from ``t``: why it was made, its checkpoints ``(k, 2)`` (goal last), for
    a recovery the sensed obstacle points ``(n, 2)`` that joined the planner's map for it, and the declared movers'
    lanes its route keeps off (``Plan.avoided``, :mod:`planner.lanes`)."""

    t: float
    reason: str  # "start", "event" (a known change of the map, Fig. 6.5), "recovery" (after a trap) or "blocked
    #              checkpoint" (the IR saw one the robot cannot reach); the last two add what the IR sensed (SENSED)
    checkpoints: np.ndarray
    added: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    avoided: tuple = ()


@dataclass
class RunRecord:
    """Everything a run did: the outcome (docs/design.md §6) and the traces the plots draw."""

    world: World
    architecture: str
    seed: int
    map_source: str = ""  # which map drove ("" for an architecture that drives none)
    trial: int | None = 0
    reached: bool = False
    arrived: bool = False
    time_s: float = 0.0
    path_m: float = 0.0
    collisions: int = 0
    contact_s: float = 0.0
    checkpoints_reached: int = 0
    replans: int = 0
    recoveries: int = 0
    trapped: bool = False
    final_distance_m: float = math.nan
    ended: str = ""
    time_limit_s: float = math.nan  # the run's time limit (:func:`time_limit_for`)
    period: float = 0.128
    poses: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))  # (S, 3): start, then every sub-step
    times: np.ndarray = field(default_factory=lambda: np.zeros(0))  # (S,) time of each pose
    commands: list = field(default_factory=list)  # (t, v_l, v_r) sent each tick
    plans: list = field(default_factory=list)  # PlanChange
    checkpoint_log: list = field(default_factory=list)  # (t, x, y) of each checkpoint reached
    collision_log: list = field(default_factory=list)  # (t, x, y) of the robot at each new contact episode
    trap_log: list = field(default_factory=list)  # (t, x, y) where the monitor fired
    hits: list = field(default_factory=list)  # (t, (n, 2) world points the IR saw)
    goal_path: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))  # (ticks, 2) goal at each tick
    robot: object = None  # the RobotParams that drove
    map_robot: str | None = None  # the robot the map was trained on (None: no map)
    final_state: object = None  # the controller's state when the run ended
    learned: object = None  # with learning: the map the run ended with (one trial's pytree)
    updates: int | None = None  # with learning: the map's updates during the run

    def outcome(self) -> dict:
        """The ``ekm run --json`` record: ``world, architecture, reached, time_s, path_m, collisions`` (contact
        episodes), ``checkpoints_reached, replans, trapped, final_distance_m``, then ``contact_s`` (time in
        contact), ``arrived`` (stopped at the goal, collisions or not), ``recoveries``, ``ended`` (why the run
        stopped), ``seed``, ``map`` and ``trial`` (which map drove), then how it moved (each measure of
        :data:`evaluation.motion.MEASURES`, by key), then the robot (:meth:`robot_record`)."""
        return {"world": self.world.name, "architecture": self.architecture, "reached": self.reached,
                "time_s": round(self.time_s, 3), "path_m": round(self.path_m, 4), "collisions": self.collisions,
                "checkpoints_reached": self.checkpoints_reached, "replans": self.replans, "trapped": self.trapped,
                "final_distance_m": round(self.final_distance_m, 5), "contact_s": round(self.contact_s, 3),
                "arrived": self.arrived,
                "recoveries": self.recoveries, "ended": self.ended, "seed": self.seed,
                "map": self.map_source or None, "trial": self.trial, **self.motion(), **self.robot_record()}

    def robot_record(self) -> dict:
        """Which robot drove (``robot``, its physics' ``robot_fingerprint``), which the map was trained on
        (``map_robot``; None without a map) and, when the map learned during the run, its ``updates``."""
        from robots.params import KHEPERA

        robot = self.robot or KHEPERA
        return {"robot": robot.name, "robot_fingerprint": robot.fingerprint, "map_robot": self.map_robot,
                "updates": self.updates}

    def motion(self) -> dict:
        """How the run moved (:func:`evaluation.motion.measures`), the planner's first route as the reference."""
        from evaluation import motion

        from planner.checkpoints import path_length
        from robots.params import KHEPERA

        route = path_length(self.poses[0, :2], self.plans[0].checkpoints) if self.plans and len(self.poses) else 0.0
        # a moving goal is caught, not stopped at: its precision is the capture radius, not the robot's
        robot = self.robot or KHEPERA
        return motion.measures([c[1:] for c in self.commands], self.times, self.poses, self.period,
                               self.world.goal_at, route, self.arrived and not self.world.moving_goal,
                               reached=self.reached, time_s=self.time_s, top_speed=robot.max_wheel_speed)


def mover_radius(shape) -> float:
    """Radius of the disc round a moving shape's origin that holds it (its marker's size)."""
    x0, y0, x1, y1 = bounds(shape)
    return float(max(math.hypot(x, y) for x in (x0, x1) for y in (y0, y1))) if not isinstance(shape, Circle) \
        else math.hypot(*shape.center) + shape.radius


def run_scenario(world: World, controller: Controller, seed: int = 0, config: ScenarioConfig = ScenarioConfig(),
                 on_tick=None) -> RunRecord:
    """Drive ``controller`` through ``world`` from its start to its goal (see the module docstring).

    ``on_tick(t)`` is called after every tick (progress bars). Raises :class:`InputError` if the planner
    finds no route at the start (a world it cannot route through, or a start inside an obstacle).
    """
    state = controller.init()
    step = _in_one_loop(controller.step)
    ticks = episode(world, controller, seed, config, controller.spec, on_tick)
    try:
        obs = next(ticks)
        while True:
            state, command = step(state, obs)
            obs = ticks.send(command)
    except StopIteration as done:
        rec = done.value
        rec.final_state = state
        return rec


def episode(world: World, body, seed: int = 0, config: ScenarioConfig = ScenarioConfig(), spec: str = "",
            on_tick=None, report: dict | None = None):
    """The run of :func:`run_scenario` as a generator, for whatever chooses the commands (a controller, or a
    reinforcement-learning agent through :mod:`ekm.gym`): it yields the :class:`Observation` of each tick on
    which a command is wanted, takes the ``(2,)`` wheel speeds (m/s) sent back, and returns the
    :class:`RunRecord` when the run ends (``StopIteration.value``). ``body`` gives the ``sensors`` and the
    ``robot`` (a :class:`Controller` does). Ticks on which recovery turns the robot on the spot are not
    yielded. ``report``, if given, is kept up to date before each yield: ``collisions`` (contact episodes so
    far) and ``route_m`` (m along the plan still to go: to the current checkpoint, then leg by leg to the
    goal).

    A tick is the steps of the module docstring, each a function of the :class:`Course` so far that returns the
    next one; the physics, the trap monitor and the record being written are the :class:`Shell` they act on."""
    shell, course = start(world, body, seed, config, spec, on_tick)
    from planner.checkpoints import path_length

    limit = time_limit_for(config, path_length(np.asarray(world.start[:2]), course.plan.checkpoints),
                           shell.robot.max_wheel_speed)
    shell.rec.time_limit_s = limit
    for tick in range(math.ceil(limit / shell.period - 1e-9)):
        t = shell.sim.t
        course = after_events(shell, course, t)
        if course.ended:
            break
        course = pass_checkpoints(shell, course, t, tick)
        obs, pose, goal = observe(shell, course, t)
        if t < course.turn_until and abs(float(obs.target[0])) > config.turn_tolerance:
            command = turn_on_the_spot(float(obs.target[0]), shell.robot)  # recovery: face the new route first
        else:
            course = replace(course, turn_until=0.0)
            if report is not None:
                report.update(collisions=shell.sim.collisions, route_m=course.route_m(pose, goal))
            command = np.asarray((yield obs), dtype=float)
        course = stop_at_goal(shell, course, t, pose, goal, command)
        if course.ended:
            break
        course, moved_on = drive(shell, course, t, goal, command)
        if course.ended:
            break
        if not moved_on:
            course = watch(shell, course)
            if course.ended:
                break
    else:
        course = replace(course, ended="time limit")
    return finish(shell, course)


@dataclass(frozen=True)
class Course:
    """What a run carries from tick to tick, as a value (every step returns a new one): the plan it follows and
    the checkpoint it heads for (``index``; ``target_id`` changes with every new checkpoint, as the controller
    sees it), the planner's map (``known``: the world's known shapes and what recovery added) and its padded
    obstacles (``sight``, for the look past a checkpoint), the time of the last tick (``last_t``: an event since
    then replans), the contact episodes logged so far, since when the robot has stood within the goal's tolerance
    (``settled_since``), until when it turns on the spot after a recovery (``turn_until``), the replans and
    recoveries so far, the checkpoints of the plan the look ahead took it past without reaching them
    (``looked_past``: first and last index; empty when first > last), and how it ended (``ended``: "" while it
    runs; ``arrived``, ``trapped``)."""

    plan: object
    known: World
    sight: object
    index: int = 0
    target_id: int = 0
    last_t: float = 0.0
    collisions: int = 0
    settled_since: float | None = None
    turn_until: float = 0.0
    replans: int = 0
    recoveries: int = 0
    looked_past: tuple[int, int] = (0, -1)
    unblockable: int = -1
    ended: str = ""
    arrived: bool = False
    trapped: bool = False

    @property
    def final(self) -> bool:
        """Whether the checkpoint it heads for is the goal."""
        return self.index == len(self.plan.checkpoints) - 1

    def target(self, world: World, t: float) -> np.ndarray:
        """The point it heads for at ``t``: the checkpoint, or the goal where it is at ``t``."""
        return np.asarray(world.goal_at(t) if self.final else self.plan.checkpoints[self.index], dtype=float)

    def moved_on(self, by: int = 1) -> "Course":
        """The course ``by`` checkpoints further on, each a new target for the controller."""
        return replace(self, index=self.index + by, target_id=self.target_id + by)

    def route_m(self, pose, goal) -> float:
        """m along the plan still to go from ``pose``: to ``goal`` (the current target), then leg by leg."""
        legs = self.plan.checkpoints[self.index:]
        return float(np.linalg.norm(pose[:2] - goal) + np.linalg.norm(np.diff(legs, axis=0), axis=1).sum())


@dataclass
class Shell:
    """The imperative parts of a run that the steps act on: the world and the robot's ``body`` (its sensors and
    robot), the pymunk simulation, the trap monitor, the record being written, every tick's sensing on which the
    IR saw something (``sensed``: (t, pose, readings, markers)) and the pose trace (``poses``, ``times``)."""

    world: World
    body: object
    config: ScenarioConfig
    sim: PymunkWorld
    monitor: TrapMonitor
    rec: RunRecord
    radii: np.ndarray
    on_tick: object = None
    sensed: list = field(default_factory=list)
    poses: list = field(default_factory=list)
    times: list = field(default_factory=list)

    @property
    def robot(self):
        return self.body.robot

    @property
    def period(self) -> float:
        return self.body.robot.avoid_period

    def traced(self, t: float, trace) -> None:
        """Keep the sub-step poses ``trace`` of the period that began at ``t``."""
        self.poses.extend(trace)
        self.times.extend(t + self.robot.dt * np.arange(1, len(trace) + 1))


def start(world: World, body, seed: int, config: ScenarioConfig, spec: str, on_tick=None) -> tuple[Shell, Course]:
    """The world, the robot at its start and the first plan (raises :class:`InputError` if there is no route)."""
    robot = body.robot
    sim = PymunkWorld(world, params=robot, seed=seed)
    rec = RunRecord(world=world, architecture=spec, seed=seed, period=robot.avoid_period, robot=robot)
    current = first_plan(world, robot, config)
    rec.plans.append(PlanChange(0.0, "start", current.checkpoints.copy(), avoided=current.avoided))
    shell = Shell(world, body, config, sim, TrapMonitor(config.trap_after, config.trap_progress, config.trap_ground,
                                                          config.trap_loop),
                  rec, np.array([mover_radius(m.shape) for m in world.moving], dtype=np.float32), on_tick,
                  poses=[sim.pose], times=[0.0])
    return shell, Course(current, world, sight_of(world, 0.0, current, robot.radius))


def first_plan(world: World, robot, config: ScenarioConfig):
    """The plan a run starts with, from the world's start (raises :class:`InputError` if the robot does not fit
    there or the planner finds no route)."""
    clear = float(world.clearance(np.asarray(world.start[:2]), 0.0))
    if clear < robot.radius:
        raise InputError(f"{world.name}: the robot {robot.name} (radius {robot.radius:g} m) does not fit at the start "
                         f"{list(world.start[:2])} (clearance {clear:.3f} m)")
    return plan(world, t=0.0, cell=config.cell, checkpoints=config.checkpoints, refine=config.refine,
                padding=robot.radius, lanes=config.lanes)


def sight_of(known: World, t: float, current, radius: float) -> tuple:
    """The planner's map the checkpoints of ``current`` were planned on, padded by the robot's ``radius`` — the known
    map at ``t`` and the movers' lanes the plan keeps off (``Plan.avoided``) — for the look past a checkpoint."""
    return padded_obstacles(known, t, radius) + tuple((shape, radius) for shape in current.avoided)


def replan_from(previous, known: World, position, t: float, robot, config: ScenarioConfig):
    """A new plan from the robot's ``position`` on the map ``known`` at ``t`` (Fig. 6.5; thesis 7.1.1), or None if
    the map leaves no way through."""
    try:
        return replan(previous, known, position, t, padding=robot.radius, reach=config.start_reach,
                      refine=config.refine, lanes=config.lanes)
    except InputError:  # NoRouteError included: the change left no way through
        return None


def replanned(shell: Shell, course: Course, t: float, reason: str, known: World,
              added=np.zeros((0, 2)), current=None) -> Course | None:
    """The course on a new plan (``current``, or one made from where the robot is) on the map ``known`` (Fig. 6.5;
    thesis 7.1.1), its first checkpoint a new target; None if the map leaves no way through."""
    current = replan_from(course.plan, known, shell.sim.pose[:2], t, shell.robot, shell.config) \
        if current is None else current
    if current is None:
        return None
    shell.rec.plans.append(PlanChange(t, reason, current.checkpoints.copy(), added, current.avoided))
    shell.monitor.reset(t)
    return replace(course, plan=current, known=known, sight=sight_of(known, t, current, shell.robot.radius), index=0,
                   target_id=course.target_id + 1, replans=course.replans + 1, looked_past=(0, -1))


def after_events(shell: Shell, course: Course, t: float) -> Course:
    """Step 1: replan if a known event changed the planner's map since the last tick."""
    if map_changed(shell.world, course.last_t, t):
        changed = replanned(shell, course, t, "event", course.known)
        if changed is None:
            return replace(course, ended="no route after a change of the map")
        course = changed
    return replace(course, last_t=t)


def pass_checkpoints(shell: Shell, course: Course, t: float, tick: int) -> Course:
    """Checkpoints already within reach (two that coincide at a corner, or a replan starting on one), and with
    visible checkpoints one the robot is near whose successor it already sees (it cut the corner); then, every
    ``look_every`` ticks, a later checkpoint it already sees from wherever a detour has taken it (round a blocked
    door, say): the checkpoints before it are behind the robot. And when, on such a tick, a known wall comes between
    the robot and its checkpoint (its disc would touch the wall on the straight way there), the robot
    turns back to the latest of the ``look_back`` checkpoints before it that the look ahead took it past and that
    it sees (issue 35: the look ahead skips a doorway's mouth, a mover pushes the robot back beside the jamb, and a
    controller heading for a point behind the jamb commits to the wrong side of it). The trap monitor is told each
    checkpoint aimed at when the tick's passing is done (:meth:`~evaluation.monitor.TrapMonitor.aim`): turning back
    is not progress."""
    start = course.index
    course = _passed(shell, course, t, tick)
    if course.index != start:
        shell.monitor.aim(course.index, t)
    return course


def _passed(shell: Shell, course: Course, t: float, tick: int) -> Course:
    """The passing of :func:`pass_checkpoints`, before the monitor is told."""
    config, position, log = shell.config, shell.sim.pose[:2], shell.rec.checkpoint_log
    last = len(course.plan.checkpoints) - 1
    visible = course.plan.rule == "visible"
    while course.index < last and (
            np.linalg.norm(position - course.plan.checkpoints[course.index]) < config.checkpoint_tolerance
            or (visible and _sees_next(position, course.plan, course.index, config, course.sight))):
        log.append((t, *course.plan.checkpoints[course.index]))
        course = course.moved_on()
    if not (visible and tick % config.look_every == 0):
        return course
    if course.index < last:
        later = _seen_later(position, course.plan, course.index, config, course.sight)
        log.extend((t, *course.plan.checkpoints[j]) for j in range(course.index, later))
        if later > course.index:
            first, last_past = course.looked_past
            first = min(first, course.index) if first <= last_past else course.index
            course = replace(course.moved_on(later - course.index), looked_past=(first, later - 1))
    if config.look_back:
        earlier = _seen_earlier(position, course, config)
        if earlier is not None:
            course = replace(course, index=earlier, target_id=course.target_id + 1)
    return course


def observe(shell: Shell, course: Course, t: float) -> tuple[Observation, np.ndarray, np.ndarray]:
    """Step 2: sense, and the controller's :class:`Observation`; with the pose and the target it was made from."""
    world, sim = shell.world, shell.sim
    goal = course.target(world, t)
    if world.moving_goal:
        shell.rec.goal_path = np.vstack([shell.rec.goal_path, goal[None]])
    pose = sim.pose
    ir = sim.sense(shell.body.sensors)
    markers = _markers(world, sim, t, shell.radii)
    if np.isfinite(ir).any():
        shell.sensed.append((t, pose, ir, markers))
    moving = course.final and world.moving_goal
    obs = Observation(
        t=np.float32(t), ir=ir.astype(np.float32),
        target=np.asarray(egocentric(pose, goal), np.float32), target_id=np.int32(course.target_id),
        final=np.bool_(course.final), pose=pose.astype(np.float32),
        target_velocity=np.asarray(world.goal.velocity(t) if moving else (0.0, 0.0), np.float32),
        markers=markers)
    return obs, pose, goal


def stop_at_goal(shell: Shell, course: Course, t: float, pose, goal, command) -> Course:
    """Step 4: within the goal's tolerance, a command that rounds to zero (or a robot that has stood there for
    ``settle_s``) ends the run; the wheels spin down (motor lag) and the robot comes to rest."""
    config = shell.config
    inside = (course.final and not shell.world.moving_goal
              and float(np.linalg.norm(pose[:2] - goal)) < config.checkpoint_tolerance)
    since = (t if course.settled_since is None else course.settled_since) if inside else None
    course = replace(course, settled_since=since)
    if inside and (is_stop_command(command, shell.robot) or t - since >= config.settle_s - 1e-9):
        shell.sim.step(np.zeros(2), period=shell.period)
        shell.traced(t, shell.sim.trace)
        shell.rec.checkpoint_log.append((t, *goal))
        return replace(course, ended="stopped at the goal", arrived=True)
    return course


def drive(shell: Shell, course: Course, t: float, goal, command) -> tuple[Course, bool]:
    """Step 3: send the command for one period and read the sub-step trace — new contact episodes, a moving goal
    caught (under the robot's body), a checkpoint reached (within its tolerance); and whether the robot moved on
    to the next checkpoint."""
    sim, rec, robot = shell.sim, shell.rec, shell.robot
    rec.commands.append((t, float(command[0]), float(command[1])))
    _, trace = sim.step(command, period=shell.period)
    shell.traced(t, trace)
    if sim.collisions > course.collisions:
        rec.collision_log.extend([(sim.t, *sim.pose[:2])] * (sim.collisions - course.collisions))
        course = replace(course, collisions=sim.collisions)
    if shell.on_tick is not None:
        shell.on_tick(sim.t)
    sub_t = t + robot.dt * np.arange(1, len(trace) + 1)
    if course.final and shell.world.moving_goal:
        capture = robot.radius if shell.config.capture_radius is None else shell.config.capture_radius
        goals = np.array([shell.world.goal_at(s) for s in sub_t])
        if np.any(caught := np.linalg.norm(trace[:, :2] - goals, axis=1) < capture):
            j = int(np.argmax(caught))
            rec.checkpoint_log.append((float(sub_t[j]), *goals[j]))
            return replace(course, ended="caught the moving goal", arrived=True), False
    elif not course.final and np.any(near := np.linalg.norm(trace[:, :2] - goal, axis=1)
                                     < shell.config.checkpoint_tolerance):
        rec.checkpoint_log.append((t + robot.dt * (int(np.argmax(near)) + 1), *goal))
        course = course.moved_on()
        shell.monitor.aim(course.index, sim.t)
        return course, True
    return course, False


def watch(shell: Shell, course: Course) -> Course:
    """Step 5: the trap monitor; on a trap, recovery — the sensed obstacle joins the planner's map, the route is
    replanned round it and the robot turns to face it — or the end of the run; else a blocked checkpoint
    (:func:`unblocked`)."""
    sim, config = shell.sim, shell.config
    trapped = shell.monitor.update(sim.t, float(np.linalg.norm(sim.pose[:2] - course.target(shell.world, sim.t))),
                                   sim.pose[:2])
    if not trapped:
        return unblocked(shell, course)
    shell.rec.trap_log.append((sim.t, *sim.pose[:2]))
    if not config.recover or course.recoveries >= config.max_recoveries:
        return replace(course, ended="trapped", trapped=True)
    course = replace(course, recoveries=course.recoveries + 1)
    found = recovery(course.plan, course.known, shell.sensed, shell.body, sim.pose[:2], sim.t, config)
    if found is None:
        return replace(course, ended="trapped (no route around the sensed obstacle)", trapped=True)
    current, known, added = found
    return replace(replanned(shell, course, sim.t, "recovery", known, added, current),
                   turn_until=sim.t + config.turn_s)


def unblocked(shell: Shell, course: Course) -> Course:
    """With recovery, a checkpoint (not the goal) this tick's IR shows blocked (:func:`blocked_checkpoint`): the course
    on a plan round the near readings (:func:`recovery` with ``near_only``), the robot turned to face it, no recovery
    spent; where they leave no route, the checkpoint stays (``unblockable``) and the trap monitor watches."""
    sim, config = shell.sim, shell.config
    this_tick = shell.sensed[-1:] if shell.sensed and shell.sensed[-1][0] == course.last_t else []
    if not (config.recover and config.blocked and not course.final and course.target_id != course.unblockable
            and blocked_checkpoint(this_tick, shell.body, course.plan.checkpoints[course.index], course.sight,
                                   config.sensed_radius, config.sensed_near)):
        return course
    found = recovery(course.plan, course.known, shell.sensed, shell.body, sim.pose[:2], sim.t, config, near_only=True)
    if found is None:
        return replace(course, unblockable=course.target_id)
    current, known, added = found
    return replace(replanned(shell, course, sim.t, "blocked checkpoint", known, added, current),
                   turn_until=sim.t + config.turn_s)


def finish(shell: Shell, course: Course) -> RunRecord:
    """The record of the run that ended so: its traces, and the outcome measured on them."""
    rec, sim = shell.rec, shell.sim
    rec.ended, rec.arrived, rec.trapped = course.ended, course.arrived, course.trapped
    rec.replans, rec.recoveries = course.replans, course.recoveries
    rec.poses, rec.times = np.asarray(shell.poses), np.asarray(shell.times)
    rec.hits = _hits(shell.sensed, shell.body)
    rec.time_s = float(rec.checkpoint_log[-1][0] if rec.arrived else rec.times[-1])
    rec.path_m = float(np.linalg.norm(np.diff(rec.poses[:, :2], axis=0), axis=1).sum())
    rec.collisions, rec.contact_s = sim.collisions, sim.contact_s
    rec.checkpoints_reached = len(rec.checkpoint_log)
    rec.final_distance_m = float(np.linalg.norm(sim.pose[:2] - np.asarray(shell.world.goal_at(sim.t))))
    rec.reached = rec.arrived and rec.collisions == 0
    return rec


def turn_on_the_spot(alpha, robot, xp=np):
    """Wheel speeds ``(2,)`` that turn the robot on the spot towards a target ``alpha`` rad off its heading, at
    half of c*: a disc turning on the spot sweeps nothing, so this can hit nothing the robot is not already
    touching."""
    v = 0.5 * robot.max_wheel_speed * xp.where(alpha > 0, 1.0, -1.0)
    return xp.stack([-v, v])


def _seen_later(position, current, index: int, config: ScenarioConfig, sight) -> int:
    """The last of the ``look_ahead`` checkpoints after ``index`` that the robot at ``position`` sees (as
    :func:`_sees_next` measures it), or ``index`` if it sees none of them."""
    need = _sight_need(position, sight)
    last = min(index + config.look_ahead, len(current.checkpoints) - 1)
    for j in range(last, index, -1):
        if visibility.segment_clear(position, current.checkpoints[j], sight, need):
            return j
    return index


def _seen_earlier(position, course: Course, config: ScenarioConfig) -> int | None:
    """When a known wall comes between the robot at ``position`` and its checkpoint — the robot's disc would touch
    it somewhere along the straight segment to it (slack below 0 on the planner's map ``course.sight``, or below
    the look ahead's own need where the robot stands closer than that: a segment starts with the slack of its
    start, and the look ahead took the robot on from there) — the latest of the ``look_back`` checkpoints before
    it that the look ahead took the robot past (``course.looked_past``) and that it sees as :func:`_seen_later`
    measures it; otherwise None."""
    current, index, sight = course.plan, course.index, course.sight
    first, last = course.looked_past
    lowest = max(first, index - config.look_back)
    if last < lowest:
        return None
    need = _sight_need(position, sight)
    if visibility.segment_clear(position, current.checkpoints[index], sight, min(0.0, need)):
        return None
    for j in range(min(last, index - 1), lowest - 1, -1):
        if visibility.segment_clear(position, current.checkpoints[j], sight, need):
            return j
    return None


def _sees_next(position, current, index: int, config: ScenarioConfig, sight) -> bool:
    """Whether the robot at ``position``, within ``pass_radius`` of checkpoint ``index``, sees the next one: the
    straight segment to it keeps half the planner's margin (or the slack the robot has, if less) on the
    planner's map ``sight`` (:mod:`planner.visibility`). The checkpoint was a corner to get round; from here
    there is nothing left to get round."""
    here = current.checkpoints[index]
    if np.linalg.norm(position - here) > config.pass_radius:
        return False
    return visibility.segment_clear(position, current.checkpoints[index + 1], sight, _sight_need(position, sight))


def _sight_need(position, sight) -> float:
    """The slack (m) a straight segment from ``position`` must keep on the planner's map ``sight`` to count as seen:
    half the planner's margin, or the slack the robot has where it stands if less, less the visibility's tolerance
    (:mod:`planner.visibility`)."""
    return min(0.5 * visibility.MARGIN, float(visibility.slack(position, sight))) - visibility.TOLERANCE


def _in_one_loop(step):
    """``step`` run inside a one-iteration ``fori_loop`` of one jitted call: the same computation (the same
    bits), cheaper to call (probably because XLA's CPU runtime runs a loop body's many small kernels one
    after the other instead of handing independent ones to its thread pool).

    Every architecture builds its step as a ``functools.partial`` of a jitted function with the map arrays
    and the hashable parameters bound as keywords; the wrapper passes the arrays as arguments and binds the
    rest into one jitted function per step function and parameters (:func:`_looped`), so it compiles once
    per architecture and parameters, like the step itself, not once per run. Anything else, or a state
    whose types the step changes (which cannot be a loop carry),
    is called as it is.
    """
    parts = split_step(step)
    if parts is None:
        return step
    func, arrays, static = parts
    looped, plain = _looped(func, static), False

    def call(state, obs):
        nonlocal plain
        if not plain:
            try:
                return looped(state, obs, arrays)
            except TypeError:
                plain = True
        return step(state, obs)

    return call


def split_step(step):
    """``(func, arrays, static)`` of a controller's step built as every architecture builds it — a
    ``functools.partial`` of a function with keywords only — such that ``step(state, obs)`` is
    ``func(state, obs, **arrays, **dict(static))``: ``arrays`` the keywords that are pytrees of arrays (the maps,
    which a batch may hold one of per run), ``static`` the rest as a sorted, hashable tuple (what a compiled
    program is specialised on). None for any other step."""
    if not isinstance(step, functools.partial) or step.args:
        return None
    arrays = {k: v for k, v in step.keywords.items() if _is_arrays(v)}
    static = tuple(sorted((k, v) for k, v in step.keywords.items() if k not in arrays))
    try:
        hash(static)
    except TypeError:
        return None
    return step.func, arrays, static


def _is_arrays(value) -> bool:
    import jax

    leaves = jax.tree.leaves(value)
    return bool(leaves) and all(isinstance(a, (jax.Array, np.ndarray)) for a in leaves)


def _looped_impl(state, obs, arrays, *, func, static):
    import jax

    def one(s):
        return func(s, obs, **arrays, **dict(static))

    command = jax.eval_shape(one, state)[1]
    return jax.lax.fori_loop(0, 1, lambda _, carry: one(carry[0]), (state, jax.numpy.zeros(command.shape, command.dtype)))


@functools.cache
def _looped(func, static):
    """The jitted :func:`_looped_impl` of one step function and its static parameters, made once per process: the
    parameters are bound here, not passed as static arguments, so a tick does not hash them again (a frozen
    dataclass hashes all its fields on every call, a noticeable part of a tick for Samba's)."""
    import jax

    return jax.jit(functools.partial(_looped_impl, func=func, static=static))


def _hits(sensed: list, controller: Controller) -> list:
    """``RunRecord.hits`` — (t, world points ``(n, 2)`` the IR saw) — of the ``sensed`` ticks (t, pose, readings,
    markers), all in one :func:`~robots.controllers.base.hit_points` call rather than one call a tick."""
    if not sensed:
        return []
    ts, poses, readings, _ = zip(*sensed)
    pts, seen = hit_points(np.array(poses), np.array(readings), controller.sensors.angles, controller.robot.radius)
    return [(t, p[s]) for t, p, s in zip(ts, pts, seen)]


def _markers(world: World, sim: PymunkWorld, t: float, radii: np.ndarray) -> np.ndarray:
    """Object markers ``(k, 5)`` of the moving obstacles: (x, y, vx, vy, radius), world frame."""
    if not world.moving:
        return np.zeros((0, 5), np.float32)
    pos = sim.moving_positions()
    vel = np.array([m.path.velocity(t) for m in world.moving])
    return np.concatenate([pos, vel, radii[:, None]], axis=1).astype(np.float32)


#: m: a sensed point within a declared mover's radius plus this of where the mover was is the mover
#: (:func:`sensed_points`).
MOVER_MARGIN = 0.01


def sensed_points(sensed: list, controller: Controller,
                  margin: float = MOVER_MARGIN) -> tuple[np.ndarray, np.ndarray]:
    """Every still obstacle point the IR saw in the ``sensed`` ticks (t, pose, readings, markers), ``(n, 2)``, and
    the reading ``(n,)`` (m from the body surface) each came from. A point within a declared mover's radius +
    ``margin`` of where the mover was at that tick is the mover, not an obstacle to plan round."""
    if not sensed:
        return np.zeros((0, 2)), np.zeros(0)
    _, poses, readings, markers = zip(*sensed)
    readings = np.array(readings)
    pts, seen = hit_points(np.array(poses), readings, controller.sensors.angles, controller.robot.radius)
    markers = np.array(markers).reshape(len(sensed), -1, 5)  # (ticks, k, 5)
    if markers.shape[1]:
        gap = np.linalg.norm(pts[:, :, None, :] - markers[:, None, :, :2], axis=-1)  # (ticks, m, k)
        seen &= ~np.any(gap <= markers[:, None, :, 4] + margin, axis=-1)
    return pts[seen], readings[seen]


def recovery(previous, known: World, sensed: list, controller: Controller, position, t: float,
             config: ScenarioConfig, near_only: bool = False):
    """Recovery's new plan from ``position`` round what the IR ``sensed`` (thesis 7.1.1): ``(plan, map, added
    points)``, or None if not even the map as it was leaves a way through. With ``near_only`` (the replan round a
    blocked checkpoint, :func:`blocked_checkpoint`): round the readings within ``config.sensed_near`` or not at all —
    what it adds stays on the map, and a far reading's noise there would close a gap for every recovery after it.

    Every still point sensed joins the map (:func:`with_sensed`); where that closes every way — the readings'
    10 % noise scatters a far pillar's points across a gap a few millimetres wider than the robot — the plan is
    made round the readings within ``config.sensed_near`` alone (their error is under a tenth of that), and failing
    that on the map as it was. Why: a trap is the controller's, not proof that no way exists; ending the run there
    lost worlds whose every gap the robot fits (issue 35, pillar forests)."""
    points, readings = sensed_points(sensed, controller)
    sensors = controller.sensors
    near = readings <= config.sensed_near
    steps = (np.ones_like(near), near, np.zeros_like(near))  # nested: each keeps a subset of the one before
    if near_only:
        steps = (near,)
    for i, keep in enumerate(steps):
        if i and keep.sum() == steps[i - 1].sum():
            continue  # the same points as the step before: the same plan
        if near_only and not keep.any():
            continue  # nothing near to plan round
        grown, added = with_sensed(known, points[keep], readings[keep], config.sensed_radius, sensors.noise,
                                   sensors.resolution_m)
        current = replan_from(previous, grown, np.asarray(position, float), t, controller.robot, config)
        if current is not None:
            return current, grown, added
    return None


def with_sensed(known: World, points, readings, radius: float, noise: float = 0.1,
                resolution: float = 0.005) -> tuple[World, np.ndarray]:
    """``known`` with every sensed obstacle point that the map does not already explain added as a disc of
    ``radius`` (thesis 7.1.1: recovery), and those points ``(n, 2)``.

    A point is explained — it is a wall or obstacle of the map, seen with the IR's error — when it lies
    within ``radius`` plus three standard deviations of its reading's noise (``3 · noise · reading``) plus
    the resolution of the map's shapes. Only points nobody can mistake for the map join it: a doorway's
    jambs, seen from afar with a few centimetres of noise, must not close the doorway. Points are merged
    into one disc per ``radius``-sized square first.
    """
    points, readings = np.asarray(points, float).reshape(-1, 2), np.asarray(readings, float).reshape(-1)
    if not len(points):
        return known, np.zeros((0, 2))
    w, h = known.size
    inside = (points[:, 0] > 0) & (points[:, 0] < w) & (points[:, 1] > 0) & (points[:, 1] < h)
    points, readings = points[inside], readings[inside]
    explained = explained_within(readings, radius, noise, resolution)
    new = points[known.clearance(points, known_only=True) > explained] if len(points) else points
    new = np.unique(np.round(new / radius) * radius, axis=0).reshape(-1, 2)  # one disc per cell
    discs = tuple(Circle((float(x), float(y)), radius) for x, y in new)
    return replace(known, obstacles=known.obstacles + discs), new


def explained_within(readings, radius: float, noise: float, resolution: float, xp=np):
    """m: how near a shape of the map a sensed point from ``readings`` (m) lies when the map explains it — the added
    disc's ``radius`` plus three standard deviations of the reading's noise (``3 · noise · reading``) plus the
    resolution of the map's shapes (:func:`with_sensed`)."""
    return radius + 3.0 * noise * xp.asarray(readings) + resolution


#: Standard deviations of a reading's noise a point must lie within the robot's radius of a checkpoint by, to block it
#: (:func:`blocked_checkpoint`).
DOUBT = 1.0


def blocked_checkpoint(sensed: list, body, checkpoint, sight, radius: float = 0.005, near: float = 0.05) -> bool:
    """Whether the IR of the ``sensed`` tick (a list of at most one (t, pose, readings, markers)) saw an obstacle where
    the robot's disc would stand at ``checkpoint`` ``(2,)``: a still point read within ``near`` (m; the readings a
    blocked checkpoint's replan adds, :func:`recovery`'s ``near_only``) lies within the robot's radius of it even
    had its reading erred by :data:`DOUBT` standard deviations (``noise`` × reading) away from it, and the planner's
    map ``sight`` (padded by the robot's radius) does not explain that point (:func:`explained_within`, ``radius``
    the added disc's). Such a checkpoint cannot be reached; waiting for the trap monitor to say so cost a recovery's
    whole time-out, again and again where an unforeseen U's arms were found a piece at a time (issue 35)."""
    points, readings = sensed_points(sensed, body)
    points, readings = points[readings <= near], readings[readings <= near]
    if not len(points):
        return False
    sensors = body.sensors
    doubt = DOUBT * sensors.noise * readings
    gap = np.linalg.norm(points - np.asarray(checkpoint), axis=1) + doubt
    k = int(np.argmin(gap))
    r = body.robot.radius
    if gap[k] >= r:
        return False
    return bool(visibility.slack(points[k], sight) + r > explained_within(readings[k], radius, sensors.noise,
                                                                            sensors.resolution_m))


@dataclass(frozen=True)
class Driver:
    """An architecture ready to drive one run: its ``controller``, the map it drives (``source``, "" for none;
    ``trial``, None for none; ``map_robot``, the robot the map was trained on) and whether it ``learns``."""

    controller: Controller
    source: str = ""
    trial: int | None = None
    map_robot: str | None = None
    learns: bool = False


def driver(spec, maps=None, *, seed: int = 0, trial: int | None = None, source: str = "given map", robot=None,
           learn=None) -> Driver:
    """The :class:`Driver` of the architecture ``spec`` for the run with ``seed`` (:func:`run_architecture`'s
    arguments; raises :class:`InputError` for a map, trial or learning rule the architecture cannot take)."""
    import jax

    from robots.params import KHEPERA

    robot = KHEPERA if robot is None else robot
    if not spec.uses_map:  # Samba, motor schemas: no EKM to drive
        if maps is not None or trial is not None:
            raise InputError(f"architecture {spec.name} drives no map: drop the map and trial")
        if learn is not None:
            raise InputError(f"architecture {spec.name} drives no map: it has nothing to learn (drop --learn)")
        return Driver(spec.build(robot=robot))
    if maps is None:
        from ekm.data import load_default_map

        maps, source = load_default_map(spec.default_chart), f"shipped {spec.default_chart}-chart map"
    if trial is None:
        trial = seed % maps.trials
    if not 0 <= trial < maps.trials:
        raise InputError(f"trial {trial}: the map file holds trials 0..{maps.trials - 1}")
    ekm = jax.tree.map(lambda a: a[trial], maps.ekm)
    controller = spec.build(ekm, maps.cfg, robot=robot)
    if learn is not None:
        from robots.controllers.learner import learning

        controller = learning(controller, ekm, maps.cfg, learn)
    return Driver(controller, source, int(trial), map_robot(maps), learn is not None)


def driven(rec: RunRecord, d: Driver) -> RunRecord:
    """``rec`` with what drove it: the map's source, trial and robot, and with learning the map the run ended with
    (``learned``, from the controller's ``final_state``) and its updates."""
    rec.map_source, rec.trial, rec.map_robot = d.source, d.trial, d.map_robot
    if d.learns:
        rec.learned = rec.final_state.ekm
        rec.updates = int(rec.final_state.trace.updates)
    return rec


def run_architecture(world: World, spec, maps=None, *, seed: int = 0, trial: int | None = None,
                     config: ScenarioConfig = ScenarioConfig(), on_tick=None, source: str = "given map",
                     robot=None, learn=None) -> RunRecord:
    """Run the architecture ``spec`` (:class:`robots.controllers.spec.ArchitectureSpec`) through ``world``.

    ``maps``: a :class:`ekm.mapfile.SavedMaps` (``ekm train``'s file), or None for the shipped map of the
    architecture's chart (:mod:`ekm.data`); ``source`` names a given one in the record. ``trial``: which of
    its trials drives; by default
    ``seed % trials``, so that seeds 0–9 run every trained map of a 5-trial file twice, each time with
    other noise. ``robot``: the :class:`~robots.params.RobotParams` that drives (None: the Khepera).
    ``learn``: a :class:`robots.controllers.learner.LearnParams` — the map goes on learning during the run
    (the map it ends with is the record's ``learned``) — or None for a frozen map.
    """
    d = driver(spec, maps, seed=seed, trial=trial, source=source, robot=robot, learn=learn)
    return driven(run_scenario(world, d.controller, seed=seed, config=config, on_tick=on_tick), d)


def map_robot(maps) -> str:
    """The name of the robot a map file was trained on (``khepera`` for files that do not say)."""
    robot = maps.meta.get("robot") if isinstance(maps.meta, dict) else None
    return robot.get("name", "khepera") if isinstance(robot, dict) else "khepera"
