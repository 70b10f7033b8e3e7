"""Fit the localizer's confidence from `dualspectra bench --json` logs (every candidate's
scores and IoU are in them), and report how well it ranks results.

    python fit_confidence.py [FEATURE,FEATURE,...] OUT1.json [OUT2.json ...]

Label of a pair: symmetry-aware IoU >= 0.5. Features (default: the model of 2026-12-01,
partial_fit,consensus,margin; shipped from 2026-12-02: partial_fit,margin,log_region_cost;
shipped now: partial_fit; as in `selection::agreement` and `selection::confidence`):
  - log_region_cost: spectral misfit of the chosen region's step potential,
  - partial_fit: mean nearest SHOT distance of the partial into the region,
  - boundary_misfit: |ln(L_R / L_N)|,
  - consensus: fraction of the scored candidates whose region has IoU >= 0.5 with the
    chosen one (starts that agree),
  - margin: log ranking of the best-ranked disagreeing candidate minus the chosen one's
    (at most 3),
  - cost_ratio: log of the chosen region cost over the lowest,
  - support: mean IoU of the chosen region with the scored candidates' regions, each
    weighted by exp(-(log ranking - lowest log ranking)) (needs `iou_with_candidates`,
    bench JSON from 2026-12-02 on; 0 without),
  - fit_ratio: log of the chosen partial fit over the lowest partial fit of any candidate,
  - log_descriptor: log of the chosen descriptor score.
A logistic model on these, fitted by Newton's method (L2 0.1), is reported by its area
under the ROC curve, in-sample and leave-one-set-out (each set predicted by a model fitted
on the others), and by the mean IoU of the 80% most confident results.
"""
import gzip
import json
import sys

import numpy as np

# Partial-fit exponent of the ranking (selection::PARTIAL_FIT_EXPONENT; 2 before 2026-12-02 night):
# the margin is a difference of log rankings.
GAMMA = 4.0

FEATURES = sys.argv[1].split(",") if len(sys.argv) > 1 and ".json" not in sys.argv[1] else ["partial_fit", "consensus", "margin"]



def pair_rows(path):
    data = json.load(gzip.open(path, "rt") if path.endswith(".gz") else open(path))
    sets = data["sets"] if "sets" in data else [{"set": path, "pairs": data["pairs"]}]
    for s in sets:
        for p in s["pairs"]:
            if p.get("error") or not p.get("candidates"):
                continue
            cands = p["candidates"]
            chosen = cands[p["selected"]]
            scored = [c for c in cands if c.get("region_cost") is not None]
            consensus = np.mean([c["iou_with_chosen"] >= 0.5 for c in scored]) if scored else 0.0

            def rank(c):
                d, f, m = c.get("descriptor_score"), c.get("partial_fit"), c.get("boundary_misfit") or 0.0
                return np.log(d) + GAMMA * np.log(f) + 0.5 * m if d and f else np.inf

            others = [rank(c) for c in scored if c["iou_with_chosen"] < 0.5]
            margin = min(min(others) - rank(chosen), 3.0) if others else 3.0
            best_cost = min(c["region_cost"] for c in scored) if scored else 1.0
            cost_ratio = np.log(max(chosen.get("region_cost") or 1e3, 1e-9) / max(best_cost, 1e-9))
            ranks = [rank(c) for c in scored]
            low = min(ranks) if ranks else 0.0
            wts = [np.exp(-(r - low)) if np.isfinite(r) else 0.0 for r in ranks]
            idx = [i for i, c in enumerate(cands) if c.get("region_cost") is not None]
            overlaps = chosen.get("iou_with_candidates")
            support = (sum(w * overlaps[i] for w, i in zip(wts, idx)) / max(sum(wts), 1e-12)) if overlaps else 0.0
            fits = [c["partial_fit"] for c in cands if c.get("partial_fit")]
            fit_ratio = np.log((chosen.get("partial_fit") or 1.0) / min(fits)) if fits else 0.0
            yield s.get("set", s.get("dataset")), p["name"], p["scores_sym"]["iou"], {
                "log_region_cost": np.log(max(chosen.get("region_cost") or 1e3, 1e-6)),
                "partial_fit": chosen.get("partial_fit") or 1.0,
                "boundary_misfit": chosen.get("boundary_misfit") or 2.0,
                "consensus": consensus,
                "margin": margin,
                "cost_ratio": cost_ratio,
                "support": support,
                "fit_ratio": fit_ratio,
                "log_descriptor": np.log(max(chosen.get("descriptor_score") or 1e3, 1e-9)),
            }


def fit(x, y, l2=0.1, iters=50):
    x1 = np.hstack([x, np.ones((len(x), 1))])
    w = np.zeros(x1.shape[1])
    for _ in range(iters):
        p = 1 / (1 + np.exp(-x1 @ w))
        g = x1.T @ (p - y) + l2 * np.r_[w[:-1], 0]
        h = x1.T @ (x1 * (p * (1 - p))[:, None]) + l2 * np.eye(len(w))
        w -= np.linalg.solve(h, g)
    return w


def predict(w, x):
    return 1 / (1 + np.exp(-(np.hstack([x, np.ones((len(x), 1))]) @ w)))


def auc(score, y):
    pos, neg = score[y == 1], score[y == 0]
    if len(pos) == 0 or len(neg) == 0:
        return float("nan")
    return float(np.mean([(p > n) + 0.5 * (p == n) for p in pos for n in neg]))


def main(paths):
    paths = [p for p in paths if p.endswith((".json", ".json.gz"))]
    rows = [r for path in paths for r in pair_rows(path)]
    sets = np.array([r[0] for r in rows])
    iou = np.array([r[2] for r in rows])
    x = np.array([[r[3][f] for f in FEATURES] for r in rows])
    y = (iou >= 0.5).astype(float)
    mu, sd = x.mean(0), x.std(0) + 1e-12
    z = (x - mu) / sd
    w = fit(z, y)
    conf = predict(w, z)
    print(f"{len(rows)} pairs, {int(y.sum())} with IoU >= 0.5")
    print("in-sample AUC", round(auc(conf, y), 3))
    for i, f in enumerate(FEATURES):
        print(f"  AUC of {f} alone: {round(max(auc(z[:, i], y), 1 - auc(z[:, i], y)), 3)}")
    loso = np.zeros(len(rows))
    for s in np.unique(sets):
        test = sets == s
        if test.all():
            loso[:] = conf
            break
        ws = fit(z[~test], y[~test])
        loso[test] = predict(ws, z[test])
    print("leave-one-set-out AUC", round(auc(loso, y), 3))
    order = np.argsort(-conf)
    top = order[: int(round(0.8 * len(order)))]
    print(f"mean IoU all {iou.mean():.3f}, 80% most confident {iou[top].mean():.3f}")
    for s in np.unique(sets):
        m = sets == s
        print(f"  {s}: {m.sum()} pairs, AUC {auc(conf[m], y[m]):.3f}, mean conf {conf[m].mean():.3f}, mean IoU {iou[m].mean():.3f}")
    # Weights on raw features: conf = sigmoid(b + sum_i a_i x_i).
    a = w[:-1] / sd
    b = w[-1] - np.sum(w[:-1] * mu / sd)
    print("raw weights", {f: round(float(v), 4) for f, v in zip(FEATURES, a)}, "bias", round(float(b), 4))


if __name__ == "__main__":
    main(sys.argv[1:])
