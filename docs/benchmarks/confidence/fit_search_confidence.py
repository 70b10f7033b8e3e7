"""Fit the search's confidence across models (search::search_confidence), and report how well
it tells the right model from the wrong ones over library queries.

    python fit_search_confidence.py SEARCH.jsonl [--distances DISTANCES.json] [FEATURES ...]

SEARCH.jsonl: `cargo run --release -p dualspectra-lab --example research_search -- DATA
SEARCH.jsonl` (every dev partial searched in the 180 models of `library/`, shortlist 10; one
line per query with every located model's score, localization confidence and whether it was
a quick localization). A row per located model; label: the model is of the right class.
FEATURES: comma-separated lists of gap and lead (how far the score is behind, or ahead of,
the lowest score of the other located models, clamped to 1 and 0.05, in units of 0.01), rgap
(the gap over the range of the query's located scores), mgap (the gap over the median of the
query's located scores less the lowest, clamped to 3), margin
(lead - gap), logit (the logit of the localization's confidence, clamped to [1e-6, 1 - 1e-6]),
quick (1 for a quick localization), score (the similarity score itself, units of 0.01), position (0 for the best, 1 for the second...), first,
screen_gap (the screen score's gap to the query's best, units of 0.01), best_logit (the logit
of the best model's localization confidence), and with --distances (`research_model_distances
DATA DISTANCES.json`: the screen's distance between every two library models) kin (the located
model's distance to the best located model, 0 for the best) and rkin (kin over its median
among the other located models, clamped to 3); default: logit;
gap,logit; gap,lead,logit; rgap,lead,logit; mgap,lead,logit (the product's
search_confidences).
A logistic model (Newton, L2 0.1) is fitted on every row and reported by the area under the
ROC curve of right against wrong models (per set, all, and fitted leaving that set out), of
the answers (each query's best model, right against wrong; all, then per set), and the share of wrong models at confidence >= 0.5 and of right ones below it.
"""
import json, math, sys

import numpy as np

# The same AUC and logistic fit as the localization's confidence.
from fit_confidence_models import auc, fit_logistic, predict

MAX_GAP = 1.0
MAX_LEAD = 0.05
CLAMP = 1e-6


def rows(path, max_gap=MAX_GAP, max_lead=MAX_LEAD, distances=None):
    """One row per located model of every query. `distances`: the screen's model distances
    (`research_model_distances`), for the kin features."""
    if distances is not None:
        index = {n: i for i, n in enumerate(distances['names'])}
        D = distances['distances']
    for line in open(path):
        q = json.loads(line)
        located = [m for m in q['ranking'] if m['located'] and m['score'] is not None]
        if len(located) < 2:
            continue
        screen = [m['screen_score'] for m in q['ranking'] if m.get('screen_score') is not None]
        screen_best = min(screen) if screen else 0.0
        scores = sorted(m['score'] for m in located)
        best = min(located, key=lambda m: m['score'])
        if distances is not None:
            # How alike each located model looks to the best one, over the median of that
            # among the others.
            to_best = [D[index[m['model']]][index[best['model']]] for m in located]
            spread = sorted(d for m, d in zip(located, to_best) if m is not best)
            spread = max(spread[len(spread) // 2], 1e-12)
        for i, m in enumerate(located):
            best_other = min(o['score'] for j, o in enumerate(located) if j != i)
            diff = min(max(m['score'] - best_other, -max_lead), max_gap)
            p = min(max(m['confidence'], CLAMP), 1 - CLAMP)
            best_p = min(max(best['confidence'], CLAMP), 1 - CLAMP)
            row = dict(
                set=q['set'], partial=q['partial'], label=int(m['class'] == q['right']), conf=m['confidence'],
                gap=max(diff, 0.0) / 0.01, lead=max(-diff, 0.0) / 0.01, margin=-diff / 0.01,
                logit=math.log(p / (1 - p)), quick=float(m['quick']), score=m['score'] / 0.01,
                position=float(scores.index(m['score'])), first=float(m['score'] == scores[0]),
                rgap=max(diff, 0.0) / max(scores[-1] - scores[0], 1e-12),
                mgap=min(max(diff, 0.0) / max(scores[len(scores) // 2] - scores[0], 1e-12), 3.0),
                screen_gap=((m.get('screen_score') or screen_best) - screen_best) / 0.01,
                best_logit=math.log(best_p / (1 - best_p)),
            )
            if distances is not None:
                row['kin'] = to_best[i] if m is not best else 0.0
                row['rkin'] = min(to_best[i] / spread, 3.0) if m is not best else 0.0
            yield row


def matrix(R, features):
    return np.array([[r[f] for f in features] for r in R]), np.array([r['label'] for r in R], dtype=float)


def report(R, name, score):
    sets = sorted({r['set'] for r in R})
    cells = []
    for s in sets + ['all']:
        rs = [r for r in R if s == 'all' or r['set'] == s]
        cells.append(auc([score(r) for r in rs if r['label']], [score(r) for r in rs if not r['label']]))
    # The answers: each query's best model, right against wrong (all sets, then per set).
    tops = [r for r in R if r['first']]
    cells.append(auc([score(r) for r in tops if r['label']], [score(r) for r in tops if not r['label']]))
    for s in sets:
        t = [r for r in tops if r['set'] == s]
        cells.append(auc([score(r) for r in t if r['label']], [score(r) for r in t if not r['label']]))
    wrong_high = np.mean([score(r) >= 0.5 for r in R if not r['label']])
    right_low = np.mean([score(r) < 0.5 for r in R if r['label']])
    print(f"| {name} | " + " | ".join(f"{c:.3f}" for c in cells) + f" | {wrong_high:.3f} | {right_low:.3f} |")


if __name__ == '__main__':
    args = sys.argv[1:]
    distances = None
    if '--distances' in args:
        at = args.index('--distances')
        distances = json.load(open(args[at + 1]))
        del args[at:at + 2]
    sys.argv = [sys.argv[0]] + args
    R = list(rows(sys.argv[1], distances=distances))
    sets = sorted({r['set'] for r in R})
    print(f"{len(R)} located models ({sum(r['label'] for r in R)} right) of "
          f"{len({(r['set'], r['partial']) for r in R})} queries\n")
    print("| confidence | " + " | ".join(sets) + " | all | answers | " + " | ".join(f"answers {s}" for s in sets)
          + " | wrong >= 0.5 | right < 0.5 |")
    print("|---|" + "---|" * (2 * len(sets) + 4))
    report(R, "localization's", lambda r: r['conf'])
    for spec in sys.argv[2:] or ['logit', 'gap,logit', 'gap,lead,logit', 'rgap,lead,logit', 'mgap,lead,logit']:
        features = spec.split(',')
        X, y = matrix(R, features)
        w = fit_logistic(X, y)
        index = {id(r): i for i, r in enumerate(R)}
        p = predict(w, X)
        report(R, f"{spec}: w = [{', '.join(f'{v:.4g}' for v in w)}]", lambda r: p[index[id(r)]])
        # Leave one set out: each set scored by the model fitted on the others.
        if len(sets) < 2:
            continue
        held = {}
        for s in sets:
            train = [r for r in R if r['set'] != s]
            Xt, yt = matrix(train, features)
            wt = fit_logistic(Xt, yt)
            test = [r for r in R if r['set'] == s]
            for r, v in zip(test, predict(wt, matrix(test, features)[0])):
                held[id(r)] = v
        report(R, f"{spec}, each set left out of its fit", lambda r: held[id(r)])
