"""Environment steps per second of ``ekm/Khepera-v0`` (ekm.gym): a random agent, one environment, one CPU.

    python benchmarks/perf/bench_gym.py                        # 1,000 steps in three worlds
    python benchmarks/perf/bench_gym.py --steps 5000 --worlds maze:1000

Each step is one 0.128 s tick: eight pymunk sub-steps, the IR rays, the planner's checks. Episodes that end
are reset (the reset, which plans the route, is counted). Wall seconds after a warm-up episode.
"""

from __future__ import annotations

import argparse
import time

import numpy as np


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--steps", type=int, default=1000)
    parser.add_argument("--worlds", default="open-arena,three-rooms,concave-obstacle")
    parser.add_argument("--sensors", default="long", choices=("long", "short"))
    args = parser.parse_args()

    from ekm.gym import KheperaEnv
    from evaluation.pinning import pin_to_one_cpu

    pin_to_one_cpu()
    print(f"{'world':<20} {'steps':>6} {'seconds':>8} {'steps/s':>8} {'resets':>6}")
    for world in args.worlds.split(","):
        env = KheperaEnv(world=world, sensors=args.sensors)
        rng = np.random.default_rng(0)
        env.reset(seed=0)
        for _ in range(50):  # warm-up
            env.step(rng.uniform(-0.16, 0.16, 2))
        env.reset(seed=1)
        resets, t0 = 0, time.perf_counter()
        for _ in range(args.steps):
            _, _, terminated, truncated, _ = env.step(rng.uniform(-0.16, 0.16, 2))
            if terminated or truncated:
                env.reset()
                resets += 1
        seconds = time.perf_counter() - t0
        print(f"{world:<20} {args.steps:>6} {seconds:>8.3f} {args.steps / seconds:>8.0f} {resets:>6}")


if __name__ == "__main__":
    main()
