"""How sharply trained maps turn towards a far target: the turn gain of one step.

Run from the repository root with trained map files (first trial of each)::

    python benchmarks/reproduce/turn_gain.py indirect.npz direct.npz

A target 0.6 m away (beyond one step's reach, so the indirect map uses the fallback c = M_k w_k of
Eq. 4.5) appears at bearing α; the robot, at rest, executes one noise-free 1.024 s step of the map's
command and sees the target at α'. The turn gain is g = (α − α')/α, with bearings measured from the
robot's front for targets ahead and from its back for targets behind (it may reverse):

- g = 1: the step ends facing the target — the path straightens at once;
- g = 2: the step turns twice as far, to −α — the robot weaves from side to side on its way, and with
  noise the weave neither grows nor dies (|1 − g| = 1);
- 0 < g < 1: it turns part of the way and the weave dies out.
"""

from __future__ import annotations

import argparse

import jax
import jax.numpy as jnp
import numpy as np

from ekm import maps
from ekm.angles import wrap
from ekm.mapfile import load_maps
from robots.kinematics import RobotState, advance, egocentric, quantize_command
from robots.params import KHEPERA as P

BEARINGS = (0.2, 0.4, 0.6, 0.8, 1.0, 1.2)  # rad off the line of travel
DISTANCE = 0.6  # m: beyond the 0.16 m one step can cover


def turn_gains(control, back: bool) -> np.ndarray:
    """g for a target at each of :data:`BEARINGS` off the robot's front (or, ``back``, its back), both sides."""
    off = jnp.asarray(BEARINGS + tuple(-b for b in BEARINGS), jnp.float32)
    alpha = off + (jnp.pi if back else 0.0)
    targets = DISTANCE * jnp.stack([jnp.cos(alpha), jnp.sin(alpha)], axis=-1)
    n = P.substeps(P.target_period)

    def one(target):
        robot = RobotState(jnp.zeros(3, jnp.float32), jnp.zeros(2, jnp.float32))
        c = quantize_command(control(egocentric(robot.pose, target, jnp)), P, jnp)
        moved, _ = advance(robot, c, jnp.zeros(P.noise_shape(P.target_period)), n, P, jnp)
        return egocentric(moved.pose, target, jnp)[0]

    after = jax.jit(jax.vmap(one))(targets)
    off_after = wrap(after - (jnp.pi if back else 0.0))
    g = np.asarray((off - off_after) / off)
    k = len(BEARINGS)
    return 0.5 * (g[:k] + g[k:])  # mean of the left and right target


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("maps", nargs="+", help="map files written by `ekm train`")
    args = ap.parse_args()
    head = " | ".join(f"g at {b:.1f} rad" for b in BEARINGS)
    print(f"| map | target | {head} |")
    print("|---|---|" + "---:|" * len(BEARINGS))
    for path in args.maps:
        saved = load_maps(path)
        ekm = jax.tree.map(lambda a: a[0], saved.ekm)

        def control(u, ekm=ekm, cfg=saved.cfg):
            return maps.control(ekm, u, cfg)[0]

        for back in (False, True):
            g = turn_gains(control, back)
            print(f"| {saved.cfg.mapping} ({path}) | {'behind' if back else 'ahead'} | "
                  + " | ".join(f"{x:.2f}" for x in g) + " |", flush=True)


if __name__ == "__main__":
    main()
