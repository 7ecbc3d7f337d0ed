"""Fuzzing what users hand the package: world files and map files, generated and mutated by hypothesis.

Every input either loads into a valid object or raises the package's own :class:`ekm.errors.InputError` —
no other exception, and no warning that would reach a user's terminal. Example counts are fixed and the
search is derandomised, so the run is the same every time and bounded in time (about 30 s).
"""

import copy
import io
import json
import math
import warnings
import zipfile

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from ekm.data import default_map
from ekm.errors import InputError
from ekm.mapfile import SavedMaps, load_maps
from robots.worldfile import World, load_world, parse_world

FUZZ = settings(max_examples=300, derandomize=True, deadline=None,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])

BASE_WORLD = json.loads(json.dumps({
    "name": "fuzz", "size": [1.2, 0.6], "wall_thickness": 0.01,
    "walls": [[0.4, 0.0, 0.4, 0.24], [0.4, 0.36, 0.4, 0.6]],
    "obstacles": [{"type": "box", "center": [0.2, 0.1], "size": [0.05, 0.05], "angle": 0.3},
                  {"type": "polygon", "points": [[0.6, 0.1], [0.7, 0.1], [0.65, 0.2]]}],
    "unforeseen": [{"type": "circle", "center": [0.9, 0.3], "radius": 0.04},
                   {"type": "segment", "from": [1.0, 0.5], "to": [1.1, 0.5]}],
    "moving": [{"shape": {"type": "circle", "radius": 0.025},
                "path": {"type": "circle", "center": [0.6, 0.4], "radius": 0.08, "period_s": 12, "direction": "cw"}},
               {"shape": {"type": "box", "size": [0.03, 0.03]},
                "path": {"type": "line", "from": [0.5, 0.05], "to": [0.7, 0.05], "speed_mps": 0.05, "bounce": False}}],
    "events": [{"at_s": 5.0, "add": [{"type": "box", "center": [0.8, 0.16], "size": [0.02, 0.12]}], "known": True}],
    "start": [0.1, 0.3, 0.0],
    "goal": [1.1, 0.42],
}))

NUMBERS = st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.integers(-10**30, 10**30),
                    st.sampled_from([0, -0.0, 1e-300, -1e-300, 1e300, 5e-324, 0.025, -0.025, 1.2, 0.6]))
JSON_VALUES = st.recursive(
    st.one_of(st.none(), st.booleans(), NUMBERS, st.text(max_size=8)),
    lambda inner: st.one_of(st.lists(inner, max_size=5), st.dictionaries(st.text(max_size=6), inner, max_size=4)),
    max_leaves=12)


def paths_in(doc, prefix=()):
    """Every (path, value) inside a JSON document."""
    yield prefix, doc
    if isinstance(doc, dict):
        for k, v in doc.items():
            yield from paths_in(v, prefix + (k,))
    elif isinstance(doc, list):
        for i, v in enumerate(doc):
            yield from paths_in(v, prefix + (i,))


ALL_PATHS = [p for p, _ in paths_in(BASE_WORLD) if p]


@st.composite
def mutated_worlds(draw):
    """The base world with a few of its values replaced, keys deleted or added, lists emptied or extended."""
    doc = copy.deepcopy(BASE_WORLD)
    for _ in range(draw(st.integers(1, 4))):
        path = draw(st.sampled_from(ALL_PATHS))
        parent = doc
        try:
            for k in path[:-1]:
                parent = parent[k]
            key = path[-1]
            action = draw(st.sampled_from(["replace", "replace", "number", "delete", "extra", "empty"]))
            if action == "replace":
                parent[key] = draw(JSON_VALUES)
            elif action == "number":
                parent[key] = draw(NUMBERS)
            elif action == "delete":
                del parent[key]
            elif action == "extra" and isinstance(parent, dict):
                parent[draw(st.text(min_size=1, max_size=6))] = draw(JSON_VALUES)
            elif action == "empty":
                parent[key] = [] if isinstance(parent[key], list) else {}
        except (KeyError, IndexError, TypeError):
            pass  # an earlier mutation removed the path: nothing to do
    return doc


def polygons():
    """Random polygons: self-intersecting, degenerate, repeated points, huge, tiny, outside the arena."""
    point = st.tuples(st.floats(-1.0, 2.0, allow_nan=False), st.floats(-1.0, 2.0, allow_nan=False))
    return st.lists(point, min_size=0, max_size=9).map(lambda pts: {"type": "polygon", "points": [list(p) for p in pts]})


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


def check_world(world):
    assert isinstance(world, World)
    numbers = [*world.size, *world.start]
    assert all(math.isfinite(v) for v in numbers) and world.size[0] > 0 and world.size[1] > 0
    assert world.clearance(np.asarray(world.start[:2]), 0.0) >= 0.025 - 1e-9  # the robot fits at its start


@FUZZ
@given(mutated_worlds())
def test_mutated_world_files_load_or_are_refused_with_one_line(doc):
    world = assert_loads_or_refuses(lambda: parse_world(doc, "fuzz.json"))
    if world is not None:
        check_world(world)


@FUZZ
@given(st.lists(polygons(), min_size=1, max_size=3), st.tuples(st.floats(0.0, 3.0), st.floats(0.0, 3.0)))
def test_random_polygons_and_arenas_load_or_are_refused(shapes, size):
    doc = {"name": "poly", "size": list(size), "unforeseen": shapes, "start": [0.1, 0.1, 0.0], "goal": [0.2, 0.2]}
    world = assert_loads_or_refuses(lambda: parse_world(doc, "poly.json"))
    if world is not None:
        check_world(world)


@FUZZ
@given(st.binary(max_size=200) | st.text(max_size=200).map(str.encode))
def test_arbitrary_bytes_as_a_world_file_are_refused_with_one_line(tmp_path_factory, data):
    path = tmp_path_factory.mktemp("w") / "world.json"
    path.write_bytes(data)
    assert_loads_or_refuses(lambda: load_world(path))


# ------------------------------------------------------------------------------------------- map files

MAP_BYTES = default_map("signed").read_bytes()


def check_maps(saved):
    assert isinstance(saved, SavedMaps)
    assert all(np.all(np.isfinite(np.asarray(a))) for a in saved.ekm)
    assert saved.trials >= 1 and saved.ekm.w.shape[1:] == (saved.cfg.size, 2)


@FUZZ
@given(st.data())
def test_map_files_with_flipped_bytes_or_truncated_load_or_are_refused(tmp_path_factory, data):
    raw = bytearray(MAP_BYTES)
    if data.draw(st.booleans(), label="truncate"):
        raw = raw[: data.draw(st.integers(0, len(raw) - 1), label="length")]
    else:
        for _ in range(data.draw(st.integers(1, 8), label="flips")):
            i = data.draw(st.integers(0, len(raw) - 1), label="at")
            raw[i] ^= data.draw(st.integers(1, 255), label="mask")
    path = tmp_path_factory.mktemp("m") / "map.npz"
    path.write_bytes(bytes(raw))
    saved = assert_loads_or_refuses(lambda: load_maps(path))
    if saved is not None:
        check_maps(saved)


def rewritten(map_bytes, change):
    """The shipped map file with its arrays changed by ``change(arrays, meta)``, as new bytes."""
    with np.load(io.BytesIO(map_bytes)) as data:
        arrays = {k: data[k] for k in data.files}
    meta = json.loads(str(arrays.pop("metadata")))
    with np.errstate(invalid="ignore"):  # the change itself may cast NaN to int
        change(arrays, meta)
    buf = io.BytesIO()
    np.savez(buf, metadata=np.array(json.dumps(meta)), **arrays)
    return buf.getvalue()


ARRAY_CHANGES = st.sampled_from([
    ("shape", lambda a, m: a.__setitem__("M", a["M"][:, :7])),
    ("trials", lambda a, m: a.__setitem__("w", a["w"][:2])),
    ("ndim", lambda a, m: a.__setitem__("w", a["w"][0])),
    ("dtype int", lambda a, m: a.__setitem__("w", a["w"].astype(np.int64))),
    ("dtype complex", lambda a, m: a.__setitem__("M", a["M"].astype(np.complex64))),
    ("dtype string", lambda a, m: a.__setitem__("w", np.array(["x"] * 5))),
    ("nan", lambda a, m: a["M"].__setitem__((1, 3, 0, 1), np.nan)),
    ("inf", lambda a, m: a["w"].__setitem__((0, 0, 1), np.inf)),
    ("missing", lambda a, m: a.pop("M")),
    ("extra", lambda a, m: a.__setitem__("c", np.zeros((5, 225, 2), np.float32))),
    ("empty", lambda a, m: (a.__setitem__("w", a["w"][:0]), a.__setitem__("M", a["M"][:0]))),
    ("version", lambda a, m: m.__setitem__("version", 99)),
    ("version string", lambda a, m: m.__setitem__("version", "2")),
    ("format", lambda a, m: m.__setitem__("format", "something")),
    ("mapping", lambda a, m: m["ekm"].__setitem__("mapping", "diagonal")),
    ("neurons", lambda a, m: m["ekm"].__setitem__("neurons", 14)),
    ("neurons type", lambda a, m: m["ekm"].__setitem__("neurons", "15")),
    ("chart", lambda a, m: m["ekm"].__setitem__("chart", "cartesian")),
    ("gamma", lambda a, m: m["ekm"].__setitem__("gamma_alpha", -1.0)),
    ("no ekm", lambda a, m: m.pop("ekm")),
    ("arena", lambda a, m: m["train"].__setitem__("arena", [0, 1])),
    ("curve", lambda a, m: m.__setitem__("curve", [{"step": "x"}])),
])


@FUZZ
@given(st.lists(ARRAY_CHANGES, min_size=1, max_size=3, unique_by=lambda c: c[0]))
def test_map_files_with_wrong_arrays_or_metadata_are_refused_with_one_line(tmp_path_factory, changes):
    def change(arrays, meta):
        for _, f in changes:
            try:
                f(arrays, meta)
            except (KeyError, IndexError, TypeError, ValueError):  # an earlier change removed or reshaped its target
                pass

    path = tmp_path_factory.mktemp("m") / "map.npz"
    path.write_bytes(rewritten(MAP_BYTES, change))
    saved = assert_loads_or_refuses(lambda: load_maps(path))
    if saved is not None:
        check_maps(saved)


def test_a_pickled_object_in_a_map_file_is_refused_and_never_unpickled(tmp_path):
    class Bomb:
        def __reduce__(self):  # unpickling would run this
            return (exec, ("raise SystemExit('unpickled!')",))

    def change(arrays, meta):
        arrays["w"] = np.array([Bomb()], dtype=object)

    path = tmp_path / "pickled.npz"
    with np.load(io.BytesIO(MAP_BYTES)) as data:
        arrays = {k: data[k] for k in data.files}
    change(arrays, None)
    np.savez(path, **arrays)  # np.savez pickles object arrays
    with pytest.raises(InputError, match="refused|dtype"):
        load_maps(path)


def test_a_map_file_that_is_a_zip_of_something_else_is_refused(tmp_path):
    path = tmp_path / "other.npz"
    with zipfile.ZipFile(path, "w") as z:
        z.writestr("readme.txt", "hello")
    with pytest.raises(InputError, match="not an ekm map file|cannot read"):
        load_maps(path)
