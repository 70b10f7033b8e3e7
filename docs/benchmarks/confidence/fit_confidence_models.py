"""Fit the localizer's confidence across full shapes (selection::confidence), and report how
well it ranks results: the right full shape against the wrong ones, and good regions against bad
ones on the right shape.

    python fit_confidence_models.py BENCH.json RETRIEVAL.jsonl [FEATURES ...]

BENCH.json: `dualspectra bench --all DATA --json BENCH.json` (every dev pair on its own full
shape; label: symmetry-aware IoU >= 0.5). RETRIEVAL.jsonl: `cargo run --release -p
dualspectra-lab --example research_retrieval -- run DATA RETRIEVAL.jsonl shrec16:8
shrec16_holes:8 pfaust_m:22:1 pfaust_h:22:1` (each of those partials on every full shape of its
set; on a wrong shape the label is 0). FEATURES: comma-separated lists of fit (the chosen
region's partial fit), log_cost (log10 of the final alignment cost), log_region_cost,
share (vote share), log_desc (log10 descriptor score); default: fit and fit,log_cost.
A logistic model (Newton, L2 0.1) is fitted on the bench rows and the wrong-shape rows and
reported by the area under the ROC curve of right shape against wrong shapes (per set, all, and
leave one set out), of IoU >= 0.5 on the bench rows, and the share of wrong-shape results
at confidence >= 0.5.
"""
import json, sys, math
import numpy as np

def feats(fit, cost, region_cost, share, desc):
    return dict(
        fit=fit,
        log_cost=math.log10(max(cost, 1e-6)),
        log_region_cost=math.log10(max(region_cost or 1e3, 1e-6)),
        share=share if share is not None and math.isfinite(share) else 0.0,
        log_desc=math.log10(max(desc or 1e3, 1e-6)),
    )

def bench_rows(path):
    d = json.load(open(path))
    for s in d['sets']:
        for p in s['pairs']:
            if p.get('error') or not p.get('candidates'): continue
            c = p['candidates'][p['selected']]
            yield dict(set=s['set'], kind='own', label=int(p['scores_sym']['iou'] >= 0.5), conf=p['confidence'],
                       **feats(c['partial_fit'] or 1.0, p['cost'], c['region_cost'], c['vote_share'], c['descriptor_score']))

def retrieval_rows(path):
    for line in open(path):
        p = json.loads(line)
        if p.get('error') or not p.get('candidates'): continue
        c = p['candidates'][p['selected']]
        right = p['full'] == p['truth']
        yield dict(set=p['set'], kind='right' if right else 'wrong', label=int(right and (p.get('iou') or 0) >= 0.5),
                   conf=p['confidence'], partial=p['partial'],
                   **feats(c['partial_fit'] or 1.0, p['cost'] if p['cost'] is not None else 1e3, c['region_cost'], c['vote_share'], c['descriptor_score']))

def auc(pos, neg):
    pos, neg = np.asarray(pos), np.asarray(neg)
    if len(pos) == 0 or len(neg) == 0: return float('nan')
    gt = (pos[:, None] > neg[None, :]).sum() + 0.5 * (pos[:, None] == neg[None, :]).sum()
    return gt / (len(pos) * len(neg))

def fit_logistic(X, y, l2=0.1):
    X1 = np.hstack([np.ones((len(X), 1)), X])
    w = np.zeros(X1.shape[1])
    for _ in range(100):
        p = 1 / (1 + np.exp(-X1 @ w))
        g = X1.T @ (p - y) + l2 * np.r_[0, w[1:]]
        H = X1.T @ (X1 * (p * (1 - p))[:, None]) + l2 * np.diag(np.r_[0, np.ones(len(w) - 1)])
        w -= np.linalg.solve(H, g)
    return w

def predict(w, X):
    return 1 / (1 + np.exp(-(np.hstack([np.ones((len(X), 1)), X]) @ w)))

if __name__ == '__main__':
    bench, retr = sys.argv[1], sys.argv[2]
    feat_sets = [f.split(',') for f in (sys.argv[3:] or ['fit', 'fit,log_cost'])]
    B = list(bench_rows(bench)); R = list(retrieval_rows(retr))
    sets = sorted({r['set'] for r in R})
    print(f"bench rows {len(B)}, retrieval rows {len(R)} (right {sum(r['kind']=='right' for r in R)}, wrong {sum(r['kind']=='wrong' for r in R)})")
    def report(name, score):
        # AUC right model (IoU>=.5) vs wrong models, per set and all; AUC within model (bench).
        per = []
        for s in sets + ['all']:
            rows = [r for r in R if s == 'all' or r['set'] == s]
            per.append(auc([score(r) for r in rows if r['kind'] == 'right'], [score(r) for r in rows if r['kind'] == 'wrong']))
        own = auc([score(r) for r in B if r['label']], [score(r) for r in B if not r['label']])
        wrong_hi = np.mean([score(r) >= 0.5 for r in R if r['kind'] == 'wrong'])
        right_hi = np.mean([score(r) >= 0.5 for r in R if r['kind'] == 'right'])
        print(f"{name:40s} right-vs-wrong AUC " + ' '.join(f"{s}:{a:.3f}" for s, a in zip(sets + ['all'], per))
              + f" | own IoU>=.5 AUC {own:.3f} | wrong>=0.5: {wrong_hi:.2f}, right>=0.5: {right_hi:.2f}")
    report('confidence in the logs', lambda r: r['conf'])
    for fs in feat_sets:
        rows = B + [r for r in R if r['kind'] == 'wrong']
        X = np.array([[r[f] for f in fs] for r in rows]); y = np.array([r['label'] for r in rows])
        w = fit_logistic(X, y)
        report('in-sample ' + ','.join(fs), lambda r, w=w, fs=fs: predict(w, np.array([[r[f] for f in fs]]))[0])
        print('   weights', np.round(w, 4).tolist())
        # leave one set out (of the retrieval sets: its bench rows and wrong rows left out)
        preds = {}
        for s in sets:
            tr = [r for r in B if r['set'] != s] + [r for r in R if r['kind'] == 'wrong' and r['set'] != s]
            Xs = np.array([[r[f] for f in fs] for r in tr]); ys = np.array([r['label'] for r in tr])
            ws = fit_logistic(Xs, ys)
            for i, r in enumerate(R):
                if r['set'] == s: preds[i] = predict(ws, np.array([[r[f] for f in fs]]))[0]
        idx = {id(r): i for i, r in enumerate(R)}
        per = []
        for s in sets + ['all']:
            rows = [r for r in R if s == 'all' or r['set'] == s]
            per.append(auc([preds[idx[id(r)]] for r in rows if r['kind'] == 'right'], [preds[idx[id(r)]] for r in rows if r['kind'] == 'wrong']))
        print(f"   leave-one-set-out right-vs-wrong AUC " + ' '.join(f"{s}:{a:.3f}" for s, a in zip(sets + ['all'], per)))

