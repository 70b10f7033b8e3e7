"""Session 12 offline study: the best IoU with the ground truth of balls/coballs with the
partial's area around farthest-point centres of the null shape (fps4/16/40) or any of 400.

    python3 ball_fit.py [PAIR_SUBSTRING ...]   ($DUALSPECTRA_DATA/shrec16; numpy, scipy)
"""
import numpy as np, scipy.sparse as sp, scipy.sparse.csgraph as cg, sys, os, re
D=os.path.join(os.environ.get('DUALSPECTRA_DATA', '../shared/datasets'), 'shrec16')
def off(p):
    t=open(p).read().split(); i=1 if t[0]=='OFF' else 0
    nv,nf=int(t[i]),int(t[i+1]); i+=3
    V=np.array(t[i:i+3*nv],float).reshape(nv,3); i+=3*nv
    F=np.array(t[i:i+4*nf],int).reshape(nf,4)[:,1:]; return V,F
def mass(V,F):
    a=0.5*np.linalg.norm(np.cross(V[F[:,1]]-V[F[:,0]],V[F[:,2]]-V[F[:,0]]),axis=1)
    m=np.zeros(len(V)); 
    for k in range(3): np.add.at(m,F[:,k],a/3)
    return m
def graph(V,F):
    e=np.concatenate([F[:,[0,1]],F[:,[1,2]],F[:,[2,0]]]); w=np.linalg.norm(V[e[:,0]]-V[e[:,1]],axis=1)
    return sp.coo_matrix((np.r_[w,w],(np.r_[e[:,0],e[:,1]],np.r_[e[:,1],e[:,0]])),shape=(len(V),)*2).tocsr()
def fps(V,n,first=0):
    ch=[first]; d=((V-V[first])**2).sum(1)
    while len(ch)<n: j=int(d.argmax()); ch.append(j); d=np.minimum(d,((V-V[j])**2).sum(1))
    return ch
def iou(a,b): return (a&b).sum()/max((a|b).sum(),1)
names=sorted(f[:-4] for f in os.listdir(D+'/cuts') if f.endswith('.off'))
only=sys.argv[1:] 
cache={}
res=[]
for nm in names:
    if only and not any(o in nm for o in only): continue
    cls=re.match(r'cuts_(\w+)_shape',nm).group(1)
    if cls not in cache:
        V,F=off(f'{D}/null/{cls}.off'); m=mass(V,F); G=graph(V,F)
        C=fps(V,400); Dm=cg.dijkstra(G,indices=C)
        cache[cls]=(V,F,m,Dm)
    V,F,m,Dm=cache[cls]
    Vp,Fp=off(f'{D}/cuts/{nm}.off'); ap=mass(Vp,Fp).sum(); at=m.sum()
    gts=[]
    for suf in ('baryc_gt','baryc_gt_sym'):
        rows=np.loadtxt(f'{D}/cuts/{nm}.{suf}',ndmin=2); t=rows[:,0].astype(int)-1
        g=np.zeros(len(V),bool); g[F[t].ravel()]=True; gts.append(g)
    best=[]
    for ci in range(len(Dm)):
        d=Dm[ci]; o=np.argsort(d,kind='stable'); cm=np.cumsum(m[o])
        k=np.searchsorted(cm,ap); ball=np.zeros(len(V),bool); ball[o[:k+1]]=True
        k2=np.searchsorted(cm,at-ap); co=np.ones(len(V),bool); co[o[:k2+1]]=False
        best.append(max(max(iou(ball,g),iou(co,g)) for g in gts))
    best=np.array(best)
    res.append((nm,ap/at,best.max(),best[:4].max(),best[:16].max(),best[:40].max()))
    print('%-24s frac %.2f any400 %.2f fps4 %.2f fps16 %.2f fps40 %.2f'%res[-1],flush=True)
r=np.array([x[2:] for x in res]); print('mean any400 %.3f fps4 %.3f fps16 %.3f fps40 %.3f'%tuple(r.mean(0)))
