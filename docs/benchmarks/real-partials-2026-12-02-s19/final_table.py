"""Per-set table of a bench JSON re-chosen with the vote-share rule (no gate; ranking
d * f^4 * exp(0.5 b) / s^delta): strict IoU, symmetry-aware IoU, strict P and R
(|R & G| = IoU (|R| + |G|) / (1 + IoU)), and the confidence (selection::confidence, its
margin recomputed from the candidates' pairwise IoUs) with its ROC AUC for "sym IoU >= 0.5"
and the IoU of the 80 % most confident results.

    python final_table.py full-votes.json.gz [DELTA=6]
"""
import gzip, json, math, sys, statistics as st
W = [8.0654, -13.7498, 3.165, -0.9818]
delta = float(sys.argv[2]) if len(sys.argv) > 2 else 6.0
opener = gzip.open if sys.argv[1].endswith('.gz') else open
d = json.load(opener(sys.argv[1], 'rt'))
def rank(c):
    dd, f = c.get('descriptor_score'), c.get('partial_fit')
    if dd is None or f is None: return math.inf
    s = c.get('vote_share'); s = 1.0 if s is None else max(s, 1e-3)
    return dd * f ** 4 * math.exp(0.5 * (c.get('boundary_misfit') or 0.0)) / s ** delta
def auc(scores, labels):
    pos = [s for s, l in zip(scores, labels) if l]; neg = [s for s, l in zip(scores, labels) if not l]
    if not pos or not neg: return float('nan')
    return sum((p > n) + 0.5 * (p == n) for p in pos for n in neg) / (len(pos) * len(neg))
allm, every = [], []
for s in d['sets']:
    rows = []
    for p in s['pairs']:
        cs = p['candidates']
        costed = [i for i, c in enumerate(cs) if c.get('region_cost') is not None] or list(range(len(cs)))
        i = min(costed, key=lambda i: (rank(cs[i]), i)); c = cs[i]
        R, G, iou = c['region_size'], p['gt_size'], c['iou']; inter = iou * (R + G) / (1 + iou)
        lr = lambda x: math.log(rank(x)) if 0 < rank(x) < math.inf else math.inf
        others = [lr(cs[j]) for j in range(len(cs)) if cs[j].get('region_cost') is not None and c['iou_with_candidates'][j] < 0.5]
        margin = min(min(others, default=math.inf) - lr(c), 3.0)
        if math.isnan(margin): margin = 0.0
        margin = max(min(margin, 3.0), -3.0)
        fit = min(max(c.get('partial_fit') or 1.0, 0.0), 10.0)
        cost = min(max(c.get('region_cost') or 1e3, 1e-6), 1e6)
        conf = 1 / (1 + math.exp(-(W[0] + W[1] * fit + W[2] * margin + W[3] * math.log(cost))))
        rows.append((iou, c['iou_sym'], inter / R if R else 0, inter / G if G else 0, conf))
    m = [st.mean(r[j] for r in rows) for j in range(4)]; allm.append(m); every += rows
    a = auc([r[4] for r in rows], [r[1] >= 0.5 for r in rows])
    print(f"{s['set']:14s} {len(rows):3d}  IoU {m[0]:.3f}  sym {m[1]:.3f}  P {m[2]:.3f}  R {m[3]:.3f}  conf AUC {a:.3f}")
print('mean of sets       IoU %.3f  sym %.3f  P %.3f  R %.3f' % tuple(st.mean(m[j] for m in allm) for j in range(4)))
top = sorted(every, key=lambda r: -r[4])[: int(0.8 * len(every))]
print('all %d pairs: confidence AUC %.3f (%d with sym IoU >= 0.5); sym IoU of the 80%% most confident %.3f, of all %.3f'
      % (len(every), auc([r[4] for r in every], [r[1] >= 0.5 for r in every]), sum(r[1] >= 0.5 for r in every), st.mean(r[1] for r in top), st.mean(r[1] for r in every)))
