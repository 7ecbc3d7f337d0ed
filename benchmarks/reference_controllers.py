"""Analytic reference controllers on the fixed simulator, scored by the ch. 6.1 test and metrics.

Not an EKM: these show which (E, T(25), D(25)) the simulator itself allows in the 1 x 1 m arena, so
that the trained maps' figures can be judged against them (thesis ch. 6.1 quotes T ~ 9 steps/m and
D < 9 % for the indirect map). One 1.024 s step holds one wheel command, i.e. the robot moves on one
circular arc per step; every family below is a different rule for choosing that arc:

- ``arc``: the exact inverse of the one-step kinematics (heading change 2 alpha, chord d), scaled
  down to c* when infeasible — the command an ideal indirect EKM would give (Eq. 4.5 with a perfect M);
  ``back`` lets it drive backwards to targets behind (|alpha| > pi/2), as the thesis' maps do (Fig. 6.2:
  neurons at alpha = +-3);
- ``turn``: rotate in place by alpha when |alpha| > thr (and the target is not within reach), else ``arc``.

Run: python -m benchmarks.reference_controllers  (takes ~1 min; numbers go in the tuning report).
"""

from __future__ import annotations

import sys

import numpy as np

from robots.kinematics import egocentric, initial_state, is_stop_command, step, wrap_angle
from robots.params import KHEPERA as P

T, B, CMAX = P.target_period, P.wheel_base, P.max_wheel_speed


def arc(u, back):
    a, d = u
    rev = back and abs(a) > np.pi / 2
    a2 = wrap_angle(a - np.pi) if rev else a
    g = a2 / np.sin(a2) if abs(a2) > 1e-6 else 1.0
    s = d * g / T * (-1.0 if rev else 1.0)
    w = 2.0 * a2 / T
    c = np.array([s - w * B / 2, s + w * B / 2])
    if np.any(np.abs(c) > CMAX):
        c = c * CMAX / np.max(np.abs(c))  # keep the arc's shape, shorten it
    return c


def turn(u, back, thr):
    a, d = u
    a2 = wrap_angle(a - np.pi) if (back and abs(a) > np.pi / 2) else a
    if abs(a2) > thr and d > 0.03:
        w = a2 / T
        c = np.array([-w * B / 2, w * B / 2])
        if np.any(np.abs(c) > CMAX):
            c = c * CMAX / np.max(np.abs(c))
        return c
    return arc(u, back)


def run(ctrl, seed, n_targets=50, cap=50, eps=0.025):
    rng = np.random.default_rng(seed)
    targets = rng.uniform(0.1, 0.9, (n_targets, 2))
    robot = initial_state(np.array([0.5, 0.5, 0.0]))
    prev = robot.pose[:2].copy()
    errs, ts, ds, caps = [], [], [], 0
    for tgt in targets:
        l = np.linalg.norm(tgt - prev)
        hit, path = (None if l >= eps else (0.0, 0.0)), 0.0
        for k in range(cap):
            c = ctrl(egocentric(robot.pose, tgt))
            if is_stop_command(c):
                break
            p0 = robot.pose[:2]
            robot, tr = step(robot, c, rng.normal(size=2), 64)
            seg = np.linalg.norm(np.diff(np.vstack([p0, tr[:, :2]]), axis=0), axis=1)
            cum = path + np.cumsum(seg)
            dist = np.linalg.norm(tr[:, :2] - tgt, axis=1)
            if hit is None and np.any(dist < eps):
                j = int(np.argmax(dist < eps))
                hit = (k + (j + 1) / 64, cum[j])
            path = cum[-1]
        else:
            caps += 1
        robot, _ = step(robot, np.zeros(2), np.zeros(2), 64)  # coast to rest
        errs.append(np.linalg.norm(robot.pose[:2] - tgt))
        prev = tgt
        if hit:
            ts.append(hit[0] / l)
            ds.append(abs(hit[1] - l) / l)
    return np.mean(errs), len(ts) / n_targets, np.mean(ts), np.mean(ds), caps


def main():
    rows = [("arc, forward only", lambda u: arc(u, False)), ("arc, forward+backward", lambda u: arc(u, True))]
    for thr in (1.2, 0.9, 0.6, 0.3, 0.15):
        rows.append((f"turn if |a|>{thr}, fwd", lambda u, t=thr: turn(u, False, t)))
        rows.append((f"turn if |a|>{thr}, fwd+back", lambda u, t=thr: turn(u, True, t)))
    print(f"{'controller':28s} {'E mm':>6s} {'P25':>5s} {'T25':>6s} {'D25':>6s} caps   (5 seeds x 50 targets)")
    for name, ctrl in rows:
        r = np.array([run(ctrl, s)[:4] for s in range(5)]).mean(0)
        print(f"{name:28s} {1000 * r[0]:6.2f} {r[1]:5.2f} {r[2]:6.2f} {r[3]:6.3f}", flush=True)


if __name__ == "__main__":
    sys.exit(main())
