"""Offline selection study: re-choose among the candidates logged by
`DS_VERBOSE=1 cargo run --release --example 401_localize_shrec -- $DATA` (one line per
optimised start: final cost, descriptor score `sel`, region cost `rc`, symmetry-aware IoU,
region topology and boundary length) with alternative rules. The optimised starts are the
same for every rule, so the comparison has none of the re-run noise (one flipped choice moves
a 16-pair mean by ~0.06). `gated` re-implements `alignment::selection::choose` (the default
rule) and reproduces the logged choice.

    python3 docs/benchmarks/selection_study.py docs/benchmarks/shrec16-2026-11-24-s8-candidates.log

`--max-cut M` keeps only the spectral-cut starts `cut1+` .. `cutM-` of a log (the others
all): on `shrec16-2026-11-24-s10-candidates-spectral6.log` (default starts + 6 cuts),
`--max-cut 0` is the session-10 default and 3, 4 the `--spectral-cuts` settings measured.

`--centres C` keeps the starts of the first C farthest-point centres (in the log's order,
which is the sampling order): on `shrec16-2026-11-24-s11-candidates-48.log.gz` (16 centres,
48 starts, with the descriptor-fit column `df` of session 11), `--centres 4` is the default.
`--max-plane N` keeps only the plane-cut starts `plane0` .. `plane{N-1}` (the others all):
on `shrec16-2026-11-24-s12-candidates-planes26.log.gz` (4 centres' 12 starts + 26 plane
cuts), `--max-plane 6` is the session-12 default and `--max-plane 0` session 11's. Options
come before the log files. Logs may be gzipped.
"""
import gzip, math, re, sys, statistics

def parse(path):
    pairs = []
    cur = None
    for line in (gzip.open(path, 'rt') if path.endswith('.gz') else open(path)):
        m = re.match(r'^(cuts_\S+)\s+iou ([0-9.]+) \(direct ([0-9.]+)\).*oracle ([0-9.]+)', line)
        if m:
            cur = dict(name=m.group(1), iou=float(m.group(2)), oracle=float(m.group(4)), cands=[], blen=float('nan'), n=40)
            pairs.append(cur)
            continue
        m = re.match(r'^\s+partial: chi (-?\d+) comp (\d+) blen ([0-9.]+)', line)
        if m and cur:
            cur['blen'] = float(m.group(3))
            continue
        m = re.match(r'^\s+(\*?)\s*(\S+)\s+cost\s+(\S+) sel\s+(\S+) rc\s+(\S+) iou ([0-9.]+) it (\d+) chi (-?\d+) comp (\d+) blen ([0-9.]+)', line)
        if m and cur:
            df = re.search(r' df (\S+)', line)
            cur['cands'].append(dict(fin=m.group(1) == '*', label=m.group(2), cost=float(m.group(3)), sel=float(m.group(4)),
                                     rc=float(m.group(5)), iou=float(m.group(6)), chi=int(m.group(8)), comp=int(m.group(9)), blen=float(m.group(10)),
                                     df=float(df.group(1)) if df else float('nan')))
    return [p for p in pairs if p['cands']]

def misfit(c, p):
    if c['blen'] > 0 and p['blen'] > 0:
        return abs(math.log(c['blen'] / p['blen']))
    return 0.0

def gated(p, gate=3.0, floor_rms=0.1, beta=0.5, cost_gate=None):
    cands = [c for c in p['cands'] if c['fin']]
    best = min((c['rc'] for c in cands if math.isfinite(c['rc'])), default=math.inf)
    floor = p['n'] * floor_rms ** 2
    pool = [c for c in cands if c['rc'] <= max(gate * best, floor)] if math.isfinite(best) else cands
    if cost_gate is not None:
        bc = min(c['cost'] for c in pool)
        pool = [c for c in pool if c['cost'] <= cost_gate * bc]
    return min(pool, key=lambda c: c['sel'] * math.exp(beta * misfit(c, p)))

def mean(xs):
    return sum(xs) / len(xs) if xs else float('nan')

def keep_cuts(pairs, max_cut):
    """Drop the spectral-cut starts `cutJ+`/`cutJ-` with J > max_cut."""
    def keep(c):
        m = re.match(r'cut(\d+)[+-]$', c['label'])
        return m is None or int(m.group(1)) <= max_cut
    return [dict(p, cands=[c for c in p['cands'] if keep(c)],
                 oracle=max(c['iou'] for c in p['cands'] if keep(c))) for p in pairs]

def keep_planes(pairs, count):
    """Drop the plane-cut starts `planeJ` with J >= count."""
    def keep(c):
        m = re.match(r'plane(\d+)$', c['label'])
        return m is None or int(m.group(1)) < count
    return [dict(p, cands=[c for c in p['cands'] if keep(c)],
                 oracle=max(c['iou'] for c in p['cands'] if keep(c))) for p in pairs]

def keep_centres(pairs, count):
    """Keep the starts around the first `count` centres (labels `kind@vertex...`); others all."""
    def centre(c):
        m = re.match(r'\w+@(\d+)', c['label'])
        return m.group(1) if m else None
    out = []
    for p in pairs:
        order = []
        for c in p['cands']:
            if centre(c) is not None and centre(c) not in order:
                order.append(centre(c))
        keep = set(order[:count])
        cands = [c for c in p['cands'] if centre(c) is None or centre(c) in keep]
        out.append(dict(p, cands=cands, oracle=max(c['iou'] for c in cands)))
    return out

if __name__ == '__main__':
    args = sys.argv[1:]
    max_cut = centres = max_plane = None
    while args[:1] in (['--max-cut'], ['--centres'], ['--max-plane']):
        if args[0] == '--max-cut':
            max_cut = int(args[1])
        elif args[0] == '--max-plane':
            max_plane = int(args[1])
        else:
            centres = int(args[1])
        args = args[2:]
    pairs = [q for f in args for q in parse(f)]
    if max_cut is not None:
        pairs = keep_cuts(pairs, max_cut)
    if centres is not None:
        pairs = keep_centres(pairs, centres)
    if max_plane is not None:
        pairs = keep_planes(pairs, max_plane)
    print(f"{len(pairs)} pairs; logged chosen {mean([p['iou'] for p in pairs]):.3f} oracle {mean([p['oracle'] for p in pairs]):.3f}")
    halves = [[p for i, p in enumerate(pairs) if i % 2 == h] for h in (0, 1)]
    def report(name, rule):
        r = [mean([rule(p)['iou'] for p in h]) for h in halves]
        print(f"{name:40s} all {mean([rule(p)['iou'] for p in pairs]):.3f}  halves {r[0]:.3f} / {r[1]:.3f}")
    report('gated (current)', gated)
    for cg in [2, 3, 5, 10, 30, 100]:
        report(f'gated + cost gate {cg}', lambda p, cg=cg: gated(p, cost_gate=cg))
    report('lowest cost', lambda p: min(p['cands'], key=lambda c: c['cost']))
    report('lowest rc', lambda p: min(p['cands'], key=lambda c: c['rc']))
    report('lowest sel', lambda p: min(p['cands'], key=lambda c: c['sel']))
    for g in [1.5, 2, 4, 6, 10]:
        report(f'gate {g}', lambda p, g=g: gated(p, gate=g))
    for b in [0, 0.25, 1, 2]:
        report(f'boundary weight {b}', lambda p, b=b: gated(p, beta=b))
    for gam in [0.1, 0.25, 0.5, 1]:
        report(f'sel * rc^{gam} * exp(0.5 misfit)',
               lambda p, gam=gam: min(p['cands'], key=lambda c: c['sel'] * max(c['rc'], 1e-9) ** gam * math.exp(0.5 * misfit(c, p))))
    def rank_rule(p, w):
        cs = p['cands']
        rsel = {i: r for r, i in enumerate(sorted(range(len(cs)), key=lambda i: cs[i]['sel']))}
        rrc = {i: r for r, i in enumerate(sorted(range(len(cs)), key=lambda i: cs[i]['rc']))}
        return cs[min(range(len(cs)), key=lambda i: rsel[i] + w * rrc[i])]
    for w in [0.5, 1, 2]:
        report(f'rank(sel) + {w} rank(rc)', lambda p, w=w: rank_rule(p, w))
    if all(not math.isnan(c['df']) for p in pairs for c in p['cands']):
        with_fit = lambda p, f: dict(p, cands=[dict(c, sel=f(c)) for c in p['cands']])
        report('gated, descriptor fit for sel', lambda p: gated(with_fit(p, lambda c: c['df'])))
        report('gated, sel * fit', lambda p: gated(with_fit(p, lambda c: c['sel'] * c['df'])))
        report('gated, sel * fit^2', lambda p: gated(with_fit(p, lambda c: c['sel'] * c['df'] ** 2)))
        report('lowest fit', lambda p: min(p['cands'], key=lambda c: c['df']))
