"""Offline re-choice from a bench --all JSON with vote shares: per set, all pairs / even / odd."""
import json, math, sys, statistics as st
FLOOR_RMS=0.1
d=json.load(open(sys.argv[1])); k=d['options']['k']
def rank(c, gamma, beta, bw=0.5):
    dd, f = c.get('descriptor_score'), c.get('partial_fit')
    if dd is None or f is None: return math.inf
    m = c.get('boundary_misfit') or 0.0
    s = c.get('vote_share'); s = 1.0 if s is None else max(s,1e-3)
    return dd * f ** gamma * math.exp(bw * m) / s**beta
def choose(cands, gate, gamma, beta):
    costs=[c['region_cost'] for c in cands if c.get('region_cost') is not None]
    g=max(gate*min(costs), 2*k*FLOOR_RMS**2)
    G=[i for i,c in enumerate(cands) if c.get('region_cost') is not None and c['region_cost']<=g]
    return min(G, key=lambda i:(rank(cands[i],gamma,beta), i))
variants=[(3,4,0),(3,4,3),(1e9,4,0),(1e9,4,2),(1e9,4,3),(1e9,4,4),(1e9,4,6),(30,4,3),(100,4,3),(1e9,2,3),(1e9,3,3),(1e9,6,3)]
if len(sys.argv)>2: variants=[tuple(float(x) for x in v.split(':')) for v in sys.argv[2:]]
for part in ('all','even','odd'):
    print('==',part)
    for v in variants:
        out=[]
        for s in d['sets']:
            ps=[p for i,p in enumerate(s['pairs']) if part=='all' or (i%2==0)==(part=='even')]
            ps=[p for p in ps if p.get('candidates')]
            out.append((s['set'],st.mean(p['candidates'][choose(p['candidates'],*v)]['iou_sym'] for p in ps)))
        print('gate %-5g gamma %g beta %-3g'%v,' '.join('%s %.3f'%(a[:8],b) for a,b in out),' mean %.3f'%st.mean(b for _,b in out))
