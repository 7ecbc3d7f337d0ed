"""A Gymnasium environment of the robot, its worlds and its planner (``pip install 'ekm[gym]'``).

    import gymnasium
    import ekm.gym                                   # registers ekm/Khepera-v0
    env = gymnasium.make("ekm/Khepera-v0", world="three-rooms", sensors="long", robot="khepera")
    obs, info = env.reset(seed=0)
    obs, reward, terminated, truncated, info = env.step(env.action_space.sample())

Every step is one 0.128 s tick of :func:`evaluation.scenario.episode` — the same run as ``ekm run`` makes, the
planner's checkpoints, the trap monitor's recovery and all, with the agent choosing the wheel speeds where
an architecture would. The same ``seed`` gives the same run: a controller driven through the environment
ends as ``ekm run --seed`` does.

- **Observation** ``(m + 2,)`` float32: the ``m`` IR readings (m from the body surface; the sensor's range
  where nothing is seen), then the current checkpoint as (α, d) — bearing from the heading (rad, + = left)
  and distance (m). ``info["observation"]`` holds the full :class:`~robots.controllers.base.Observation`.
- **Action** ``(2,)``: the left and right wheel speeds in m/s, within ±c* (the robot's top speed: 0.16 for the
  Khepera).
- **Reward** per step: ``10 ×`` the metres of progress along the plan (the route still to go: to the
  current checkpoint, then leg by leg to the goal), ``− 1`` per new collision (contact episode), ``− 0.01``
  (time), and ``+ 10`` on reaching the goal without a collision.
- **terminated** when the run stops at (or catches) the goal; **truncated** when it ends otherwise: the time
  limit, trapped, or no route left. ``info["outcome"]`` then holds the ``ekm run --json`` record.
"""

from __future__ import annotations

import math

import gymnasium
import numpy as np
from gymnasium import spaces

from robots.params import KHEPERA

ENV_ID = "ekm/Khepera-v0"

#: The reward's terms (module docstring).
PROGRESS, COLLISION, TIME, GOAL = 10.0, 1.0, 0.01, 10.0


class _Body:
    """What the run needs of the robot: its sensors and its parameters."""

    def __init__(self, sensors, robot):
        self.sensors, self.robot = sensors, robot


class KheperaEnv(gymnasium.Env):
    """The robot in one world (module docstring). ``world``: a named world, a world file or ``FAMILY:SEED``;
    ``sensors``: ``"long"`` (12 IR, 17.5 cm) or ``"short"`` (8, 5 cm); ``time_limit`` (simulated s),
    ``checkpoints`` (``"visible"`` or ``"thesis"``), ``recover`` and ``cell`` as for ``ekm run``; ``robot``: a
    named robot or a robot file (default the Khepera; ``ekm robots``)."""

    metadata = {"render_modes": ["rgb_array"], "render_fps": round(1 / KHEPERA.avoid_period)}

    def __init__(self, world: str = "three-rooms", sensors: str = "long", time_limit: float = 120.0,
                 checkpoints: str = "visible", recover: bool = True, cell: float | None = None,
                 render_mode: str | None = None, robot=None):
        from ekm.api.driving import scenario_config
        from ekm.api.worlds import world as load_world
        from ekm.errors import InputError
        from robots.robotfile import load_robot

        if sensors not in ("long", "short"):
            raise InputError(f"sensors: must be long or short, got {sensors!r}")
        if render_mode not in (None, "rgb_array"):
            raise InputError(f"render_mode: must be None or 'rgb_array', got {render_mode!r}")
        self.world = load_world(world)
        self.config = scenario_config("ekm.gym", time_limit=time_limit, recover=recover, checkpoints=checkpoints,
                                      cell=cell)
        self.robot = load_robot(robot)
        self.body = _Body(self.robot.long_range if sensors == "long" else self.robot.short_range, self.robot)
        self.render_mode = render_mode
        m = len(self.body.sensors.angles)
        self.range_m = self.body.sensors.range_m
        far = float(math.hypot(*self.world.size))
        self.observation_space = spaces.Box(
            low=np.array([0.0] * m + [-math.pi, 0.0], np.float32),
            high=np.array([self.range_m] * m + [math.pi, far], np.float32), dtype=np.float32)
        c = self.robot.max_wheel_speed
        self.action_space = spaces.Box(low=-c, high=c, shape=(2,), dtype=np.float32)
        self._ticks, self._raw, self._trace = None, None, []
        self._done = True

    def _observe(self, obs) -> np.ndarray:
        ir = np.where(np.isfinite(obs.ir), np.minimum(obs.ir, self.range_m), self.range_m)
        out = np.concatenate([ir, np.asarray(obs.target, np.float64)]).astype(np.float32)
        return np.clip(out, self.observation_space.low, self.observation_space.high)

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        """Start a run: with ``seed``, the run ``ekm run --seed SEED`` makes; without, one drawn from the
        environment's generator (itself seeded by the first ``reset(seed=…)``)."""
        from evaluation.scenario import episode

        super().reset(seed=seed)
        self.run_seed = int(seed) if seed is not None else int(self.np_random.integers(0, 2**31 - 1))
        self._report: dict = {}
        self._trace = [np.asarray(self.world.start[:2], float)]
        self._ticks = episode(self.world, self.body, self.run_seed, self.config, spec="gym", report=self._report)
        self._raw = next(self._ticks)
        self._done = False
        self._route, self._collisions = self._report["route_m"], self._report["collisions"]
        return self._observe(self._raw), {"observation": self._raw, "seed": self.run_seed}

    def step(self, action):
        if self._done:
            raise RuntimeError("ekm/Khepera-v0: the run has ended; call reset()")
        command = np.asarray(action, dtype=float).reshape(2)
        if not np.isfinite(command).all():
            raise ValueError(f"ekm/Khepera-v0: the action must be two finite wheel speeds, got {command.tolist()}")
        # beyond ±c* the motors clip it, as they clip an architecture's command: the same run either way
        try:
            self._raw = self._ticks.send(command)
        except StopIteration as finished:
            return self._end(finished.value)
        self._trace.append(np.asarray(self._raw.pose[:2], float))
        route, collisions = self._report["route_m"], self._report["collisions"]
        reward = PROGRESS * (self._route - route) - COLLISION * (collisions - self._collisions) - TIME
        self._route, self._collisions = route, collisions
        return self._observe(self._raw), float(reward), False, False, {"observation": self._raw}

    def _end(self, rec):
        """The last step: the run's record decides terminated and truncated."""
        self._done = True
        self._trace.extend(np.asarray(rec.poses[-1:, :2], float))
        goal = np.asarray(self.world.goal_at(rec.times[-1]), float)
        route = float(np.linalg.norm(rec.poses[-1, :2] - goal)) if rec.arrived else self._route
        reward = PROGRESS * (self._route - route) - COLLISION * (rec.collisions - self._collisions) - TIME
        if rec.reached:
            reward += GOAL
        outcome = rec.outcome()
        info = {"observation": self._raw, "outcome": outcome, "record": rec}
        return self._observe(self._raw), float(reward), bool(rec.arrived), not rec.arrived, info

    def render(self):
        """An RGB image ``(h, w, 3)`` uint8 of the world, the robot's path so far and the robot."""
        if self.render_mode != "rgb_array":
            return None
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.patches import Circle

        from robots.plot import plot_world

        ax = plot_world(self.world)
        fig = ax.figure
        trace = np.asarray(self._trace)
        ax.plot(trace[:, 0], trace[:, 1], "-", color="tab:blue", lw=1.5)
        if self._raw is not None:
            x, y, th = (float(v) for v in self._raw.pose)
            r = self.robot.radius
            ax.add_patch(Circle((x, y), r, fc="0.8", ec="k", zorder=6))
            ax.plot([x, x + r * math.cos(th)], [y, y + r * math.sin(th)], "k-", lw=1.5)
        canvas = FigureCanvasAgg(fig)
        canvas.draw()
        image = np.asarray(canvas.buffer_rgba())[..., :3].copy()
        return image


def _register() -> None:
    if ENV_ID not in gymnasium.envs.registry:
        gymnasium.register(id=ENV_ID, entry_point="ekm.gym:KheperaEnv", vector_entry_point="ekm.gym_vector:make")


_register()
