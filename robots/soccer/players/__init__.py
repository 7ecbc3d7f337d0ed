"""Soccer players: each module has a parameter dataclass and ``build(params, field, robot, spec) -> Controller``."""
