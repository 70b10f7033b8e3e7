"""Time `dualspectra.batch.search_batch` on SHREC'16 CUTS partials against the 8 full shapes:
in this process (one process, the core's 2 threads) against a 2-worker Dask ``LocalCluster``
(2 processes, 1 thread each), in the same run, and check that both rank alike.

    python docs/benchmarks/batch_timing.py $DUALSPECTRA_DATA/shrec16 [STRIDE] [OUT.json] [both|here|cluster]

STRIDE takes every STRIDE-th CUTS partial (sorted by name; default 1: all 80); the last
argument runs only one of the two (default both). Prints the
wall time of each run, their ratio, top-1 accuracy and mean reciprocal rank of the ranking
(the true full shape is the partial's class), and whether the two runs gave identical
scores and regions. Figures go to docs/benchmarks/search-*.md.
"""

from __future__ import annotations

import json
import os
import sys
import time
from pathlib import Path
from typing import Any, Dict, List

import numpy as np

import dualspectra as ds
from dualspectra.batch import BatchMatch, search_batch


def _progress(label: str) -> Any:
    last = [-1]

    def report(fraction: float, stage: str) -> bool:
        percent = int(100 * fraction)
        if percent // 10 != last[0] // 10:
            last[0] = percent
            print(f"  {label}: {percent:3d}% {stage}", file=sys.stderr, flush=True)
        return True

    return report


def _ranks(rankings: List[List[BatchMatch]], truths: List[int]) -> List[int]:
    return [1 + [m.index for m in ranking].index(truth) for ranking, truth in zip(rankings, truths)]


def main() -> None:
    root = Path(sys.argv[1])
    stride = int(sys.argv[2]) if len(sys.argv) > 2 else 1
    out = Path(sys.argv[3]) if len(sys.argv) > 3 and sys.argv[3] != "-" else None
    which = sys.argv[4] if len(sys.argv) > 4 else "both"
    full_paths = sorted((root / "null").glob("*.off"))
    classes = [p.stem for p in full_paths]
    partial_paths = sorted((root / "cuts").glob("cuts_*_shape_*.off"))[::stride]
    partials = [ds.read_mesh(str(p)) for p in partial_paths]
    fulls = [ds.read_mesh(str(p)) for p in full_paths]
    truths = [classes.index(p.stem.split("_")[1]) for p in partial_paths]
    print(f"{len(partials)} partials x {len(fulls)} full shapes; load {os.getloadavg()[0]:.2f}")

    runs: Dict[str, Any] = {}
    if which in ("both", "here"):
        start = time.perf_counter()
        here = search_batch(partials, fulls, threads=2, progress=_progress("here"))
        runs["here (1 process, 2 threads)"] = (time.perf_counter() - start, here)
    if which in ("both", "cluster"):
        from distributed import Client, LocalCluster

        with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
            with Client(cluster) as client:
                start = time.perf_counter()
                spread = search_batch(partials, fulls, threads=1, client=client, progress=_progress("cluster"))
                runs["LocalCluster (2 workers x 1 thread)"] = (time.perf_counter() - start, spread)
    results = [r for _, r in runs.values()]
    identical = len(results) == 2 and all(
        a.index == b.index and a.score == b.score and np.array_equal(a.region, b.region)
        for ra, rb in zip(*results)
        for a, b in zip(ra, rb)
    )
    base = next(iter(runs.values()))[0]
    summary = {"partials": len(partials), "fulls": len(fulls), "identical": identical, "runs": {}}
    for name, (seconds, rankings) in runs.items():
        ranks = _ranks(rankings, truths)
        top1 = sum(r == 1 for r in ranks) / len(ranks)
        mrr = float(np.mean([1 / r for r in ranks]))
        print(f"{name}: {seconds:.1f} s ({seconds / base:.2f}x), top-1 {top1:.3f}, MRR {mrr:.3f}")
        summary["runs"][name] = {"seconds": seconds, "top1": top1, "mrr": mrr, "ranks": ranks}
    print(f"identical scores and regions: {identical}; load {os.getloadavg()[0]:.2f}")
    if out is not None:
        out.write_text(json.dumps(summary, indent=1))


if __name__ == "__main__":
    main()
