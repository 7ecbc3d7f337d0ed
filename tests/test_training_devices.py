"""``ekm train`` spreads the trial axis over the JAX devices present, and the maps are those of one device."""

import json
import os
import subprocess
import sys

import numpy as np

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
