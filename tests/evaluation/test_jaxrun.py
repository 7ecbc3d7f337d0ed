"""The scenario runner on the JAX engine (evaluation.jaxrun): a scripted controller's runs, with answers worked out
by hand, the same records as the pymunk runner's, and the trap monitor's recovery between chunks."""

import math
import time
from functools import partial

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from evaluation import jaxrun
from evaluation.scenario import ScenarioConfig, run_scenario
from robots.controllers.base import Controller
from robots.params import KHEPERA
from robots.worldfile import parse_world
from robots.worldnames import load_world


@jax.jit
def _go(state, obs, *, gain):
    """Steer at the checkpoint (4 × its bearing, rad/s), forward at min(c*, gain × its distance) times the cosine
    of the bearing; zero within 5 mm of it."""
    alpha, d = obs.target[0], obs.target[1]
    v = jnp.minimum(KHEPERA.max_wheel_speed, gain * d) * jnp.maximum(jnp.cos(alpha), 0.0)
    half = 0.5 * KHEPERA.wheel_base * 4.0 * alpha
    wheels = jnp.stack([v - half, v + half])
    wheels = wheels * jnp.minimum(1.0, KHEPERA.max_wheel_speed / jnp.maximum(jnp.max(jnp.abs(wheels)), 1e-9))
    return state, jnp.where(d < 0.005, 0.0, wheels)


GO = Controller(name="go", spec="go", sensors=KHEPERA.long_range, init=lambda: jnp.zeros(()),
                step=partial(_go, gain=2.0))

#: A wall across the way, unforeseen: the goal is straight behind it; 9.5 cm gaps above and below.
DEAD_END = parse_world({"name": "dead-end", "size": [1.0, 0.5], "start": [0.3, 0.275, 0.0], "goal": [0.9, 0.275],
                        "unforeseen": [{"type": "box", "center": [0.61, 0.25], "size": [0.02, 0.3]}]}, "dead-end.json")


RUNS = [(load_world("open-arena"), 0), (load_world("open-arena"), 1), (DEAD_END, 0)]


@pytest.fixture(scope="module")
def batch():
    """One batch, one compilation: open-arena seeds 0 and 1, and the dead end (seed 0) — in blocks of 2, so that the
    batch is padded to whole blocks and its open runs are moved to the front as others end."""
    mp = pytest.MonkeyPatch()
    mp.setattr(jaxrun, "BLOCK", 2)
    try:
        return jaxrun.run_scenarios(RUNS, GO, ScenarioConfig(time_limit=60.0))
    finally:
        mp.undo()


def test_a_scripted_controller_reaches_the_goal_of_open_arena_in_the_time_hand_arithmetic_gives(batch):
    # From (0.5, 0.5) to (0.8, 0.8): D = 0.4243 m, the goal 45° to the left. At least D / (1.1 c*) = 2.41 s (top
    # speed, every slip draw at +10 %); at most a 0.5 s turn, then (D - 0.08) / (0.9 c*) = 2.39 s at top speed,
    # then the approach at 2 d from d = 0.08 to 0.005 m, 0.5 ln(16) / 0.9 = 1.54 s: 4.43 s. The path: at least the
    # straight line less the 5 mm it may stop short, at most 10 % longer (the turn, the slip).
    d = math.hypot(0.3, 0.3)
    for rec in batch[:2]:
        assert rec.reached and rec.ended == "stopped at the goal" and rec.collisions == 0
        assert 2.41 <= rec.time_s <= 4.43
        assert d - 0.005 <= rec.path_m <= 1.1 * d and rec.final_distance_m < 0.005  # it stops within 5 mm
        assert rec.checkpoints_reached == 1 and rec.replans == 0 and rec.time_limit_s == 60.0
    assert batch[0].path_m != batch[1].path_m  # other seeds, other noise


def test_the_pymunk_runner_gives_the_same_answer_and_the_same_record_keys(batch):
    rec = run_scenario(load_world("open-arena"), GO, seed=0, config=ScenarioConfig(time_limit=60.0))
    assert rec.reached and 2.41 <= rec.time_s <= 4.43
    ours, theirs = batch[0].outcome(), rec.outcome()
    assert list(ours) == list(theirs)
    assert [k for k, v in ours.items() if v is None] == [k for k, v in theirs.items() if v is None]


def test_a_dead_end_traps_the_robot_at_the_time_the_monitor_s_rule_gives_and_recovery_replans(batch):
    # The robot drives at c* (±10 %) from x = 0.3 to the wall's face less its radius, 0.6 - 0.025 = 0.575: there
    # after 0.275 / 0.176 = 1.56 s to 0.275 / 0.144 = 1.91 s, its last progress (1.2 cm closer in its last tick);
    # pressed against the wall it comes no closer and enters no new 5 cm square. Trapped 20 s later, at the end of
    # the first tick (multiples of 0.128 s) at or after that: between 21.56 and 22.04 s.
    rec = batch[2]
    recovery = next(p for p in rec.plans if p.reason == "recovery")
    assert 21.56 <= recovery.t <= 22.04
    assert rec.recoveries >= 1 and rec.replans >= 1 and len(recovery.added) > 0
    assert np.all(np.abs(recovery.added[:, 0] - 0.6) < 0.03)  # what the IR saw: the wall's face
    x_at_trap = rec.poses[np.searchsorted(rec.times, recovery.t) - 1, 0]
    assert abs(x_at_trap - 0.575) < 0.002


@pytest.mark.slow  # another compilation (recovery off is part of the program): 5-20 s
def test_without_recovery_the_dead_end_ends_the_run_trapped():
    rec, = jaxrun.run_scenarios([(DEAD_END, 0)], GO, ScenarioConfig(time_limit=60.0, recover=False))
    assert rec.trapped and rec.ended == "trapped" and not rec.reached and rec.replans == 0
    assert 21.56 <= rec.time_s <= 22.04  # the tick the monitor fired ends the run


@pytest.mark.slow  # another compilation (a batch of one): 5-20 s
def test_a_run_is_the_same_whatever_batch_it_is_in(batch):
    alone = jaxrun.run_scenarios([RUNS[1]], GO, ScenarioConfig(time_limit=60.0))[0]
    assert (alone.time_s, alone.path_m, alone.collisions) == (batch[1].time_s, batch[1].path_m, batch[1].collisions)
    assert np.array_equal(alone.poses, batch[1].poses)


@pytest.mark.slow  # Samba compiled for the JAX runner: 10-30 s
def test_a_lone_run_of_a_shipped_architecture_is_bit_for_bit_the_same_run_in_a_batch():
    """Samba's step is float arithmetic with trigonometry: a vmap of one run compiled as unbatched code rounded a
    command of ``pillars:3`` differently in its last bit at 0.64 s (0.155545205 against 0.15554519 m/s), and 120 s
    later the lone run had timed out where the batched one reached the goal in 9.9 s. Every run is batched now."""
    from robots.controllers.spec import parse_architecture

    world, samba = load_world("pillars:3"), parse_architecture("samba").build()
    config = ScenarioConfig(time_limit=2.0)
    alone = jaxrun.run_scenarios([(world, 0)], samba, config)[0]
    among = jaxrun.run_scenarios([(world, 0), (world, 1)], samba, config)[0]
    assert np.array_equal(np.asarray(alone.commands), np.asarray(among.commands))
    assert np.array_equal(alone.poses, among.poses)


@pytest.mark.slow  # 96 runs on each engine, nine batches to compile
def test_the_two_engines_agree_on_success_in_the_named_worlds():
    # docs/guide/jaxworld.md's agreement table, seeds 0-3: per world and architecture the two success rates' 95 %
    # Wilson intervals overlap (at 4 runs they exclude each other only for 0 against 4 reached); every named world,
    # the mover and the door of the three rooms and the moving goal included
    import ekm
    from evaluation.compare import wilson

    worlds = ("open-arena,three-rooms,three-rooms-static,concave-obstacle,extended-obstacle,three-rooms-moving,"
              "three-rooms-changed,moving-target")
    rates = {engine: {(r["world"], r["architecture"]): round(r["success_rate"] * r["trials"])
                      for r in ekm.compare(worlds, "fusion,fields,samba", trials=4, engine=engine, workers=1).rows}
             for engine in ("pymunk", "jax")}
    assert len(rates["jax"]) == 24 and rates["jax"].keys() == rates["pymunk"].keys()
    for cell, k in rates["pymunk"].items():
        (lo, hi), (lo2, hi2) = wilson(k, 4), wilson(rates["jax"][cell], 4)
        assert lo <= hi2 and lo2 <= hi, (cell, k, rates["jax"][cell])
    assert rates["jax"][("open-arena", "fields")] == rates["jax"][("three-rooms", "samba")] == 4


#: The straight way from start to goal, shut at 1 s by a box the planner is told of (10 cm gaps above and below).
SHUT = parse_world({"name": "shut", "size": [1.0, 0.5], "start": [0.3, 0.25, 0.0], "goal": [0.9, 0.25],
                    "events": [{"at_s": 1.0, "known": True,
                                "add": [{"type": "box", "center": [0.7, 0.25], "size": [0.02, 0.3]}]}]}, "shut.json")


#: A known wall up to y = 0.4 that the route must go round, and an unforeseen 4 cm box (x 0.49-0.53, y 0.44-0.48) over
#: the corner: the first plan's checkpoint there, (0.51, 0.47), lies inside the box, where no robot can stand.
BOXED_CORNER = parse_world({"name": "boxed-corner", "size": [1.0, 0.8], "walls": [[0.5, 0.0, 0.5, 0.4]],
                            "unforeseen": [{"type": "box", "center": [0.51, 0.46], "size": [0.04, 0.04]}],
                            "start": [0.2, 0.2, 0.0], "goal": [0.8, 0.2]}, "boxed-corner.json")


def test_a_checkpoint_the_ir_shows_inside_an_unforeseen_box_is_replanned_at_once_on_both_engines():
    # The scripted robot heads for the checkpoint (it avoids nothing) and its IR reads the box's near faces closer to
    # the checkpoint than the radius (2.5 cm) less the readings' doubt within seconds, long before the trap monitor's
    # 20 s: the plan is made again round what it saw (points on the box, grown by the readings' noise) with no
    # recovery spent, and the robot arrives; without the rule it pushes at the box until the monitor fires.
    jax_rec, = jaxrun.run_scenarios([(BOXED_CORNER, 0)], GO, ScenarioConfig(time_limit=60.0))
    pymunk_rec = run_scenario(BOXED_CORNER, GO, seed=0, config=ScenarioConfig(time_limit=60.0))
    assert np.allclose(pymunk_rec.plans[0].checkpoints[1], (0.51, 0.47), atol=0.011)  # the checkpoint in the box
    for rec in (jax_rec, pymunk_rec):
        assert [p.reason for p in rec.plans] == ["start", "blocked checkpoint"]
        assert rec.plans[1].t < 5.0 and rec.recoveries == 0 and rec.replans == 1
        added = rec.plans[1].added
        assert len(added) and np.all((added >= (0.48, 0.43)) & (added <= (0.54, 0.49)))
        assert rec.arrived
    late = run_scenario(BOXED_CORNER, GO, seed=0, config=ScenarioConfig(time_limit=60.0, blocked=False))
    assert late.plans[1].reason == "recovery" and late.plans[1].t >= 20.0


def test_a_known_event_replans_at_the_first_tick_after_it_on_both_engines():
    # Ticks are 0.128 s apart: the first at or after 1 s is the 8th, at 1.024 s. The new plan goes round the box
    # through one of the 10 cm gaps, so the run is longer than the straight 0.6 m, and reaches without a collision.
    jax_rec, = jaxrun.run_scenarios([(SHUT, 0)], GO, ScenarioConfig(time_limit=60.0))
    pymunk_rec = run_scenario(SHUT, GO, seed=0, config=ScenarioConfig(time_limit=60.0))
    for rec in (jax_rec, pymunk_rec):
        assert [(p.reason, round(p.t, 3)) for p in rec.plans] == [("start", 0.0), ("event", 1.024)]
        assert rec.replans == 1 and rec.recoveries == 0
        assert rec.reached and rec.collisions == 0 and rec.path_m > 0.6
        cps = rec.plans[1].checkpoints
        by_box = cps[np.abs(cps[:, 0] - 0.7) < 0.05]  # round the box (y 0.1-0.4), through a gap, not through it
        assert len(by_box) and np.all(np.abs(by_box[:, 1] - 0.25) > 0.15)


@pytest.mark.slow  # four compilations of the fields' batch
def test_padding_the_movers_markers_changes_no_run(monkeypatch):
    # A batch pads every world's markers to its rows by still markers 10 km away: the fields (whose inputs are the
    # markers' places ahead) drive the same runs, bit for bit, with one row per mover and with eight.
    from evaluation.scenario import driver
    from robots.controllers.spec import parse_architecture
    from robots.generator import generate

    runs = [(load_world("three-rooms-moving"), 0), (generate("movers", 1001), 1), (generate("traffic", 1003), 2)]
    fields = driver(parse_architecture("fields"), None, seed=0, trial=0).controller
    records = {}
    for rows in (1, 8):
        monkeypatch.setattr(jaxrun, "MIN_MARKERS", rows)
        records[rows] = jaxrun.run_scenarios(runs, fields, ScenarioConfig())
    assert [len(w.moving) for w, _ in runs] == [1, 2, 3]
    for one, eight in zip(records[1], records[8]):
        assert np.array_equal(one.poses, eight.poses)
        assert (one.ended, one.time_s, one.collisions) == (eight.ended, eight.time_s, eight.collisions)


#: A goal sliding away from the robot at 5 cm/s, 30 cm ahead of it at the start.
CHASE = parse_world({"name": "chase", "size": [1.0, 0.5], "start": [0.2, 0.25, 0.0],
                     "goal": {"path": {"type": "line", "from": [0.5, 0.25], "to": [0.9, 0.25], "speed_mps": 0.05,
                                       "bounce": False}}}, "chase.json")


def test_a_moving_goal_is_caught_when_the_robot_comes_within_its_radius_on_both_engines():
    # Full speed all the way (the gain of 8 keeps min(c*, 8 d) at c* down to 2 cm), so the robot closes on the goal
    # at c* (±10 %) less 5 cm/s, 0.094-0.126 m/s, from 0.3 m to the capture radius (its own, 2.5 cm): caught
    # between 0.275 / 0.126 = 2.18 s and 0.275 / 0.094 = 2.93 s, plus the motors' 0.1 s to speed up.
    chase = Controller(name="go", spec="go", sensors=KHEPERA.long_range, init=lambda: jnp.zeros(()),
                       step=partial(_go, gain=8.0))
    jax_rec, = jaxrun.run_scenarios([(CHASE, 0)], chase, ScenarioConfig(time_limit=60.0))
    pymunk_rec = run_scenario(CHASE, chase, seed=0, config=ScenarioConfig(time_limit=60.0))
    for rec in (jax_rec, pymunk_rec):
        assert rec.ended == "caught the moving goal" and rec.reached and rec.collisions == 0
        assert 2.18 <= rec.time_s <= 3.03
        goal_then = 0.5 + 0.05 * rec.time_s
        assert abs(rec.poses[-1, 0] - goal_then) < 0.025 + 0.003  # within the radius at the catch (+ the tick's end)
        assert len(rec.goal_path) == len(rec.commands)  # the goal where it was at every tick
    assert abs(jax_rec.time_s - pymunk_rec.time_s) < 0.1


def test_runs_in_the_same_world_share_its_first_plan(monkeypatch):
    # Planning is the host's work and depends on the world, robot and scenario alone: two architectures' runs in
    # one world plan it once; another world (or another config) plans again.
    made = []
    real = jaxrun.first_plan
    monkeypatch.setattr(jaxrun, "first_plan", lambda *a: made.append(a[0].name) or real(*a))
    plans: dict = {}
    config = ScenarioConfig(time_limit=60.0)
    first = jaxrun.start_run(DEAD_END, GO, 0, config, "go", plans)
    second = jaxrun.start_run(DEAD_END, GO, 1, config, "other", plans)
    jaxrun.start_run(load_world("open-arena"), GO, 0, config, "go", plans)
    jaxrun.start_run(DEAD_END, GO, 0, ScenarioConfig(time_limit=30.0), "go", plans)
    assert made == ["dead-end", "open-arena", "dead-end"]
    assert second.plan is first.plan and second.rec.plans[0].checkpoints is not first.rec.plans[0].checkpoints


def test_batches_in_threads_run_every_task_and_stop_starting_them_at_the_first_failure():
    """Every task runs once with two threads; when one fails, the task running beside it finishes, no task is started
    after it but the one or two already taken (each queued task sleeps 0.2 s, far longer than the pool takes to
    notice), and the failure comes out."""
    seen: list = []
    jaxrun.in_threads([partial(seen.append, i) for i in range(7)], threads=2)
    assert sorted(seen) == list(range(7))

    log: list = []

    def slow():
        time.sleep(0.3)
        log.append("slow done")

    def bad():
        raise ValueError("boom")

    queued = [partial(lambda i: (time.sleep(0.2), log.append(i)), i) for i in range(20)]
    with pytest.raises(ValueError, match="boom"):
        jaxrun.in_threads([slow, bad] + queued, threads=2)
    assert "slow done" in log
    assert len([x for x in log if isinstance(x, int)]) <= 2


def test_the_jax_runner_turns_back_where_the_pymunk_runner_does():
    """:func:`jaxrun.pass_checkpoints` on the scene of test_scenario's look back (a wall between the robot and the
    goal; the checkpoint above the wall's end looked past): the same answers, worked out there."""
    from tests.evaluation.test_scenario import JAMB, JAMB_CHECKPOINTS

    def after(position, tick, past=(1, 1), look_back=3):
        setup = jaxrun.setup_for(GO, None, (), ScenarioConfig(look_back=look_back))
        route = jaxrun.Route(scene=None, sight=jaxrun.scene_of(jaxrun._sight_world(JAMB)),
                             checkpoints=jnp.asarray(JAMB_CHECKPOINTS, jnp.float32), last=jnp.int32(2), ticks=None,
                             may_recover=None, radii=None, goal_path=None)
        index, passed, back, _ = jaxrun.pass_checkpoints(setup, route, jnp.asarray(position, jnp.float32), jnp.int32(2),
                                                         jnp.int32(tick), jnp.asarray(past, jnp.int32))
        return int(index), int(passed), bool(back)

    assert after((0.3, 0.35), 4) == (1, 0, True)
    assert after((0.3, 0.35), 5) == (2, 0, False)
    assert after((0.3, 0.35), 4, past=(0, -1)) == (2, 0, False)
    assert after((0.3, 0.35), 4, look_back=0) == (2, 0, False)
    assert after((0.6, 0.6), 4) == (2, 0, False)
    assert after((0.525, 0.51), 4) == (2, 0, False)  # pressed against the wall's end, its way clear of it
