"""Robots in Python: :func:`robot` reads one (a named robot or a robot file), :func:`robots` lists them
(``ekm robots``)."""

from __future__ import annotations

from dataclasses import dataclass

from ekm.api.result import Result


@dataclass(frozen=True)
class Robots(Result):
    """The named robots, or the robot files checked: ``items``, each a :class:`~robots.params.RobotParams`.
    ``to_dict()`` is ``ekm robots --json``: ``robots: [{name, origin, about, fingerprint, radius, wheel_base,
    wheel_gain, max_wheel_speed, actuator_noise}]`` — ``origin`` "built in", "entry point" (an installed package's),
    "added" (:func:`ekm.register_robot`) or "file"."""

    items: tuple

    def _dict(self) -> dict:
        return {"robots": [{"name": r.name, "origin": _origin(r), "about": r.about, "fingerprint": r.fingerprint, "radius": r.radius,
                            "wheel_base": r.wheel_base, "wheel_gain": list(r.wheel_gain),
                            "max_wheel_speed": r.max_wheel_speed, "actuator_noise": r.actuator_noise}
                           for r in self.items]}

    def origins(self) -> list[str]:
        return [_origin(r) for r in self.items]

    def names(self) -> list[str]:
        return [r.name for r in self.items]


def robot(name_or_path=None):
    """The :class:`~robots.params.RobotParams` of a named robot (``ekm robots``) or a robot file, every key
    checked (:mod:`robots.robotfile`); None gives the Khepera.

    Example: ``ekm.robot("worn-wheel").wheel_gain`` is ``(0.9, 1.0)``."""
    from robots.robotfile import load_robot

    return load_robot(name_or_path)


def robots(check=None) -> Robots:
    """The named robots, or — ``check``: robot files — those files, each checked (the first bad one raises
    :class:`ekm.InputError` naming the file and key)."""
    from robots.robotfile import load_robot, named_robots

    names = named_robots() if check is None else ([check] if isinstance(check, str) else list(check))
    return Robots(items=tuple(load_robot(n) for n in names))


def _origin(r) -> str:
    from robots.robotfile import ROBOTS

    return ROBOTS.origin(r.name) if r.name in ROBOTS and ROBOTS[r.name] == r else "file"
