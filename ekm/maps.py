"""One entry point for both mappings: ``init``, ``control`` and ``update`` dispatch on the map type.

The dispatch happens at trace time (the pytree's class is static), so jitted code contains only the
chosen mapping.
"""

from __future__ import annotations

from ekm import direct, indirect
from ekm.config import EKMConfig
from ekm.direct import DirectEKM
from ekm.indirect import IndirectEKM

EKM = DirectEKM | IndirectEKM
_MODULES = {"direct": direct, "indirect": indirect}


def module_of(ekm_or_cfg):
    """The module (``ekm.direct`` or ``ekm.indirect``) implementing a map or a config's mapping."""
    if isinstance(ekm_or_cfg, EKMConfig):
        return _MODULES[ekm_or_cfg.mapping]
    return indirect if isinstance(ekm_or_cfg, IndirectEKM) else direct


def init(cfg: EKMConfig) -> EKM:
    """A fresh, untrained map of ``cfg.mapping`` kind."""
    return module_of(cfg).init(cfg)


def control(ekm: EKM, u, cfg: EKMConfig):
    """Wheel command and winner ``(c_p, k)`` for target input ``u`` = (α, d)."""
    return module_of(ekm).control(ekm, u, cfg)


def update(ekm: EKM, v, c_p, eta, sigma, cfg: EKMConfig) -> EKM:
    """One online learning step from executed command ``c_p`` and displacement ``v`` (ch. 4.3)."""
    return module_of(ekm).update(ekm, v, c_p, eta, sigma, cfg)


def learn(ekm: EKM, v, c_p, eta, g, cfg: EKMConfig) -> EKM:
    """:func:`update` for given neighbourhood weights ``g`` ``(N²,)`` (the winner already chosen)."""
    return module_of(ekm).learn(ekm, v, c_p, eta, g, cfg)
