"""What the fuzzing tests share (not a test module): hypothesis settings and the check that an input loads or
is refused with the package's own error.

Fuzzing what users hand the package — world files (tests/robots/test_worldfile.py) and map files
(tests/ekm/test_mapfile.py), generated and mutated by hypothesis. Every input either loads into a valid
object or raises the package's own :class:`ekm.errors.InputError` — no other exception, and no warning that
would reach a user's terminal. Example counts are fixed and the search is derandomised, so the run is the
same every time and bounded in time (about 30 s).
"""

import warnings

import numpy as np
from hypothesis import HealthCheck, settings

from ekm.errors import InputError

FUZZ = settings(max_examples=300, derandomize=True, deadline=None,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])


def assert_loads_or_refuses(load):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        with np.errstate(divide="raise", over="raise", invalid="raise"):  # what numpy would print as a warning
            try:
                result = load()
            except InputError as exc:
                message = str(exc)
                assert message and "\n" not in message
                result = None
    assert not caught, [str(w.message) for w in caught]
    return result
