"""Which starts are needed: re-run the choice offline on a subset of each pair's starts.

Every score of a candidate (descriptor score, region cost, partial fit, boundary misfit,
vote share) is computed from that candidate alone, and the choice is the lowest ranking among
the candidates with a region cost (dualspectra::selection::choose), so leaving starts out of
a `bench --json` run gives exactly the result a run without those starts would give. The
confidence is recomputed the same way (its margin looks at the other candidates).

usage: python3 start_subsets.py BENCH.json[.gz] [all|holes|noholes] [VERTICES]
  all: every pair takes the subset; holes: only pairs optimised on more than VERTICES
  (default 1,500: the partials with holes in the s21 run; 3,000 for a run at resolution
  2,000); noholes: the others.
"""
import gzip, json, math, sys

RANK = dict(boundary=0.5, fit_exp=4.0, share_exp=6.0, share_floor=1e-3)
CONF_W = [8.0654, -13.7498, 3.165, -0.9818]   # selection::CONFIDENCE_WEIGHTS
MAX_MARGIN = 3.0

def rank(c):
    if c['descriptor_score'] is None or c['partial_fit'] is None:
        return math.inf
    m = c['boundary_misfit'] if c['boundary_misfit'] is not None else 0.0
    s = 1.0 if c['vote_share'] is None else max(c['vote_share'], RANK['share_floor'])
    return c['descriptor_score'] * c['partial_fit'] ** RANK['fit_exp'] * math.exp(RANK['boundary'] * m) / s ** RANK['share_exp']

def choose(cs):
    eligible = [c for c in cs if c['region_cost'] is not None] or cs
    return min(eligible, key=rank)   # min keeps the first of ties, as the library does

def confidence(chosen, cs):
    f = min(max(chosen['partial_fit'] if chosen['partial_fit'] is not None else 1.0, 0.0), 10.0)
    r = min(max(chosen['region_cost'] if chosen['region_cost'] is not None else 1000.0, 1e-6), 1e6)
    log_rank = lambda x: math.log(rank(x)) if 0 < rank(x) < math.inf else math.inf
    i = cs.index(chosen)
    others = [log_rank(o) for o in cs if o['region_cost'] is not None and o['iou_with_candidates'][i] < 0.5]
    g = min(min(others, default=math.inf) - log_rank(chosen), MAX_MARGIN)
    g = 0.0 if math.isnan(g) else g
    z = CONF_W[0] + CONF_W[1] * f + CONF_W[2] * g + CONF_W[3] * math.log(r)
    return 1.0 / (1.0 + math.exp(-z))

def auc(scores, labels):
    pos = [s for s, l in zip(scores, labels) if l]
    neg = [s for s, l in zip(scores, labels) if not l]
    if not pos or not neg:
        return float('nan')
    return sum((p > n) + 0.5 * (p == n) for p in pos for n in neg) / len(pos) / len(neg)

# Starts in a 20-start run: ball/coball/bump for centres 0-3 (indices 0-11), plane0-5, descriptor-fit, descriptor-vote.
SUBSETS = {
    'all': lambda l, i: True,
    'no-planes': lambda l, i: not l.startswith('plane'),
    '2centres': lambda l, i: not 6 <= i < 12,
    '3centres': lambda l, i: not 9 <= i < 12,
    'no-bump': lambda l, i: not l.startswith('bump'),
    'no-coball': lambda l, i: not l.startswith('coball'),
    'no-ball': lambda l, i: not l.startswith('ball'),
    'desc-only': lambda l, i: l.startswith('descriptor'),
    'desc+2c': lambda l, i: l.startswith('descriptor') or i < 6,
    'desc+planes': lambda l, i: l.startswith('descriptor') or l.startswith('plane'),
    'desc+balls': lambda l, i: l.startswith('descriptor') or l.startswith('ball'),
    'desc+bumps': lambda l, i: l.startswith('descriptor') or l.startswith('bump'),
    'planes+centres': lambda l, i: not l.startswith('descriptor'),
}

def main():
    path = sys.argv[1]
    mask = sys.argv[2] if len(sys.argv) > 2 else 'all'
    threshold = int(sys.argv[3]) if len(sys.argv) > 3 else 1500
    data = json.load(gzip.open(path) if path.endswith('.gz') else open(path))
    sets = data['sets'] if 'sets' in data else [{'set': data.get('dataset', '?'), 'pairs': data['pairs']}]
    print('subset        ' + ' '.join(f"{s['set'][:12]:>12s}" for s in sets) + '   mean   AUC(conf, IoU>=0.5)')
    for name, keep in SUBSETS.items():
        means, confs, labels = [], [], []
        for s in sets:
            ious = []
            for p in s['pairs']:
                cs = p['candidates']
                holes = p.get('optimisation_vertices', 0) > threshold
                if (mask == 'holes' and not holes) or (mask == 'noholes' and holes):
                    ious.append(p['scores_sym']['iou'])
                    confs.append(p['confidence']); labels.append(p['scores_sym']['iou'] >= 0.5)
                    continue
                idx = [i for i, c in enumerate(cs) if keep(c['label'], i)]
                if not idx:
                    ious.append(0.0); confs.append(0.0); labels.append(False)
                    continue
                sub = [dict(cs[i], iou_with_candidates=[cs[i]['iou_with_candidates'][j] for j in idx]) for i in idx]
                chosen = choose(sub)
                ious.append(chosen['iou_sym'])
                confs.append(confidence(chosen, sub)); labels.append(chosen['iou_sym'] >= 0.5)
            means.append(sum(ious) / len(ious))
        print(f"{name:14s}" + ' '.join(f"{m:12.3f}" for m in means) + f"   {sum(means) / len(means):.3f}  {auc(confs, labels):.3f}")

if __name__ == '__main__':
    main()
