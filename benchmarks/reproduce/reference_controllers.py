"""Analytic reference controllers on the same simulator, scored by the same ch. 6.1 test and metrics.

Run from the repository root (about a minute)::

    python benchmarks/reproduce/reference_controllers.py                # Webots slip noise (the package's model)
    python benchmarks/reproduce/reference_controllers.py --per-command  # one noise draw per 1.024 s command

Not EKMs: they show which (E, T(25), D(25)) the simulator itself allows in the 1 × 1 m arena, so the
trained maps can be judged against them (the thesis quotes T ≈ 9 steps/m and D < 9 % for its indirect
map in Webots). One 1.024 s step holds one wheel command, so the robot moves on one circular arc per
step; each controller is a rule for choosing that arc:

- ``arc``: the exact inverse of the one-step kinematics — a chord of length d at bearing α is the arc
  that turns the heading by 2α — driving backwards to targets behind (|α| > π/2), scaled down to c*
  when infeasible. It is what a perfect indirect map would command (Eq. 4.5 with exact M_k).
- ``turn > θ``: rotate in place by α when |α| > θ (and the target is more than 3 cm away), else ``arc``.

``--per-command`` draws each wheel's noise once per command, with the same 10 % standard deviation
(uniform half-width 0.1·√3): the model this package used before it followed Webots. A full-speed
step then turns the heading by 0.44 rad (std) at random, and no controller reaches T(25) ≤ 9.
"""

from __future__ import annotations

import argparse
import dataclasses
import math

import jax
import jax.numpy as jnp

from ekm.charts import signed
from ekm.config import EKMConfig
from ekm.kohonen import units
from evaluation.metrics import summarize
from evaluation.protocol import drive_test, test_targets
from robots.params import KHEPERA as P, RobotParams

T, B, CMAX = P.target_period, P.wheel_base, P.max_wheel_speed
CFG = EKMConfig()


def _limit(c):
    """Shorten an arc to the wheel limit c*, keeping its shape."""
    return c * jnp.minimum(1.0, CMAX / jnp.maximum(jnp.max(jnp.abs(c)), 1e-12))


def arc(u):
    """Wheel commands of the one-step arc to u = (α, d); backwards for targets behind (the signed chart
    of ``ekm.charts``: one formula on (α', d'), d' < 0 behind)."""
    a2, d = signed(u, CFG) * units(CFG)
    gain = jnp.where(jnp.abs(a2) > 1e-6, a2 / jnp.sin(jnp.where(jnp.abs(a2) > 1e-6, a2, 1.0)), 1.0)
    s = d * gain / T
    w = 2.0 * a2 / T
    return _limit(jnp.stack([s - w * B / 2, s + w * B / 2]))


def turn_then_arc(threshold):
    """Rotate in place towards the target when it is more than ``threshold`` rad off the line of travel."""

    def control(u):
        a2 = signed(u, CFG)[0] * jnp.pi
        spin = _limit(jnp.stack([-a2 * B / (2 * T), a2 * B / (2 * T)]))
        return jnp.where((jnp.abs(a2) > threshold) & (u[1] > 0.03), spin, arc(u))

    return control


def score(control, trials: int = 5, arena=(1.0, 1.0), params: RobotParams = P) -> dict:
    """The ch. 6.1 test (50 targets, seed 0, as ``ekm evaluate``) for ``trials`` noise draws."""
    pts = test_targets(50, arena, seed=0)
    centre = jnp.asarray([0.5 * arena[0], 0.5 * arena[1], 0.0])
    keys = jax.random.split(jax.random.fold_in(jax.random.PRNGKey(0), 1), trials)
    rec = jax.jit(jax.vmap(lambda k: drive_test(control, pts, centre, k, params=params)))(keys)
    return summarize(rec)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--per-command", action="store_true", help="one noise draw per command (std 10 %%)")
    args = ap.parse_args()
    params = P
    if args.per_command:
        params = dataclasses.replace(P, noise_period=P.target_period, actuator_noise=0.1 * math.sqrt(3.0))
    rows = [("arc (exact one-step inverse)", arc)]
    rows += [(f"turn in place when the target is more than {t} rad off, else arc", turn_then_arc(t))
             for t in (1.2, 0.9, 0.6, 0.3)]
    print("| reference controller | E (mm) | P(25) | T(25) steps/m | D(25) | capped |")
    print("|---|---:|---:|---:|---:|---:|")
    for name, control in rows:
        s = score(control, params=params)
        print(f"| {name} | {s['E_mm']:.2f} | {s['P']['25']:.2f} | {s['T']['25']:.2f} | {s['D']['25']:.3f} | "
              f"{s['capped']} |", flush=True)


if __name__ == "__main__":
    main()
