"""A plain NumPy reference of one online training step (thesis ch. 4.3) — for tests and as the speed
baseline of ``benchmarks/`` (docs/design.md §7).

Written independently of the JAX code (no ``jax`` import here): the same equations, spelled out on
NumPy arrays in float64, one trial at a time. ``tests/training/test_reference.py`` holds the jitted JAX step equal
to it to 1e-5; ``benchmarks/perf/bench_training.py`` times both.
"""

from __future__ import annotations

import numpy as np

from ekm.angles import wrap
from ekm.config import EKMConfig
from robots.kinematics import RobotState, advance, egocentric, is_stop_command, quantize_command
from robots.params import KHEPERA, RobotParams


def winner(w, u, cfg: EKMConfig) -> int:
    """Eq. 4.2–4.4: among the ``priority`` neurons of most similar angle, the one nearest by Eq. 4.3."""
    dalpha = np.abs(wrap(u[0] - w[:, 0]))
    kth = np.sort(dalpha)[cfg.a_size - 1]
    d2 = cfg.gamma_alpha * (dalpha / np.pi) ** 2 + cfg.gamma_d * ((u[1] - w[:, 1]) / cfg.d_scale) ** 2
    d2[dalpha > kth] = np.inf
    return int(np.argmin(d2))


def neighbourhood(cfg: EKMConfig, k: int, sigma: float):
    """G(k, i): Gaussian of lattice distance, rows (directions) wrapping round."""
    n = cfg.neurons
    rows, cols = np.divmod(np.arange(n * n), n)
    dr = np.abs(rows - k // n)
    dr = np.minimum(dr, n - dr)
    return np.exp(-(dr**2 + (cols - k % n) ** 2) / (2.0 * sigma**2))


def _local(u, w, cfg: EKMConfig):
    """ũ of the linear model next to each neuron weight of ``w`` (..., 2), in map units (α/π, d/d_scale).

    ``cfg.chart`` "polar": (α, d), α unwrapped next to w_i; "signed": (α, d) ahead, (α ∓ π, -d) behind.
    """
    if cfg.chart == "polar":
        alpha = w[..., 0] + wrap(u[0] - w[..., 0])
        d = u[1]
    else:
        behind = abs(u[0]) > np.pi / 2
        alpha, d = (u[0] - np.sign(u[0]) * np.pi, -u[1]) if behind else (u[0], u[1])
        alpha = np.full(w.shape[:-1], alpha)
    return np.stack([alpha / np.pi, np.broadcast_to(d / cfg.d_scale, alpha.shape)], axis=-1)


def control(mapping: str, w, out, u, cfg: EKMConfig):
    """c_p for input ``u``: c_k (direct, ch. 4.1) or Eq. 4.5 with the M_k w_k fallback (indirect)."""
    k = winner(w, u, cfg)
    if mapping == "direct":
        return out[k].copy()
    c = out[k] @ _local(u, w[k], cfg)
    if np.all(np.abs(c) <= cfg.c_max):
        return c
    return out[k] @ _local(w[k], w[k], cfg)


def update(mapping: str, w, out, v, c_p, eta: float, sigma: float, cfg: EKMConfig):
    """Eq. 4.7 for w_i and Eq. 4.9 (indirect) or Δc_i = ηG(c_p - c_i) (direct), winner for ``v``."""
    g = neighbourhood(cfg, winner(w, v, cfg), sigma)
    if mapping == "direct":
        new_out = out + eta * g[:, None] * (c_p - out)
    else:
        v_loc = _local(v, w, cfg)  # (N², 2)
        err = c_p - np.einsum("nij,nj->ni", out, v_loc)
        new_out = out + eta * g[:, None, None] * np.einsum("ni,nj->nij", err, v_loc)
    new_w = w.copy()
    new_w[:, 0] = wrap(w[:, 0] + eta * g * wrap(v[0] - w[:, 0]))
    new_w[:, 1] = w[:, 1] + eta * g * (v[1] - w[:, 1])
    return new_w, new_out


def train_step(mapping: str, w, out, pose, wheels, target, age: int, draws, t: float, cfg: EKMConfig, tcfg,
               params: RobotParams = KHEPERA):
    """One step of ``training.online.train_step`` for one trial: returns (w, out, pose, wheels, target, age)."""
    xi_act, xi_explore, target_draw = (np.asarray(d, dtype=float) for d in draws)
    sch = tcfg.schedules
    robot = RobotState(np.asarray(pose, float), np.asarray(wheels, float))
    u = egocentric(robot.pose, target)
    c_p = control(mapping, w, out, u, cfg)
    c_sent = quantize_command(c_p + float(sch.explore(t, tcfg.steps)) * cfg.c_max * xi_explore, params)
    moved, _ = advance(robot, c_sent, xi_act, params.substeps(params.target_period), params)
    v = egocentric(robot.pose, moved.pose[:2])
    w, out = update(mapping, w, out, v, c_sent, float(sch.eta(t, tcfg.steps)), float(sch.sigma(t, tcfg.steps)), cfg)
    done = age + 1 >= tcfg.patience
    if tcfg.reach > 0:
        done = done or egocentric(moved.pose, target)[1] < tcfg.reach or bool(is_stop_command(c_sent, params))
    if done:
        lo = np.array([tcfg.margin, tcfg.margin])
        hi = np.asarray(tcfg.arena, float) - tcfg.margin
        if tcfg.target_range is None:
            target = lo + target_draw * (hi - lo)
        else:
            a = 2.0 * np.pi * target_draw[0]
            target = np.clip(moved.pose[:2] + tcfg.target_range * target_draw[1] * np.array([np.cos(a), np.sin(a)]), lo, hi)
    return w, out, moved.pose, moved.wheels, np.asarray(target, float), 0 if done else age + 1
