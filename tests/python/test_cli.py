"""The CLI's ``dualspectra spectrum MESH --k 20 --json OUT`` against scipy on libigl's matrices.

The binary is ``$DUALSPECTRA_CLI``, else ``target/{debug,release}/dualspectra`` (skip with a
message if none is built). Tolerance 1e-6 relative, as in test_spectrum (same solver; the
JSON carries shortest round-trip floats, so no precision is lost on the way).
"""

from __future__ import annotations

import json
import os
import subprocess
from pathlib import Path

import pytest
from conftest import Mesh, igl_dirichlet_eigenvalues, load, real_mesh_path, rel_err_eigenvalues, report

pytest.importorskip("igl")
ROOT = Path(__file__).resolve().parents[2]


def cli() -> Path:
    candidates = [os.environ.get("DUALSPECTRA_CLI", "")] + [str(ROOT / "target" / p / "dualspectra") for p in ("debug", "release")]
    found = [Path(c) for c in candidates if c and Path(c).is_file()]
    if not found:
        pytest.skip("dualspectra CLI not built (cargo build -p dualspectra-cli, or set DUALSPECTRA_CLI)")
    return max(found, key=lambda p: p.stat().st_mtime)


@pytest.mark.parametrize("name", ["cat", "horse"])
def test_cli_spectrum_json_matches_scipy(name: str, tmp_path: Path) -> None:
    path = real_mesh_path(name)
    out = tmp_path / "spectrum.json"
    proc = subprocess.run([str(cli()), "spectrum", str(path), "--k", "20", "--json", str(out)], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    ours = json.loads(out.read_text())["eigenvalues"]
    assert len(ours) == 20
    m: Mesh = load(name)  # the same arrays the CLI reads (flaps removed)
    ref = igl_dirichlet_eigenvalues(m, 20)
    import numpy as np

    err = rel_err_eigenvalues(np.asarray(ours), ref)
    report(f"cli spectrum {name}", max_rel=err)
    assert err <= 1e-6


def test_cli_reports_missing_file(tmp_path: Path) -> None:
    proc = subprocess.run([str(cli()), "spectrum", str(tmp_path / "nope.off"), "--k", "5"], capture_output=True, text=True, timeout=60)
    assert proc.returncode != 0 and "nope.off" in proc.stderr
