"""The ch. 6.1 test summary shared by ``ekm train`` and ``ekm evaluate``, printed as a table of P, T and D
over ε (the test itself: :func:`ekm.api.evaluation.summarize_test`)."""

from __future__ import annotations


def print_summary(s: dict, label: str) -> None:
    eps = list(s["P"])
    print(f"{label}: E = {s['E_mm']:.2f} mm over {s['trials']} trials x {s['targets']} targets "
          f"({s['capped']} hit the step cap before stopping)")
    print("  eps (mm)    " + "".join(f"{e:>9}" for e in eps))
    for key, fmt in (("P", "{:9.3f}"), ("T", "{:9.2f}"), ("D", "{:9.3f}")):
        print(f"  {key}(eps)      " + "".join(fmt.format(s[key][e]) if s[key][e] is not None else f"{'-':>9}"
                                          for e in eps))
