"""Saved maps: npz without pickle, JSON metadata, atomic writes, checked loads (docs/design.md §3); and map files
generated and mutated by hypothesis, each loaded or refused with the package's own one-line error."""

import io
import json
import zipfile

import jax
import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from ekm import maps
from ekm.config import EKMConfig
from ekm.data import default_map
from ekm.errors import InputError
from ekm.mapfile import VERSION, SavedMaps, load_maps, save_maps
from tests.fuzzing import FUZZ, assert_loads_or_refuses


def stacked(cfg, trials=3):
    """``trials`` different maps stacked along a leading axis (untrained ones, randomly perturbed)."""
    one = maps.init(cfg)
    keys = jax.random.split(jax.random.PRNGKey(0), len(one))
    return type(one)(*(a + 0.01 * jax.random.normal(k, (trials,) + a.shape) for a, k in zip(one, keys)))


@pytest.mark.parametrize("mapping", ["direct", "indirect"])
def test_round_trip_keeps_every_array_and_hyper_parameter(tmp_path, mapping):
    cfg = EKMConfig(mapping=mapping, neurons=6, gamma_d=2.5, priority=4, chart="polar")
    ekm = stacked(cfg)
    ekm = type(ekm)(ekm.w, ekm[1] + 0.01)
    path = save_maps(tmp_path / "m.npz", ekm, cfg, {"steps": 123, "seed": 7, "curve": [{"step": 0, "E_mm": 1.0}]})
    loaded = load_maps(path)
    assert loaded.cfg == cfg and loaded.trials == 3
    assert type(loaded.ekm) is type(ekm)
    for a, b in zip(loaded.ekm, ekm):
        np.testing.assert_array_equal(np.asarray(a), np.asarray(b))
    assert loaded.meta["steps"] == 123 and loaded.meta["version"] == VERSION
    assert loaded.meta["jax_version"] == jax.__version__
    with np.load(path, allow_pickle=False) as data:  # plain arrays: loads without pickle
        assert set(data.files) == {"metadata", "w", "M" if mapping == "indirect" else "c"}


def test_save_is_atomic_and_leaves_no_partial_file(tmp_path, monkeypatch):
    cfg = EKMConfig(neurons=4)
    target = tmp_path / "m.npz"

    def broken(*args, **kwargs):
        raise OSError("disk full")

    monkeypatch.setattr(np, "savez", broken)
    with pytest.raises(OSError):
        save_maps(target, stacked(cfg), cfg)
    assert list(tmp_path.iterdir()) == []


def rewrite(path, tmp_path, **changes):
    """A copy of the map file at ``path`` with some entries replaced (None drops one)."""
    with np.load(path, allow_pickle=False) as data:
        arrays = {k: data[k] for k in data.files}
    for k, v in changes.items():
        if v is None:
            arrays.pop(k)
        else:
            arrays[k] = v
    out = tmp_path / "bad.npz"
    np.savez(out, **arrays)
    return out


@pytest.fixture
def good(tmp_path):
    cfg = EKMConfig(neurons=4)
    return save_maps(tmp_path / "good.npz", stacked(cfg, 2), cfg)


def meta_of(path):
    with np.load(path, allow_pickle=False) as data:
        return json.loads(str(data["metadata"]))


@pytest.mark.parametrize("case, message", [
    ("nan", "contains NaN"),
    ("angle", "directions outside"),
    ("shape", "has shape"),
    ("dtype", "dtype"),
    ("missing", "missing array 'M'"),
    ("version", "version 99 is not supported"),
    ("format", "not an ekm map file"),
    ("trials", "trials"),
    ("object", "refused"),
    ("arena", "train.arena"),
    ("curve", "'curve'"),
])
def test_bad_map_files_are_refused_with_a_clear_message(good, tmp_path, case, message):
    w = np.load(good)["w"]
    meta = meta_of(good)
    if case == "nan":
        bad = rewrite(good, tmp_path, w=np.where(np.arange(w.size).reshape(w.shape) == 5, np.nan, w))
    elif case == "angle":
        bad = rewrite(good, tmp_path, w=w + np.array([4.0, 0.0], w.dtype))
    elif case == "shape":
        bad = rewrite(good, tmp_path, w=w[:, :10])
    elif case == "dtype":
        bad = rewrite(good, tmp_path, w=w.astype(np.int32))
    elif case == "missing":
        bad = rewrite(good, tmp_path, M=None)
    elif case == "version":
        bad = rewrite(good, tmp_path, metadata=np.array(json.dumps(meta | {"version": 99})))
    elif case == "format":
        bad = rewrite(good, tmp_path, metadata=np.array(json.dumps(meta | {"format": "other"})))
    elif case == "arena":
        bad = rewrite(good, tmp_path, metadata=np.array(json.dumps(meta | {"train": {"arena": [1.0, "wide"]}})))
    elif case == "curve":
        bad = rewrite(good, tmp_path, metadata=np.array(json.dumps(meta | {"curve": [{"step": 0}]})))
    elif case == "trials":
        bad = rewrite(good, tmp_path, w=np.concatenate([w, w]))
    else:
        bad = tmp_path / "bad.npz"
        np.savez(bad, metadata=np.array(json.dumps(meta)), w=np.array([{"a": 1}], dtype=object))
    with pytest.raises(InputError, match=message) as info:
        load_maps(bad)
    assert str(bad) in str(info.value) and "\n" not in str(info.value)


def test_not_a_map_file(tmp_path):
    text = tmp_path / "notes.npz"
    text.write_text("hello")
    with pytest.raises(InputError, match="not an .npz archive"):
        load_maps(text)
    with pytest.raises(InputError, match="no such map file"):
        load_maps(tmp_path / "missing.npz")
    other = tmp_path / "other.npz"
    with zipfile.ZipFile(other, "w") as z:
        z.writestr("readme.txt", "hi")
    with pytest.raises(InputError):
        load_maps(other)


def test_version_1_files_load_as_maps_of_the_polar_chart(good, tmp_path):
    """Files written before ``chart`` existed (format version 1) hold maps trained on the thesis's polar input."""
    meta = meta_of(good)
    assert meta["version"] == VERSION == 2 and meta["ekm"]["chart"] == "signed"
    old = meta | {"version": 1, "ekm": {k: v for k, v in meta["ekm"].items() if k != "chart"}}
    loaded = load_maps(rewrite(good, tmp_path, metadata=np.array(json.dumps(old))))
    assert loaded.cfg.chart == "polar" and loaded.cfg.neurons == 4
    np.testing.assert_array_equal(np.asarray(loaded.ekm.w), np.load(good)["w"])


# -------------------------------------------------------------------------------------------------- fuzzing

# Every input either loads into valid maps or raises InputError — no other exception, and no warning that
# would reach a user's terminal (tests/fuzzing.py).

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


@pytest.mark.parametrize("change, message", [
    ({"ekm": 0}, "metadata 'ekm' must be an object, got 0"),  # an AttributeError's traceback before issue 34
    ({"ekm": {"c_max": True}}, "metadata 'ekm.c_max' must be float, got true"),
    ({"ekm": {"neurons": "4"}}, "metadata 'ekm.neurons' must be int, got \"4\""),
    ({"robot": {"name": 7}}, "metadata 'robot' must be an object with a name"),
    ({"seed": "x"}, "metadata 'seed' must be int, got \"x\""),
])
def test_metadata_the_package_reads_is_refused_in_one_line_when_of_the_wrong_type(good, tmp_path, change, message):
    meta = meta_of(good)
    for key, value in change.items():
        meta[key] = {**meta[key], **value} if isinstance(value, dict) and key == "ekm" else value
    bad = rewrite(good, tmp_path, metadata=np.array(json.dumps(meta)))
    with pytest.raises(InputError) as info:
        load_maps(bad)
    assert str(info.value) == f"{bad}: {message}" or str(info.value).startswith(f"{bad}: {message}")
