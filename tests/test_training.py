"""Online self-organised training (thesis ch. 4.3) really learns target reaching (ch. 6.1 metrics)."""

import jax
import numpy as np
import pytest

from ekm.config import EKMConfig
from evaluation.metrics import summarize
from evaluation.protocol import evaluate, trace_paths
from robots.params import KHEPERA
from training.online import TrainConfig, draw_noise, start, train_chunk, train_step
from training.run import train

ARENA = (1.0, 1.0)


@pytest.fixture(scope="module")
def short_runs():
    """Both mappings, 30,000 steps × 2 trials, seed 0, tested on 50 targets before and after training."""
    out = {}
    for mapping in ("direct", "indirect"):
        cfg = EKMConfig(mapping=mapping)
        tcfg = TrainConfig(steps=30_000, trials=2, arena=ARENA)
        curve = {}
        train(cfg, tcfg, seed=0, eval_every=30_000,
              on_eval=lambda step, m, cfg=cfg: curve.__setitem__(step, summarize(evaluate(m, cfg, ARENA))))
        out[mapping] = curve
    return out


def test_training_cuts_the_positioning_error_at_least_five_fold(short_runs):
    for mapping, curve in short_runs.items():
        untrained, trained = curve[0]["E_mm"], curve[30_000]["E_mm"]
        assert trained * 5 <= untrained, (mapping, untrained, trained)
        assert curve[30_000]["P"]["25"] > 0.9 > curve[0]["P"]["25"]


def test_indirect_mapping_beats_direct_mapping_on_a_short_run(short_runs):
    """Error and steps per metre by a wide margin (seeds 0–3: E 1.6–1.7 mm against 2.9–3.8 mm, T(25) 7.8–8.1
    against 11.7–13.9). After 30,000 steps both maps reach P(5) = 1.0 on seeds 2 and 3, and the direct map's
    D(25) is the lower on seeds 0 and 3 (0.051 against 0.055 and 0.054), so those two are only required not
    to favour the direct map beyond that."""
    d, i = short_runs["direct"][30_000], short_runs["indirect"][30_000]
    assert i["E_mm"] < 0.7 * d["E_mm"]
    assert i["T"]["25"] < 0.8 * d["T"]["25"]
    assert i["P"]["5"] >= d["P"]["5"]
    assert i["D"]["25"] < 1.5 * d["D"]["25"]


def test_traced_paths_are_the_first_trial_of_the_same_test():
    cfg, tcfg = EKMConfig(neurons=6), TrainConfig(steps=2000, trials=2, arena=ARENA)
    maps = train(cfg, tcfg, seed=1)
    rec = jax.tree.map(lambda a: np.asarray(a)[0], evaluate(maps, cfg, ARENA, targets=8))
    pts, start, xy, first = trace_paths(maps, cfg, ARENA, targets=8)
    for a, b in zip(first, rec):
        np.testing.assert_allclose(np.asarray(a, float), np.asarray(b, float), atol=1e-5)
    n = KHEPERA.substeps(KHEPERA.target_period)
    assert xy.shape == (8, 50 * n, 2)
    # Each path ends where the robot stood when E was measured, and starts next to the arena centre.
    np.testing.assert_allclose(np.linalg.norm(np.asarray(xy)[:, -1] - np.asarray(pts), axis=-1), rec.error, atol=1e-5)
    assert np.linalg.norm(np.asarray(xy)[0, 0] - np.asarray(start)[:2]) <= 1.1 * KHEPERA.max_wheel_speed * KHEPERA.dt


def test_training_is_reproducible_from_its_seed():
    cfg, tcfg = EKMConfig(neurons=6), TrainConfig(steps=300, trials=2, arena=ARENA)
    a = train(cfg, tcfg, seed=1)
    b = train(cfg, tcfg, seed=1)
    c = train(cfg, tcfg, seed=2)
    for x, y in zip(a, b):
        np.testing.assert_array_equal(np.asarray(x), np.asarray(y))
    assert not np.allclose(np.asarray(a.M), np.asarray(c.M))
    assert not np.allclose(np.asarray(a.M[0]), np.asarray(a.M[1]))  # trials differ from each other


def test_one_chunk_is_the_same_as_its_steps_one_by_one():
    """train_chunk (lax.scan inside vmap, noise drawn up front) = train_step applied in order."""
    cfg, tcfg = EKMConfig(neurons=5), TrainConfig(steps=1000, trials=2, arena=ARENA)
    keys = jax.random.split(jax.random.PRNGKey(0), 2)
    s0 = jax.vmap(lambda k: start(k, cfg, tcfg))(keys)
    chunk = train_chunk(s0, keys, 0.0, length=25, cfg=cfg, tcfg=tcfg)
    for trial in range(2):
        s = jax.tree.map(lambda a: a[trial], s0)
        draws = draw_noise(keys[trial], 25)
        step = jax.jit(lambda s, d, t: train_step(s, d, t, cfg, tcfg, KHEPERA))
        for t in range(25):
            s = step(s, tuple(d[t] for d in draws), float(t))
        for x, y in zip(jax.tree.leaves(s), jax.tree.leaves(jax.tree.map(lambda a: a[trial], chunk))):
            np.testing.assert_allclose(np.asarray(x), np.asarray(y), atol=1e-6)
