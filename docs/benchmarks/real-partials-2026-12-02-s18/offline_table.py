"""Per-set means of a re-chosen bench JSON: strict IoU, symmetry-aware IoU, strict precision and
recall (from each candidate's IoU, region size and the truth's size:
|R & G| = IoU (|R| + |G|) / (1 + IoU))."""
import gzip, json, math, sys, statistics as st
def rank(c, g):
    return math.log(c['descriptor_score']) + g*math.log(c['partial_fit']) + 0.5*(c.get('boundary_misfit') or 0.0)
d=json.load(gzip.open(sys.argv[1],'rt')); gamma=float(sys.argv[2]); k=d['options']['k']
allm=[]
for s in d['sets']:
    rows=[]
    for p in s['pairs']:
        cs=p['candidates']; costs=[c['region_cost'] for c in cs if c.get('region_cost') is not None]
        g=max(3*min(costs),2*k*0.01)
        G=[i for i,c in enumerate(cs) if c.get('region_cost') is not None and c['region_cost']<=g]
        i=min(G,key=lambda i:(rank(cs[i],gamma),i)); c=cs[i]
        R,Gs,iou=c['region_size'],p['gt_size'],c['iou']; inter=iou*(R+Gs)/(1+iou)
        rows.append((iou,c['iou_sym'],inter/R if R else 0,inter/Gs if Gs else 0))
    m=[st.mean(r[j] for r in rows) for j in range(4)]; allm.append(m)
    print(f"{s['set']:14s} {len(rows):3d}  IoU {m[0]:.3f}  sym {m[1]:.3f}  P {m[2]:.3f}  R {m[3]:.3f}")
print('mean of sets      IoU %.3f  sym %.3f  P %.3f  R %.3f'%tuple(st.mean(m[j] for m in allm) for j in range(4)))
