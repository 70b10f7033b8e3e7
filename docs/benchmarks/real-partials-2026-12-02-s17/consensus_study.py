"""Offline re-choice among logged candidates: current rule vs support-weighted choices.
usage: python3 consensus_study.py full-base.json.gz [more bench JSON ...]"""
import gzip, json, math, sys
from collections import defaultdict

GATE, FLOOR_RMS, BW, GAMMA = 3.0, 0.1, 0.5, 2.0

def ranking(c):
    d, f = c.get('descriptor_score'), c.get('partial_fit')
    if d is None or f is None: return math.inf
    m = c.get('boundary_misfit') or 0.0
    return d * f ** GAMMA * math.exp(BW * m)

def gated(cands, k):
    costs = [c['region_cost'] for c in cands if c.get('region_cost') is not None]
    best = min(costs)
    floor = 2 * k * FLOOR_RMS ** 2
    g = max(GATE * best, floor)
    return [i for i, c in enumerate(cands) if c.get('region_cost') is not None and c['region_cost'] <= g]

def choose(cands, k, tau=None, power=1.0):
    G = gated(cands, k)
    r = {i: ranking(cands[i]) for i in G}
    if tau is None:
        return min(G, key=lambda i: (r[i], i))
    lmin = min(math.log(r[i]) for i in G if r[i] > 0)
    w = {j: math.exp(-(math.log(r[j]) - lmin) / tau) for j in G}
    def support(i):
        return sum(w[j] * cands[i]['iou_with_candidates'][j] ** power for j in G)
    return max(G, key=lambda i: (support(i), -r[i], -i))

def load(paths):
    pairs = []
    for p in paths:
        d = json.load(gzip.open(p, 'rt') if p.endswith('.gz') else open(p))
        sets = d['sets'] if 'sets' in d else [d]
        for s in sets:
            name = s.get('dataset', p)
            for pr in s['pairs']:
                if pr.get('candidates'):
                    pairs.append((name, pr))
    return pairs

pairs = load(sys.argv[1:])
rules = [('current', None, 1.0)] + [(f'tau={t} p={pw}', t, pw) for t in (0.05, 0.1, 0.2, 0.3, 0.5, 1.0) for pw in (1.0, 2.0)]
for name, tau, pw in rules:
    per = defaultdict(list)
    for set_name, pr in pairs:
        k = 20
        i = choose(pr['candidates'], k, tau, pw)
        per[set_name.split('/')[-1]].append(pr['candidates'][i]['iou_sym'])
    means = {s: sum(v) / len(v) for s, v in per.items()}
    print(f'{name:16s}', ' '.join(f'{s}:{m:.3f}({len(per[s])})' for s, m in sorted(means.items())), f' mean of sets {sum(means.values())/len(means):.3f}')
