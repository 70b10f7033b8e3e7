# usage: cmpn.py BASE.json[.gz] NAME=FILE.txt|json ... : per-set mean sym IoU on the pairs present in every file
import json,gzip,sys,re,os,numpy as np
def load(p): return json.load(gzip.open(p) if p.endswith('.gz') else open(p))
def rows(p):
    out={}
    if p.endswith('.json') or p.endswith('.gz'):
        d=load(p)
        if 'sets' not in d: d={'sets':[dict(d, set=d.get('set') or os.path.basename(d['dataset']))]}
        for s in d['sets']:
            for q in s['pairs']:
                if q.get('error') is None: out[(s['set'],q['name'])]=q['scores_sym']['iou']
        return out
    cur=None
    m=re.search(r"-(pfarm|shrec16_holes|shrec16|pfaust_m|pfaust_h)\.txt",p); cur=m.group(1) if m else None
    for line in open(p):
        if line.startswith('== '): cur=line.split()[1]; continue
        t=line.split()
        if cur and len(t)>=9:
            try: out[(cur,t[0])]=float(t[6])
            except: pass
    return out
base=rows(sys.argv[1]); news=[]
for a in sys.argv[2:]:
    n,f=a.split('=',1); r={}
    for ff in f.split(','): r.update(rows(ff))
    news.append((n,r))
keys=set(base)
for _,r in news: keys&=set(r)
sets=['shrec16','shrec16_holes','pfarm','pfaust_m','pfaust_h']
print('%-22s'%'variant'+''.join('%10s'%s[:9] for s in sets)+'   mean')
def line(n,r):
    ms=[]
    for s in sets:
        k=[x for x in keys if x[0]==s]
        ms.append(np.mean([r[x] for x in k]) if k else float('nan'))
    print('%-22s'%n+''.join('%10.3f'%m for m in ms)+'  %.3f'%np.nanmean(ms))
print('pairs', {s:len([x for x in keys if x[0]==s]) for s in sets})
line('base',base)
for n,r in news: line(n,r)
