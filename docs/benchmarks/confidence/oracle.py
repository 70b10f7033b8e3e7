"""Where the localizer loses, per set, from `dualspectra bench --json` logs: the chosen
candidate's symmetry-aware IoU against the best candidate's (the oracle: what a perfect
choice among the same starts would give), and which start families hold the best.

    python oracle.py OUT1.json [OUT2.json ...]
"""
import collections
import json
import re
import sys


def main(paths):
    for path in paths:
        data = json.load(open(path))
        sets = data["sets"] if "sets" in data else [{"set": path.split("/")[-1], "pairs": data["pairs"]}]
        for s in sets:
            pairs = [p for p in s["pairs"] if not p.get("error")]
            if not pairs:
                continue
            chosen = sum(p["scores_sym"]["iou"] for p in pairs) / len(pairs)
            oracle = sum(max(c["iou_sym"] for c in p["candidates"]) for p in pairs) / len(pairs)
            fam = collections.Counter()
            for p in pairs:
                best = max(p["candidates"], key=lambda c: c["iou_sym"])
                fam[re.sub(r"[@#0-9].*", "", best["label"])] += 1
            print(f"{s['set']}: {len(pairs)} pairs, chosen {chosen:.3f}, oracle {oracle:.3f}, best family {dict(fam)}")


if __name__ == "__main__":
    main(sys.argv[1:])
