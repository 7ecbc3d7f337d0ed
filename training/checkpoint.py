"""Training checkpoints: everything a long ``ekm train`` needs to continue where it stopped, bit for bit.

A checkpoint holds the whole per-trial training carry (:class:`training.online.Trainee`: maps, robots,
current targets, their ages), the step reached, the run's PRNG key, the learning curve so far and the
settings of the run (the map's and the protocol's hyper-parameters, seed, test and output settings).
Training after step ``done`` depends on nothing else — each chunk's noise is drawn from
``fold_in(key_run, step)`` — so a resumed run computes exactly what the uninterrupted one would have.

Format: ``.npz`` without pickle — one array per leaf of the carry, named by its path (``ekm.w``,
``robot.pose``, ...), the key as ``key_run`` — plus a JSON ``metadata`` entry. Written atomically
(:func:`ekm.files.atomic_write`): an interruption during a save leaves the previous checkpoint whole.
Loading checks the format, version, settings and every array against a fresh carry of the same
settings and raises :class:`ekm.errors.InputError` naming what is wrong.
"""

from __future__ import annotations

import json
import zipfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ekm.errors import InputError
from ekm.files import atomic_write

FORMAT = "ekm-train-checkpoint"
VERSION = 1


@dataclass(frozen=True)
class Checkpoint:
    """A training run stopped after ``done`` steps: the carry ``trainees`` (leading trial axis), ``key_run``,
    the ``curve`` so far and the run's ``settings`` (a JSON-able dict, see :func:`training.run.train`)."""

    trainees: object
    done: int
    key_run: np.ndarray
    curve: list
    settings: dict


def _leaf_names(tree) -> list[str]:
    import jax

    return [".".join(str(getattr(k, "name", getattr(k, "key", getattr(k, "idx", k)))) for k in path)
            for path, _ in jax.tree_util.tree_flatten_with_path(tree)[0]]


def save_checkpoint(path, ckpt: Checkpoint) -> Path:
    """Write ``ckpt`` to ``path`` atomically; returns the path."""
    import jax

    from ekm import __version__

    path = Path(path)
    leaves = jax.tree_util.tree_leaves(ckpt.trainees)
    arrays = {f"carry.{name}": np.asarray(leaf) for name, leaf in zip(_leaf_names(ckpt.trainees), leaves)}
    arrays["key_run"] = np.asarray(ckpt.key_run)
    meta = {"format": FORMAT, "version": VERSION, "done": int(ckpt.done), "curve": ckpt.curve,
            "settings": ckpt.settings, "package_version": __version__, "jax_version": jax.__version__}
    text = json.dumps(meta, allow_nan=False)
    with atomic_write(path) as tmp, open(tmp, "wb") as fh:
        np.savez(fh, metadata=np.array(text), **arrays)
    return path


def saved_step(path) -> int | None:
    """The step a checkpoint file holds, from its metadata alone; None if there is no readable one."""
    try:
        with np.load(path, allow_pickle=False) as data:
            return int(json.loads(str(data["metadata"]))["done"])
    except Exception:  # noqa: BLE001 — any unreadable file means "no checkpoint to offer"
        return None


def load_checkpoint(path, template_of) -> Checkpoint:
    """Read a checkpoint written by :func:`save_checkpoint`.

    ``template_of(settings)`` builds a fresh carry for the checkpoint's settings (the shapes, dtypes and
    tree structure the arrays must have); every mismatch is an :class:`InputError`.
    """
    import jax

    path = Path(path)
    where = str(path)
    if not path.is_file():
        raise InputError(f"{where}: no such training checkpoint")
    try:
        with np.load(path, allow_pickle=False) as data:
            arrays = {k: data[k] for k in data.files}
    except (zipfile.BadZipFile, OSError, EOFError, ValueError) as exc:
        raise InputError(f"{where}: not a training checkpoint ({exc.__class__.__name__}: {exc})") from None
    try:
        meta = json.loads(str(arrays.pop("metadata")))
    except (KeyError, json.JSONDecodeError, TypeError):
        raise InputError(f"{where}: not a training checkpoint (no readable metadata)") from None
    if not isinstance(meta, dict) or meta.get("format") != FORMAT:
        raise InputError(f"{where}: not a training checkpoint (format {meta.get('format') if isinstance(meta, dict) else meta!r})")
    if meta.get("version") != VERSION:
        raise InputError(f"{where}: training checkpoint version {meta.get('version')!r} is not supported "
                         f"(this ekm reads version {VERSION})")
    settings, done, curve = meta.get("settings"), meta.get("done"), meta.get("curve")
    if not isinstance(settings, dict) or not isinstance(done, int) or not isinstance(curve, list):
        raise InputError(f"{where}: training checkpoint metadata is incomplete (settings, done, curve)")
    try:
        template = template_of(settings)
    except (InputError, KeyError, TypeError, ValueError) as exc:
        raise InputError(f"{where}: training checkpoint settings are invalid ({exc})") from None
    if not 0 < done <= template.settings_steps:
        raise InputError(f"{where}: step {done} is outside the run's 1..{template.settings_steps} steps")
    leaves, treedef = jax.tree_util.tree_flatten(template.carry)
    names = _leaf_names(template.carry)
    loaded = []
    for name, leaf in zip(names, leaves):
        key = f"carry.{name}"
        if key not in arrays:
            raise InputError(f"{where}: array {key!r} is missing")
        a = arrays.pop(key)
        want = np.asarray(leaf)
        if a.shape != want.shape or a.dtype != want.dtype:
            raise InputError(f"{where}: array {key!r} has shape {a.shape} and dtype {a.dtype}, "
                             f"expected {want.shape} {want.dtype}")
        if a.dtype.kind == "f" and not np.all(np.isfinite(a)):
            raise InputError(f"{where}: array {key!r} contains NaN or infinite values")
        loaded.append(a)
    key_run = arrays.pop("key_run", None)
    if key_run is None or key_run.shape != template.key_shape or key_run.dtype != np.uint32:
        raise InputError(f"{where}: 'key_run' is missing or not a PRNG key")
    if arrays:
        raise InputError(f"{where}: unexpected arrays {sorted(arrays)}")
    import jax.numpy as jnp

    trainees = jax.tree_util.tree_unflatten(treedef, [jnp.asarray(a) for a in loaded])
    return Checkpoint(trainees=trainees, done=done, key_run=key_run, curve=curve, settings=settings)
