"""Summaries of the start studies of real-partials-2026-12-02-s18.md, from the
`research_candidates` logs in this folder (each set's log after a `# <set>` line):

    python starts_study.py ground-truth-start-candidates.log.gz   # DS_GT_START=1
    python starts_study.py descriptor-starts-candidates.log.gz

Per set: the mean symmetry-aware IoU of the chosen candidate, of the best candidate
(oracle), and of each `given#0` / `descriptor-*` start after its iterations; and how often
such a start was chosen. The 18-start baseline (the same pairs' candidates without the extra
starts, identical to the bench of real-partials-2026-12-02-s17) is the chosen candidate
among the others, taken from ../real-partials-2026-12-02-s17/full-base.json.gz.
"""
import gzip
import json
import os
import statistics as st
import sys

here = os.path.dirname(os.path.abspath(__file__))
base = {}
with gzip.open(os.path.join(here, "..", "real-partials-2026-12-02-s17", "full-base.json.gz"), "rt") as f:
    for s in json.load(f)["sets"]:
        for p in s["pairs"]:
            base[(s["set"], p["name"])] = (p["scores_sym"]["iou"], max(c["iou_sym"] for c in p["candidates"]))
sets, current = {}, None
with gzip.open(sys.argv[1], "rt") as f:
    for line in f:
        r = line.split()
        if line.startswith("# "):
            current = r[1]
        elif r and r[0] != "pair":
            sets.setdefault(current, {}).setdefault(r[0], []).append(r)
for s, pairs in sets.items():
    chosen, oracle, before, before_oracle, extra, taken = [], [], [], [], {}, {}
    for name, rows in pairs.items():
        pick = next(r for r in rows if len(r) > 8 and r[8] == "*")
        chosen.append(float(pick[7]))
        oracle.append(max(float(r[7]) for r in rows))
        for r in rows:
            if r[1].startswith(("given", "descriptor")):
                extra.setdefault(r[1], []).append(float(r[7]))
        if pick[1].startswith(("given", "descriptor")):
            taken[pick[1]] = taken.get(pick[1], 0) + 1
        b = base[(s, name)]
        before.append(b[0])
        before_oracle.append(b[1])
    starts = ", ".join(f"{k} {st.mean(v):.3f} (chosen {taken.get(k, 0)})" for k, v in extra.items())
    print(f"{s:14s} {len(chosen):2d} pairs: chosen {st.mean(chosen):.3f} (18 starts {st.mean(before):.3f}), "
          f"best candidate {st.mean(oracle):.3f} (18 starts {st.mean(before_oracle):.3f}); {starts}")
