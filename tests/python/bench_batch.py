#!/usr/bin/env python3
"""Benchmark of `dualspectra.batch.search_batch` in other units (`scale="auto"`), in this
process: PFAUST partials searched in the FAUST models of the library (a metre-scale body
against partials at unit area), shortlist 10, the library's screen built once.

    python tests/python/bench_batch.py [DATA] [--partials N]

DATA: the datasets folder (default: $DUALSPECTRA_DATA). Three runs of the same batch, in
this order, in the same process:
- `search`: `ds.search` per partial (the reference: one query's localizations share the
  partial's scale scan);
- `batch, each task afresh`: `search_batch` with no partial kept prepared
  (`_PREPARED_PARTIALS = 0`: every (partial, full shape) task takes the partial in and
  scans its scale again);
- `batch`: `search_batch` as shipped (each partial taken in once per process).
Prints seconds per run and per partial, the ratio to `search`, and whether every ranking
(model order and scores) is the same as `search`'s.
"""
from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import dualspectra as ds
import dualspectra.batch as batch


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("data", nargs="?", default=os.environ.get("DUALSPECTRA_DATA"))
    parser.add_argument("--partials", type=int, default=8, help="PFAUST-M partials (every 10th)")
    args = parser.parse_args()
    if not args.data or not Path(args.data).is_dir():
        print("bench_batch: give the datasets folder (or set DUALSPECTRA_DATA)", file=sys.stderr)
        return 2
    data = Path(args.data)
    models = sorted((data / "library" / "shapes").glob("faust_tr_reg_*.off"))
    partial_files = sorted((data / "pfaust_m" / "partials").glob("tr_reg_*.off"))[:: 10][: args.partials]
    if not models or not partial_files:
        print(f"bench_batch: no FAUST models or PFAUST-M partials under {data}", file=sys.stderr)
        return 2
    fulls = [ds.read_mesh(str(p)) for p in models]
    partials = [ds.read_mesh(str(p)) for p in partial_files]
    t = time.perf_counter()
    screen = ds.Screen(fulls)
    print(f"{len(partials)} PFAUST-M partials, {len(fulls)} FAUST models; screen built in {time.perf_counter() - t:.1f} s")
    options = dict(scale="auto", threads=2)

    t = time.perf_counter()
    reference = [ds.search(p, fulls, shortlist=10, screen=screen, **options) for p in partials]
    runs = [("search", time.perf_counter() - t, True)]
    keep = batch._PREPARED_PARTIALS
    for label, kept in (("batch, each task afresh", 0), ("batch", keep)):
        batch._PREPARED_PARTIALS = kept
        t = time.perf_counter()
        got = batch.search_batch(partials, fulls, shortlist=10, screen=screen, **options)
        seconds = time.perf_counter() - t
        same = all(
            [(m.index, m.score) for m in r] == [(m.index, m.score) for m in ref] for r, ref in zip(got, reference)
        )
        runs.append((label, seconds, same))
    batch._PREPARED_PARTIALS = keep
    print("| run | seconds | per partial | x `search` | rankings as `search`'s |")
    print("|---|---:|---:|---:|---|")
    for label, seconds, same in runs:
        print(f"| {label} | {seconds:.1f} | {seconds / len(partials):.2f} | {seconds / runs[0][1]:.2f} | {'yes' if same else 'NO'} |")
    return 0 if all(same for *_, same in runs) else 1


if __name__ == "__main__":
    sys.exit(main())
