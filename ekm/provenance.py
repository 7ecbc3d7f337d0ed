"""What made a result, for reproducing it later: the package's version and, where JAX computed it, JAX's."""

from __future__ import annotations


def provenance(jax: bool = True) -> dict:
    """``{"ekm_version": …, "jax_version": …}`` (JAX's read from the installed metadata, without importing
    JAX; left out with ``jax=False``, for results JAX did not compute)."""
    from importlib.metadata import PackageNotFoundError, version

    from ekm import __version__

    out = {"ekm_version": __version__}
    if jax:
        try:
            out["jax_version"] = version("jax")
        except PackageNotFoundError:
            out["jax_version"] = None
    return out
