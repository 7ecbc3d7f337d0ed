"""Positioning metrics of thesis ch. 6.1: E (Eq. 6.1), P(ε), T(ε) (Eq. 6.2), D(ε) (Eq. 6.3)."""

from __future__ import annotations

import numpy as np

from evaluation.protocol import EPSILONS, TargetRecord


def summarize(rec: TargetRecord) -> dict:
    """Metrics over every trial and target of ``rec`` (arrays with leading axes (trials, targets)).

    - ``E_mm``: mean distance to the target after stopping, over R·N targets (Eq. 6.1), in mm;
    - ``P[ε]``: fraction of targets approached closer than ε, with or without stopping;
    - ``T[ε]``: mean over the reached targets of t_i(ε)/l_i, control steps per metre (Eq. 6.2);
    - ``D[ε]``: mean over the reached targets of |d_i(ε) - l_i| / l_i (Eq. 6.3);
    - ``capped``: number of targets where the step cap was hit before the robot stopped.

    T and D are undefined for a target never reached within ε; they average over reached targets, and
    P says how many those are. Keys of P, T, D are ε in mm (as strings, for JSON).
    """
    error = np.asarray(rec.error, dtype=float)
    hit = np.asarray(rec.hit, dtype=bool)
    straight = np.asarray(rec.straight, dtype=float)[..., None]
    t_norm = np.asarray(rec.time, dtype=float) / straight
    dev = np.abs(np.asarray(rec.path, dtype=float) - straight) / straight
    out = {"E_mm": 1000.0 * float(error.mean()), "P": {}, "T": {}, "D": {},
           "trials": int(error.shape[0]) if error.ndim > 1 else 1, "targets": int(error.shape[-1]),
           "capped": int(np.asarray(rec.capped).sum())}
    for j, eps in enumerate(EPSILONS):
        key = f"{round(eps * 1000):d}"
        h = hit[..., j]
        out["P"][key] = float(h.mean())
        out["T"][key] = float(t_norm[..., j][h].mean()) if h.any() else None
        out["D"][key] = float(dev[..., j][h].mean()) if h.any() else None
    return out
