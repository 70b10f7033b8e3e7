import sys, collections
tag=sys.argv[1]
out=[]
for s in ['shrec16','shrec16_holes','pfarm','pfaust_m','pfaust_h']:
    rows=[l.split() for l in open(f'/work/runs/s19/starts-{tag}-{s}.txt').readlines()[1:]]
    by=collections.defaultdict(dict)
    for p,l,i in rows: by[p][l]=float(i)
    labs=['descriptor-fit','descriptor-vote','descriptor-both']
    line=f'{s:14s} {len(by):3d}'
    for l in labs:
        v=[d[l] for d in by.values() if l in d]
        if v: line+=f' {l[11:]} {sum(v)/len(v):.3f}'
    best=[max(d.values()) for d in by.values()]
    bestnd=[max(v for k,v in d.items() if not k.startswith('descriptor')) for d in by.values()]
    line+=f' best {sum(best)/len(best):.3f} best-nondesc {sum(bestnd)/len(bestnd):.3f}'
    out.append(line)
print(f'== {tag}'); print('\n'.join(out))
