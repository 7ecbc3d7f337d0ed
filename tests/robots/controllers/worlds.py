"""Small worlds built by hand for the controller tests (not a test module)."""

from robots.params import KHEPERA
from robots.worldfile import parse_world


def dead_end(gap: float):
    """A goal on the arena's middle line with ``gap`` m between the body there and the right-hand wall (x = 0.6 m),
    36 cm straight ahead of the start: a corridor's end, a niche's back."""
    return parse_world({"name": "dead-end", "size": [0.6, 0.3], "start": [0.1, 0.15, 0.0],
                        "goal": [0.6 - KHEPERA.radius - gap, 0.15]}, "dead-end.json")
