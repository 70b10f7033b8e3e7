import json,gzip,sys,numpy as np
def load(p): return json.load(gzip.open(p) if p.endswith('.gz') else open(p))
for f in sys.argv[1:]:
    d=load(f); out=[]
    for s in d['sets']:
        v=[];fi=[];best=[]
        for p in s['pairs']:
            c={x['label'][:15]:x['iou_sym'] for x in p['candidates']}
            v.append(c.get('descriptor-vote',np.nan)); fi.append(c.get('descriptor-fit',np.nan)); best.append(max(x['iou_sym'] for x in p['candidates']))
        out.append('%s vote %.3f fit %.3f best %.3f'%(s['set'][:8],np.nanmean(v),np.nanmean(fi),np.mean(best)))
    print(f.split('/')[-1][:12], ' | '.join(out))
