"""Thesis ch. 6.2 as a scenario suite: who reaches the goal where, on seeds 0–9 (slow), and a quick version.

A run succeeds when the robot stops at the goal without a single collision (``reached``). One set of
parameters per architecture, the defaults, for every world; the runs are set up as the thesis's were —
its greedy checkpoints (ch. 3.2.3) and no recovery, so the trap monitor ends a trapped run.
"""

import functools

import numpy as np
import pytest

from evaluation.scenario import ScenarioConfig, run_architecture
from robots.controllers.spec import parse_architecture
from robots.worldfile import load_world

FUSION_LONG = "fusion:sensors=long,period=0.128"  # ch. 6.2.2: 12 long-range sensors, both modules at 0.128 s
THESIS = ScenarioConfig(checkpoints="thesis", recover=False)


@functools.lru_cache(maxsize=None)
def outcome(world: str, architecture: str, seed: int) -> dict:
    return run_architecture(load_world(world), parse_architecture(architecture), seed=seed, config=THESIS).outcome()


def runs(world, architecture, seeds):
    return [outcome(world, architecture, s) for s in seeds]


def count(records, key):
    return sum(bool(r[key]) for r in records)


# ----------------------------------------------------------------------------------------------- quick

def test_quick_fusion_reaches_the_goal_past_a_small_unforeseen_obstacle():
    assert count(runs("three-rooms-static", "fusion", range(3)), "reached") == 3


def test_quick_neural_fields_negotiate_the_trap_obstacles_that_trap_command_fusion():
    for world in ("extended-obstacle", "concave-obstacle"):
        assert count(runs(world, "fields", range(3)), "reached") == 3, world
    assert count(runs("concave-obstacle", "fusion", range(3)), "trapped") == 3


# ------------------------------------------------------------------------------------- seeds 0–9 (slow)

@pytest.mark.slow
@pytest.mark.parametrize("world", ["three-rooms-static", "three-rooms-moving", "three-rooms-changed"])
def test_ch_6_2_1_command_fusion_with_short_range_sensors_reaches_the_goal(world):
    records = runs(world, "fusion", range(10))
    assert count(records, "reached") >= 9, [r["ended"] for r in records]
    if world == "three-rooms-changed":
        assert all(r["replans"] >= 1 for r in records if r["reached"])  # through the upper doorway


@pytest.mark.slow
@pytest.mark.parametrize("world", ["three-rooms-static", "extended-obstacle", "concave-obstacle"])
def test_ch_6_2_2_neural_fields_with_long_range_sensors_reach_the_goal(world):
    assert count(runs(world, "fields", range(10)), "reached") >= 8


@pytest.mark.slow
def test_ch_6_2_2_neural_fields_take_a_shorter_path_than_command_fusion_where_both_succeed():
    for world in ("three-rooms-static", "extended-obstacle", "concave-obstacle"):
        both = [(f["path_m"], c["path_m"]) for f, c in zip(runs(world, "fields", range(10)),
                                                           runs(world, "fusion", range(10)))
                if f["reached"] and c["reached"]]
        if both:
            fields_path, fusion_path = np.mean(both, axis=0)
            assert fields_path < fusion_path, (world, both)


@pytest.mark.slow
@pytest.mark.parametrize("world", ["extended-obstacle", "concave-obstacle"])
@pytest.mark.parametrize("architecture", ["fusion", FUSION_LONG])
def test_ch_6_2_2_command_fusion_is_trapped_by_extended_and_concave_obstacles(world, architecture):
    records = runs(world, architecture, range(10))
    assert count(records, "trapped") >= 8 and count(records, "reached") <= 1
