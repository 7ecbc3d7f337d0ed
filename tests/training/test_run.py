"""Training runs (training.run): online self-organised training (thesis ch. 4.3) really learns target
reaching (ch. 6.1 metrics) and is reproducible from its seed; ``ekm train`` spreads the trial axis over the
JAX devices present, and the maps are those of one device."""

import json
import os
import subprocess
import sys

import numpy as np
import pytest

from ekm.config import EKMConfig
from evaluation.metrics import summarize
from evaluation.protocol import evaluate
from training.online import TrainConfig
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


def test_training_is_reproducible_from_its_seed():
    cfg, tcfg = EKMConfig(neurons=6), TrainConfig(steps=300, trials=2, arena=ARENA)
    a = train(cfg, tcfg, seed=1)
    b = train(cfg, tcfg, seed=1)
    c = train(cfg, tcfg, seed=2)
    for x, y in zip(a, b):
        np.testing.assert_array_equal(np.asarray(x), np.asarray(y))
    assert not np.allclose(np.asarray(a.M), np.asarray(c.M))
    assert not np.allclose(np.asarray(a.M[0]), np.asarray(a.M[1]))  # trials differ from each other


# -------------------------------------------------------------------------------------------------- devices

SCRIPT = """
import json, sys
import jax, numpy as np
from ekm.config import EKMConfig
from training.online import TrainConfig
from training.run import train, trial_sharding
cfg, tcfg = EKMConfig(neurons=6), TrainConfig(steps=1500, trials=int(sys.argv[2]))
sharding = trial_sharding(tcfg.trials)
maps = train(cfg, tcfg, seed=3, eval_every=500)
np.savez(sys.argv[1], w=np.asarray(maps.w), M=np.asarray(maps.M))
print(json.dumps({"devices": jax.device_count(), "used": 1 if sharding is None else len(sharding.device_set),
                  "result_devices": len(maps.w.sharding.device_set)}))
"""


def train_on(devices: int, out, trials: int = 4):
    env = {**os.environ, "XLA_FLAGS": f"--xla_force_host_platform_device_count={devices}"}
    proc = subprocess.run([sys.executable, "-c", SCRIPT, str(out), str(trials)], capture_output=True, text=True, env=env,
                          timeout=300)
    assert proc.returncode == 0, proc.stderr
    return json.loads(proc.stdout.strip().splitlines()[-1])


def test_two_host_devices_share_the_trials_and_give_the_maps_of_one(tmp_path):
    one = train_on(1, tmp_path / "one.npz")
    two = train_on(2, tmp_path / "two.npz")
    assert one == {"devices": 1, "used": 1, "result_devices": 1}
    assert two == {"devices": 2, "used": 2, "result_devices": 2}  # the trial axis really was split
    a, b = np.load(tmp_path / "one.npz"), np.load(tmp_path / "two.npz")
    np.testing.assert_array_equal(a["w"], b["w"])
    np.testing.assert_array_equal(a["M"], b["M"])


def test_five_trials_on_two_devices_run_as_three_and_three_and_give_the_maps_of_one(tmp_path):
    one = train_on(1, tmp_path / "one.npz", trials=5)
    two = train_on(2, tmp_path / "two.npz", trials=5)
    assert one["used"] == 1 and two["used"] == 2
    a, b = np.load(tmp_path / "one.npz"), np.load(tmp_path / "two.npz")
    assert a["w"].shape[0] == b["w"].shape[0] == 5  # the padding trial is dropped
    np.testing.assert_array_equal(a["w"], b["w"])
    np.testing.assert_array_equal(a["M"], b["M"])


def test_the_trial_axis_goes_to_the_fewest_devices_that_give_the_smallest_share():
    import jax

    from training.run import trial_layout, trial_sharding

    cpu = jax.devices()[0]
    assert trial_sharding(5, [cpu]) is None
    assert trial_layout(1, [cpu, cpu]) == (1, None)  # one trial: nothing to share
    padded, sharding = trial_layout(5, [cpu, cpu])  # 5 trials run as 3 + 3, the sixth a dropped copy
    assert padded == 6 and sharding.mesh.size == 2
    padded, sharding = trial_layout(4, [cpu, cpu, cpu])  # 2 + 2 beats 2 + 1 + 1 padded to 2 + 2 + 2
    assert padded == 4 and sharding.mesh.size == 2
