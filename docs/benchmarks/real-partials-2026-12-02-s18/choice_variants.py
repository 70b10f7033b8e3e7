"""Offline re-choice among the logged candidates of a `bench --all --json` run: the region-cost
gate (multiple of the lowest), the boundary weight, the partial-fit exponent gamma and the
descriptor score's exponent of the ranking. The first variant is selection::choose as it was
(gate 3, weight 0.5, gamma 2) and reproduces the bench's choice on every pair.

    python choice_variants.py full-descriptor-starts.json.gz
"""
import gzip, json, math, sys, statistics as st
FLOOR_RMS=0.1
def rank(c, bw, gamma, dpow):
    d, f = c.get('descriptor_score'), c.get('partial_fit')
    if d is None or f is None: return math.inf
    m = c.get('boundary_misfit') or 0.0
    return d**dpow * f ** gamma * math.exp(bw * m)
def choose(cands, k, gate, bw, gamma, dpow):
    costs=[c['region_cost'] for c in cands if c.get('region_cost') is not None]
    g=max(gate*min(costs), 2*k*FLOOR_RMS**2)
    G=[i for i,c in enumerate(cands) if c.get('region_cost') is not None and c['region_cost']<=g]
    return min(G, key=lambda i:(rank(cands[i],bw,gamma,dpow), i))
d=json.load(gzip.open(sys.argv[1],'rt'))
k=d['options']['k']
variants=[(3,0.5,2,1)]+[(3,0.5,gm,1) for gm in (2.5,3,3.5,5,6)]+[(g,0.5,2,1) for g in (5,10,30,1e9)]+[(3,0.5,gm,1) for gm in (4,8)]+[(g,0.5,gm,1) for g in (10,1e9) for gm in (4,8,16)]+[(g,bw,2,dp) for g in (3,10) for bw in (0.5,1.0) for dp in (0.5,0)]+[(1e9,0,1,0),(1e9,0.5,1,0),(10,0.5,1,0)]
for v in variants:
    out=[]
    for s in d['sets']:
        ious=[]
        for p in s['pairs']:
            cs=p['candidates']; i=choose(cs,k,*v); ious.append(cs[i]['iou_sym'])
        out.append((s['set'],st.mean(ious)))
    print('gate %-6g bw %.1f gamma %-2g dpow %.1f '%v, ' '.join('%s %.3f'%(a[:8],b) for a,b in out), ' mean %.3f'%st.mean(b for _,b in out))
