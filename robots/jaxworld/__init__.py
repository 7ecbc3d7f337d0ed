"""The robot's world in JAX (docs/jaxworld.md): the pymunk world's physics as pure functions over padded arrays.

- :mod:`robots.jaxworld.scene`: a :class:`~robots.worldfile.World` as padded arrays (:class:`Scene`), worlds of
  different sizes in one batch;
- :mod:`robots.jaxworld.collide`: distances and contact normals from the robot's centre to every shape, and the
  IR rays' first hits;
- :mod:`robots.jaxworld.engine`: one control period (motors of :mod:`robots.kinematics`, sub-steps with contact
  and sliding as pymunk makes them, contact episodes) and a ``lax.scan`` over periods.

pymunk (:class:`robots.world.PymunkWorld`) stays the reference and the default engine.
"""

from robots.jaxworld.engine import EngineState, reset, sense, step
from robots.jaxworld.scene import Scene, scene_of, stack_scenes

__all__ = ["EngineState", "Scene", "reset", "scene_of", "sense", "stack_scenes", "step"]
