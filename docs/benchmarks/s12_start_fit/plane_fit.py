"""Session 12 offline study: the best IoU with the ground truth of the side of a plane with
the partial's area, over 6 (principal axes both ways) / 26 (and diagonals) directions in the
principal frame, or 16 / 32 / 128 directions spread on the sphere. Reuses ball_fit.py.

    python3 plane_fit.py [PAIR_SUBSTRING ...]
"""
import numpy as np, sys, os, re, itertools
exec(open(os.path.join(os.path.dirname(os.path.abspath(__file__)), 'ball_fit.py')).read().split('names=sorted')[0])
def sphere_dirs(n):
    i=np.arange(n)+0.5; phi=np.arccos(1-2*i/n); th=np.pi*(1+5**0.5)*i
    return np.c_[np.cos(th)*np.sin(phi),np.sin(th)*np.sin(phi),np.cos(phi)]
cube=np.array([d for d in itertools.product([-1,0,1],repeat=3) if any(d)],float); cube/=np.linalg.norm(cube,axis=1)[:,None]
axes6=np.array([d for d in cube if np.count_nonzero(d)==1])
names=sorted(f[:-4] for f in os.listdir(D+'/cuts') if f.endswith('.off'))
only=sys.argv[1:]
cache={}; res=[]
for nm in names:
    if only and not any(o in nm for o in only): continue
    cls=re.match(r'cuts_(\w+)_shape',nm).group(1)
    if cls not in cache:
        V,F=off(f'{D}/null/{cls}.off'); m=mass(V,F)
        c=(m[:,None]*V).sum(0)/m.sum(); X=V-c; Cv=(X*m[:,None]).T@X; w,U=np.linalg.eigh(Cv)
        cache[cls]=(V,F,m,U[:,::-1])
    V,F,m,U=cache[cls]
    Vp,Fp=off(f'{D}/cuts/{nm}.off'); ap=mass(Vp,Fp).sum()
    gts=[]
    for suf in ('baryc_gt','baryc_gt_sym'):
        rows=np.loadtxt(f'{D}/cuts/{nm}.{suf}',ndmin=2); t=rows[:,0].astype(int)-1
        g=np.zeros(len(V),bool); g[F[t].ravel()]=True; gts.append(g)
    def fit(dirs):
        out=[]
        for dv in dirs:
            h=V@dv; o=np.argsort(-h,kind='stable'); cm=np.cumsum(m[o]); k=np.searchsorted(cm,ap)
            r=np.zeros(len(V),bool); r[o[:k+1]]=True
            out.append(max(iou(r,g) for g in gts))
        return max(out)
    row=(nm,fit(axes6@U.T),fit(cube@U.T),fit(sphere_dirs(16)),fit(sphere_dirs(32)),fit(sphere_dirs(128)))
    res.append(row)
    print('%-24s pca6 %.2f pca26 %.2f fib16 %.2f fib32 %.2f fib128 %.2f'%row,flush=True)
r=np.array([x[1:] for x in res]); print('mean pca6 %.3f pca26 %.3f fib16 %.3f fib32 %.3f fib128 %.3f'%tuple(r.mean(0)))
