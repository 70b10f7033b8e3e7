"""Replace the descriptor-* candidates of the s18 290-pair JSON by those of research_candidates
logs (run with centers 0, plane_cuts 0), re-choose offline (gate 3, bw 0.5, gamma 4), per set.
usage: merge_choose.py TAG [--keep-old]   (logs: cands-TAG-SET.txt)"""
import gzip, json, math, sys, statistics as st, collections
FLOOR_RMS=0.1
tag=sys.argv[1]; keep='--keep-old' in sys.argv
def rank(c, bw=0.5, gamma=4, dpow=1):
    d, f = c.get('descriptor_score'), c.get('partial_fit')
    if d is None or f is None: return math.inf
    m = c.get('boundary_misfit') or 0.0
    return d**dpow * f ** gamma * math.exp(bw * m)
def choose(cands, k, gate=3):
    costs=[c['region_cost'] for c in cands if c.get('region_cost') is not None]
    g=max(gate*min(costs), 2*k*FLOOR_RMS**2)
    G=[i for i,c in enumerate(cands) if c.get('region_cost') is not None and c['region_cost']<=g]
    return min(G, key=lambda i:(rank(cands[i]), i))
d=json.load(gzip.open('/work/main/docs/benchmarks/real-partials-2026-12-02-s18/full-descriptor-starts.json.gz','rt'))
k=d['options']['k']
num=lambda x: None if x=='-' else float(x)
tot_old=[];tot_new=[]
for s in d['sets']:
    try: lines=open(f'/work/runs/s19/cands-{tag}-{s["set"]}.txt').read().split('\n')[1:]
    except FileNotFoundError: continue
    new=collections.defaultdict(list)
    for l in lines:
        r=l.split()
        if len(r)<8: continue
        new[r[0]].append(dict(label='new-'+r[1],cost=float(r[2]),descriptor_score=num(r[3]),region_cost=num(r[4]),boundary_misfit=num(r[5]),partial_fit=num(r[6]),iou_sym=float(r[7])))
    old_ch=[];new_ch=[];best=[];per=collections.defaultdict(list);chosen_lab=collections.Counter()
    for p in s['pairs']:
        if p['name'] not in new: continue
        cs=p['candidates']
        old_ch.append(cs[choose(cs,k)]['iou_sym'])
        base=[c for c in cs if keep or not c['label'].startswith('descriptor')]
        ncs=base+new[p['name']]
        i=choose(ncs,k); new_ch.append(ncs[i]['iou_sym']); chosen_lab[ncs[i]['label'].split('-')[0] if not ncs[i]['label'].startswith('new') else ncs[i]['label']]+=1
        best.append(max(c['iou_sym'] for c in ncs))
        for c in new[p['name']]: per[c['label']].append(c['iou_sym'])
    tot_old.append(st.mean(old_ch)); tot_new.append(st.mean(new_ch))
    print(f"{s['set']:14s} {len(old_ch):3d} chosen {st.mean(old_ch):.3f} -> {st.mean(new_ch):.3f}  best {st.mean(best):.3f}  "+' '.join(f'{l[4:]} {st.mean(v):.3f}' for l,v in sorted(per.items())), dict(chosen_lab))
print(f"mean of sets {st.mean(tot_old):.3f} -> {st.mean(tot_new):.3f}")
