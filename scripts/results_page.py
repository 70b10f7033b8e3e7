#!/usr/bin/env python3
"""Writes docs/benchmarks/results.md from the JSON of `dualspectra bench --all` (stdlib only).

    python3 scripts/results_page.py ALL.json OUT.md --commit SHA [--args "extra bench args"]

`scripts/results.sh` runs the benchmark and then this script; the plots the page shows are
the `--svg` files `bench --all` wrote beside it (results/cumulative-<set>.svg).
"""
from __future__ import annotations

import argparse
import datetime
import json
import os
import platform
import statistics

STAGES = ["preparation", "preprocessing", "starts", "optimisation", "region", "selection", "total"]
SET_NAMES = {
    "shrec16": "SHREC'16 CUTS (plane cuts)",
    "shrec16_holes": "SHREC'16 HOLES (many holes)",
    "pfarm": "PFARM (scans of other people against a template)",
    "pfaust_m": "PFAUST-M (people with 4 holes, other pose)",
    "pfaust_h": "PFAUST-H (people with 13 holes, other pose)",
}


def fmt(x: float, digits: int = 3) -> str:
    return f"{x:.{digits}f}"


def mean_confidence(pairs: list[dict]) -> float:
    """Mean confidence over the pairs (a failed pair counts 0, as its scores do)."""
    return statistics.mean(p.get("confidence", 0.0) for p in pairs) if pairs else 0.0


def mean_of_sets(sets: list[dict]) -> dict:
    """The JSON's `mean_of_sets`, or the same means computed from the sets (older JSON)."""
    summ = [s["summary"] for s in sets]

    def mean(get):
        return statistics.mean(get(x) for x in summ)

    return {
        "pairs": sum(x["pairs"] for x in summ),
        "failed": sum(x["failed"] for x in summ),
        "mean": {k: mean(lambda x: x["mean"][k]) for k in ("precision", "recall", "iou")},
        "mean_sym": {k: mean(lambda x: x["mean_sym"][k]) for k in ("precision", "recall", "iou")},
        "mean_area_iou": mean(lambda x: x["mean_area_iou"]),
        "median_seconds": mean(lambda x: x["median_seconds"]),
        "total_seconds": sum(x["total_seconds"] for x in summ),
    }


def row(name: str, summ: dict, conf: float | None) -> str:
    cells = [
        name,
        str(summ["pairs"]),
        fmt(summ["mean"]["iou"]),
        fmt(summ["mean_sym"]["iou"]),
        fmt(summ["mean_area_iou"]),
        fmt(summ["mean_sym"]["precision"]),
        fmt(summ["mean_sym"]["recall"]),
        "" if conf is None else fmt(conf),
        fmt(summ["median_seconds"], 2),
        fmt(summ["total_seconds"], 0),
        str(summ["failed"]),
    ]
    return "| " + " | ".join(cells) + " |"


def set_rows(report: dict) -> list[str]:
    rows = [row(SET_NAMES.get(s["set"], s["set"]), s["summary"], mean_confidence(s["pairs"])) for s in report["sets"]]
    overall = report.get("mean_of_sets") or mean_of_sets(report["sets"])
    conf = statistics.mean(mean_confidence(s["pairs"]) for s in report["sets"])
    rows.append(row("mean of sets", overall, conf))
    return rows


def stage_rows(report: dict) -> list[str]:
    present = [k for k in STAGES if all(k in s["summary"]["median_stage_seconds"] for s in report["sets"])]
    rows = ["| set | " + " | ".join(present) + " |", "|---|" + "---:|" * len(present)]
    for s in report["sets"]:
        med = s["summary"]["median_stage_seconds"]
        rows.append(f"| {s['set']} | " + " | ".join(fmt(med[k], 2) for k in present) + " |")
    return rows


def failures(report: dict) -> list[str]:
    return [
        f"- {s['set']} `{p['name']}`: {p['error']}"
        for s in report["sets"]
        for p in s["pairs"]
        if p.get("error")
    ]


def options_line(report: dict) -> str:
    opts = report.get("options")
    if not opts:
        return "the default options"
    return "options " + ", ".join(f"`{k}` {v}" for k, v in opts.items())


def page(report: dict, commit: str, args: str, date: str, machine: str, note: str = "") -> str:
    command = "bash scripts/results.sh" + (f" {args}" if args else "")
    lines = [
        "# Results",
        "",
        f"Made on {date} at commit `{commit}` on {machine}" + ("" if note else f" by `{command}`"),
        f"(`dualspectra bench --all` on every dev set under the data root, {options_line(report)}).",
        *(["", note] if note else []),
        "",
        "Scores are means over the pairs of vertex counts against the ground truth: IoU direct,",
        "symmetry-aware (the better of the direct and the left-right mirrored truth, as SHREC'16",
        "counts symmetric matches as correct) and area-weighted; precision and recall are",
        "symmetry-aware. Confidence is the localizer's estimate that IoU >= 0.5. Seconds are",
        "wall-clock per pair (median) and for the whole set (total), the full shape prepared once",
        "for all its partials. A failed pair counts with scores 0.",
        "",
        "| set | pairs | IoU | IoU (sym) | IoU (area) | precision | recall | confidence | median s | total s | failed |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
        *set_rows(report),
        "",
        "## Time per stage",
        "",
        "Median seconds per pair of each stage of the localizer.",
        "",
        *stage_rows(report),
        "",
        "## Cumulative IoU",
        "",
        "Fraction of a set's pairs whose region reaches at least a given IoU, direct and",
        "symmetry-aware (the area under a curve is its mean IoU).",
        "",
    ]
    for s in report["sets"]:
        lines += [f"![{s['set']}: cumulative IoU](results/cumulative-{s['set']}.svg)", ""]
    fail = failures(report)
    lines += ["## Failed pairs", "", *(fail or ["None."]), ""]
    lines += [
        "## Regenerate",
        "",
        "```sh",
        "bash scripts/results.sh              # every pair of every set (about 8 minutes on 2 cores)",
        "bash scripts/results.sh --limit 1    # any extra `bench` argument, e.g. a quick smoke run",
        "```",
        "",
        "It builds the CLI in release mode, runs `bench --all` on `$DUALSPECTRA_DATA` (default",
        "`../shared/datasets` beside the clone), writes the plots to `docs/benchmarks/results/`",
        "and this page from the JSON (kept in `target/results/all.json`) with",
        "`scripts/results_page.py`. Why each option and default: [options.md](options.md).",
        "",
    ]
    return "\n".join(lines)


def machine() -> str:
    cores = os.cpu_count() or 0
    model = ""
    try:
        with open("/proc/cpuinfo") as f:
            model = next((ln.split(":", 1)[1].strip() for ln in f if ln.startswith("model name")), "")
    except OSError:
        model = platform.processor()
    return f"{cores} cores" + (f" ({model})" if model else "")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("json", help="the JSON of `dualspectra bench --all ... --json`")
    ap.add_argument("out", help="the page to write (docs/benchmarks/results.md)")
    ap.add_argument("--commit", required=True, help="the commit the numbers were made at")
    ap.add_argument("--args", default="", help="extra arguments given to scripts/results.sh")
    ap.add_argument("--date", default=datetime.date.today().isoformat())
    ap.add_argument("--machine", default=None, help="default: this machine's cores and CPU model")
    ap.add_argument("--note", default="", help="a paragraph on where the numbers come from, if not from this run")
    a = ap.parse_args()
    with open(a.json) as f:
        report = json.load(f)
    text = page(report, a.commit, a.args.strip(), a.date, a.machine or machine(), a.note.strip())
    with open(a.out, "w") as f:
        f.write(text)


if __name__ == "__main__":
    main()
