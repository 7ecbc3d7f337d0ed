"""The ch. 6.1 test summary shared by ``ekm train`` and ``ekm evaluate``: run it on stacked maps, and
print it as a table of P, T and D over ε."""

from __future__ import annotations


def summarize_test(maps, cfg, arena, targets: int, seed: int) -> dict:
    """The ch. 6.1 test of stacked maps, summarised (E, P, T, D, capped)."""
    from evaluation.metrics import summarize
    from evaluation.protocol import evaluate

    return summarize(evaluate(maps, cfg, arena, targets=targets, seed=seed))


def print_summary(s: dict, label: str) -> None:
    eps = list(s["P"])
    print(f"{label}: E = {s['E_mm']:.2f} mm over {s['trials']} trials x {s['targets']} targets "
          f"({s['capped']} hit the step cap before stopping)")
    print("  eps (mm)    " + "".join(f"{e:>9}" for e in eps))
    for key, fmt in (("P", "{:9.3f}"), ("T", "{:9.2f}"), ("D", "{:9.3f}")):
        print(f"  {key}(eps)      " + "".join(fmt.format(s[key][e]) if s[key][e] is not None else f"{'-':>9}"
                                          for e in eps))
