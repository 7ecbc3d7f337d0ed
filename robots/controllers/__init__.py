"""The controllers that drive a robot through a world (docs/design.md §5).

- :mod:`~robots.controllers.base` — the :class:`Observation` every controller gets each tick and the
  :class:`Controller` it is packaged as;
- :mod:`~robots.controllers.braitenberg` — type-3C obstacle avoidance, c_o = Z u_o (Eq. 4.10);
- :mod:`~robots.controllers.fusion` — command fusion, c = β c_p + (1 − β) c_o (Eq. 4.11);
- :mod:`~robots.controllers.fields` — dynamic neural fields, cooperative EKMs (ch. 5);
- :mod:`~robots.controllers.spec` — architectures by name with parameters (``fusion:beta=0.6``).
"""
