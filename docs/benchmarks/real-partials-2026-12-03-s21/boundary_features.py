"""Boundary curves of every dev partial: vertex count, number of curves, and the rims other than
the longest over sqrt(partial area) ('others', the quantity HOLE_RIM_FRACTION thresholds).
Usage: python boundary_features.py DATA_ROOT OUT.json (numpy)."""
import numpy as np, os, sys, json, glob
from collections import defaultdict
def read_off(p):
    with open(p) as f:
        toks=f.read().split()
    i=0
    if toks[0].upper().startswith('OFF'):
        if toks[0].upper()!='OFF': toks[0]=toks[0][3:]; 
        else: i=1
    nv,nf=int(toks[i]),int(toks[i+1]); i+=3
    V=np.array(toks[i:i+3*nv],float).reshape(nv,3); i+=3*nv
    F=[]
    for _ in range(nf):
        n=int(toks[i]); F.append([int(t) for t in toks[i+1:i+1+n]]); i+=1+n
    return V,np.array(F)
def feats(p):
    V,F=read_off(p)
    E=np.sort(np.concatenate([F[:,[0,1]],F[:,[1,2]],F[:,[2,0]]]),axis=1)
    u,c=np.unique(E,axis=0,return_counts=True)
    b=u[c==1]
    # components of boundary edges
    parent=list(range(len(V)))
    def find(x):
        while parent[x]!=x: parent[x]=parent[parent[x]]; x=parent[x]
        return x
    for a,bb in b: parent[find(a)]=find(bb)
    comps=defaultdict(float)
    L=np.linalg.norm(V[b[:,0]]-V[b[:,1]],axis=1)
    for (a,bb),l in zip(b,L): comps[find(a)]+=l
    area=0.5*np.linalg.norm(np.cross(V[F[:,1]]-V[F[:,0]],V[F[:,2]]-V[F[:,0]]),axis=1).sum()
    ls=sorted(comps.values(),reverse=True)
    return dict(nv=len(V),loops=len(ls),longest=ls[0]/np.sqrt(area) if ls else 0,
                others=sum(ls[1:])/np.sqrt(area) if ls else 0, total=sum(ls)/np.sqrt(area))
root=sys.argv[1] if len(sys.argv)>1 else os.environ.get('DUALSPECTRA_DATA','../shared/datasets')
out={}
for s,pat in [('shrec16','shrec16/cuts/*.off'),('shrec16_holes','shrec16_holes/holes/*.off'),('pfarm','pfarm/cuts/*.off'),('pfaust_m','pfaust_m/partials/*.off'),('pfaust_h','pfaust_h/partials/*.off')]:
    for p in sorted(glob.glob(os.path.join(root,pat))):
        out[(s,os.path.basename(p)[:-4])]=feats(p)
json.dump({f'{k[0]}/{k[1]}':v for k,v in out.items()},open(sys.argv[2] if len(sys.argv)>2 else 'features.json','w'),indent=0)
for s in ['shrec16','shrec16_holes','pfarm','pfaust_m','pfaust_h']:
    fs=[v for k,v in out.items() if k[0]==s]
    lo=np.array([f['loops'] for f in fs]); print(s,len(fs),'loops median',np.median(lo),'min',lo.min(),'max',lo.max(),'nv median',np.median([f['nv'] for f in fs]), 'others/sqrtA median', np.median([f['others'] for f in fs]))
