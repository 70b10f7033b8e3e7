import math, statistics as st, collections, sys
FLOOR_RMS=0.1; k=20
num=lambda x: None if x=='-' else float(x)
sets={}
for s in ['shrec16','shrec16_holes','pfarm','pfaust_m','pfaust_h']:
    try:
        T=open(f'/work/runs/s19/vfull-{s}.txt').read().split('\n')[1:]
        E=[l for l in open(f'/work/runs/s19/vfull-{s}.err').read().split('\n') if l.startswith('VOTE')]
    except FileNotFoundError: continue
    T=[l for l in T if l.strip()]
    n=min(len(T),len(E))
    pairs=collections.OrderedDict()
    for t,e in zip(T[:n],E[:n]):
        r=t.split(); ev=e.split()
        assert r[1]==ev[1], (r,ev)
        pairs.setdefault(r[0],[]).append(dict(label=r[1],descriptor_score=num(r[3]),region_cost=num(r[4]),boundary_misfit=num(r[5]),partial_fit=num(r[6]),iou_sym=float(r[7]),star=len(r)>8,vf=float(ev[2])))
    # drop incomplete last pair
    if not pairs: continue
    last=list(pairs)[-1]
    if len(pairs[last])!=20: pairs.pop(last)
    sets[s]=list(pairs.values())
def rank(c, gamma, beta, bw=0.5):
    d, f = c.get('descriptor_score'), c.get('partial_fit')
    if d is None or f is None: return math.inf
    m = c.get('boundary_misfit') or 0.0
    return d * f ** gamma * math.exp(bw * m) / max(c['vf'],1e-3)**beta
def choose(cands, gate, gamma, beta):
    costs=[c['region_cost'] for c in cands if c.get('region_cost') is not None]
    g=max(gate*min(costs), 2*k*FLOOR_RMS**2)
    G=[i for i,c in enumerate(cands) if c.get('region_cost') is not None and c['region_cost']<=g]
    return min(G, key=lambda i:(rank(cands[i],gamma,beta), i))
for s,ps in sets.items():
    ok=sum(ps[i][choose(ps[i],3,4,0)]['star'] for i in range(len(ps)))
    print(s,len(ps),'pairs; replay matches star in',ok)
for gate in [float(x) for x in sys.argv[1].split(",")] if len(sys.argv)>1 else (3,10,1e9):
  for gamma in (4,):
    for beta in [float(x) for x in sys.argv[2].split(",")] if len(sys.argv)>2 else (0,0.5,1,2,3,4):
        out=[(s,st.mean(cs[choose(cs,gate,gamma,beta)]['iou_sym'] for cs in ps)) for s,ps in sets.items()]
        print('gate %-5g gamma %g beta %-4g'%(gate,gamma,beta),' '.join('%s %.3f'%(a[:8],b) for a,b in out),' mean %.3f'%st.mean(b for _,b in out))
