"""Per-set table of two `dualspectra bench --all --json` runs: python compare.py BEFORE.json[.gz] AFTER.json[.gz]"""
import sys,gzip,json
def load(p): return json.load(gzip.open(p) if p.endswith('.gz') else open(p))
a=load(sys.argv[1]); b=load(sys.argv[2])
print('| set | pairs | IoU strict before / after | sym before / after | P / R after | median s/pair after | pairs better / worse (sym, >0.05) |')
print('|---|---|---|---|---|---|---|')
for sa,sb in zip(a['sets'],b['sets']):
    A=sa['summary'];B=sb['summary']
    pa={p['name']:p['scores_sym']['iou'] for p in sa['pairs']}
    pb={p['name']:p['scores_sym']['iou'] for p in sb['pairs']}
    up=sum(pb[n]-pa[n]>0.05 for n in pb if n in pa); dn=sum(pa[n]-pb[n]>0.05 for n in pb if n in pa)
    print(f"| {sb['set']} | {B['pairs']} | {A['mean']['iou']:.3f} / **{B['mean']['iou']:.3f}** | {A['mean_sym']['iou']:.3f} / **{B['mean_sym']['iou']:.3f}** | {B['mean_sym']['precision']:.3f} / {B['mean_sym']['recall']:.3f} | {B['median_seconds']:.2f} | {up} / {dn} |")
A=a['mean_of_sets'];B=b['mean_of_sets']
print(f"| mean of sets | {B['pairs']} | {A['mean']['iou']:.3f} / **{B['mean']['iou']:.3f}** | {A['mean_sym']['iou']:.3f} / **{B['mean_sym']['iou']:.3f}** | {B['mean_sym']['precision']:.3f} / {B['mean_sym']['recall']:.3f} | {B['median_seconds']:.2f} | |")
