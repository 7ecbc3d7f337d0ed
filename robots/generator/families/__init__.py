"""The package's families of generated worlds, one module each: ``layout(rng, level)`` and ``FAMILY``, listed in
:data:`robots.generator.FAMILIES`."""
