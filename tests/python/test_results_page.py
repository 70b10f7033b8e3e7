"""scripts/results_page.py, which writes docs/benchmarks/results.md from `bench --all` JSON:
every set gets a row whose figures are the JSON's, the mean of sets is the mean of the set
rows (computed when an older JSON lacks it), failures are listed, and every set's plot is
linked. Stdlib and a generated report only: no benchmark is run."""

from __future__ import annotations

import importlib.util
import json
import random
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "scripts" / "results_page.py"


def load_script():
    spec = importlib.util.spec_from_file_location("results_page", SCRIPT)
    assert spec and spec.loader
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def scores(rng: random.Random) -> dict:
    return {"precision": rng.random(), "recall": rng.random(), "iou": rng.random()}


def fake_set(rng: random.Random, name: str, n: int, failed: int) -> dict:
    pairs = [
        {
            "name": f"{name}_{i}",
            "confidence": 0.0 if i < failed else rng.random(),
            "error": "invalid mesh: no faces" if i < failed else None,
        }
        for i in range(n)
    ]
    stages = ["preparation", "preprocessing", "starts", "optimisation", "region", "selection", "total"]
    return {
        "set": name,
        "dataset": f"/data/{name}",
        "summary": {
            "pairs": n,
            "failed": failed,
            "mean": scores(rng),
            "mean_sym": scores(rng),
            "mean_area_iou": rng.random(),
            "median_seconds": 10 * rng.random(),
            "total_seconds": 100 * rng.random(),
            "median_stage_seconds": {k: rng.random() for k in stages},
        },
        "pairs": pairs,
    }


def table_rows(text: str) -> dict[str, list[str]]:
    """The first table's rows by their first cell."""
    rows = {}
    for line in text.splitlines():
        if line.startswith("| ") and not line.startswith("| set "):
            cells = [c.strip() for c in line.strip("|").split("|")]
            rows.setdefault(cells[0], cells)
        elif rows and not line.startswith("|"):
            break
    return rows


def test_rows_carry_the_json_figures_and_the_mean_of_sets_is_their_mean() -> None:
    rp = load_script()
    rng = random.Random(7)
    sets = [fake_set(rng, name, n, f) for name, n, f in [("shrec16", 5, 1), ("pfarm", 3, 0), ("other_set", 4, 0)]]
    text = rp.page({"sets": sets}, "abc1234", "", "2030-01-01", "2 cores")
    rows = table_rows(text)
    assert "abc1234" in text and "2030-01-01" in text and "2 cores" in text
    ious = []
    for s in sets:
        label = rp.SET_NAMES.get(s["set"], s["set"])
        cells = rows[label]
        summ = s["summary"]
        assert cells[1] == str(summ["pairs"]) and cells[-1] == str(summ["failed"])
        assert float(cells[2]) == round(summ["mean"]["iou"], 3)
        assert float(cells[3]) == round(summ["mean_sym"]["iou"], 3)
        ran = [p["confidence"] for p in s["pairs"]]
        assert abs(float(cells[7]) - sum(ran) / len(ran)) <= 5e-4
        ious.append(summ["mean_sym"]["iou"])
        assert f"results/cumulative-{s['set']}.svg" in text
    mean = rows["mean of sets"]
    assert abs(float(mean[3]) - sum(ious) / len(ious)) <= 5e-4
    assert mean[1] == str(sum(s["summary"]["pairs"] for s in sets))
    # the failed pair is named with its error
    assert "`shrec16_0`: invalid mesh: no faces" in text


def test_the_command_line_writes_the_page(tmp_path: Path) -> None:
    rng = random.Random(3)
    report = {"sets": [fake_set(rng, "shrec16", 2, 0)], "options": {"k": 20}}
    src, out = tmp_path / "all.json", tmp_path / "results.md"
    src.write_text(json.dumps(report))
    subprocess.run([sys.executable, str(SCRIPT), str(src), str(out), "--commit", "f00d", "--args", "--limit 1"], check=True)
    text = out.read_text()
    assert text.startswith("# Results") and "f00d" in text and "`bash scripts/results.sh --limit 1`" in text
    assert "`k` 20" in text and "None." in text
