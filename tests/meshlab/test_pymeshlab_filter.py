"""The MeshLab 2025.07 filter plugin, headless in PyMeshLab 2025.7 (pytest).

    DUALSPECTRA_PYMESHLAB_PLUGIN=<build>/plugins/libfilter_dualspectra.so \\
    DUALSPECTRA_FFI_LIB=target/debug/deps/libdualspectra_ffi.so \\
        .venv/bin/python -m pytest tests/meshlab/test_pymeshlab_filter.py

The plugin is the `double` build (PyMeshLab's libmeshlab-common.so uses double scalars and
refuses a plugin built otherwise), loaded with `pymeshlab.load_plugin`; the meshes are the
generated pair of make_pair.py (a bumpy icosphere and plane cuts of it, moved rigidly, with the
known region). The filter's parameters are checked against the library's option table, read
with ctypes from the dualspectra-ffi shared library the plugin was linked from
(DUALSPECTRA_FFI_LIB). DUALSPECTRA_MESHLAB_LEVEL (3) and DUALSPECTRA_MESHLAB_K (10) size the
localizations, DUALSPECTRA_MESHLAB_MIN_IOU (0.7) is the IoU the region must reach. The Python
example of meshlab_filter/README.md is run as written there, in a directory holding the pair
and the plugin under the README's path; so is the ranking example (`dualspectra_search`), on a
library of three models in which full.off must win.
"""

from __future__ import annotations

import ctypes
import json
import os
import re
import subprocess
import sys
from pathlib import Path
from typing import Any, Dict, Iterator, List

import numpy as np
import pytest

pymeshlab = pytest.importorskip("pymeshlab")

HERE = Path(__file__).resolve().parent
README = HERE.parent.parent / "meshlab_filter" / "README.md"
FILTER = "dualspectra_localize"
SEARCH = "dualspectra_search"
LEVEL = int(os.environ.get("DUALSPECTRA_MESHLAB_LEVEL", "3"))
K = int(os.environ.get("DUALSPECTRA_MESHLAB_K", "10"))
MIN_IOU = float(os.environ.get("DUALSPECTRA_MESHLAB_MIN_IOU", "0.7"))


def _required_path(variable: str) -> Path:
    value = os.environ.get(variable)
    if not value or not Path(value).is_file():
        pytest.fail(f"{variable}={value!r} is not a file (see this module's docstring)")
    return Path(value)


@pytest.fixture(scope="session")
def plugin() -> Path:
    """The plugin, loaded into PyMeshLab once (before any MeshSet is made)."""
    path = _required_path("DUALSPECTRA_PYMESHLAB_PLUGIN")
    pymeshlab.load_plugin(str(path))
    return path


@pytest.fixture(scope="session")
def schema() -> List[Dict[str, Any]]:
    """The library's option table (`ds_options_schema_json`)."""
    lib = ctypes.CDLL(str(_required_path("DUALSPECTRA_FFI_LIB")))
    lib.ds_options_schema_json.restype = ctypes.c_char_p
    return json.loads(lib.ds_options_schema_json().decode("utf-8"))


@pytest.fixture(scope="session")
def pair(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """make_pair.py's meshes and known regions."""
    out = tmp_path_factory.mktemp("pair")
    subprocess.run([sys.executable, str(HERE / "make_pair.py"), "--out", str(out), "--level", str(LEVEL)], check=True)
    return out


def expected(pair: Path, name: str) -> set:
    return {int(line) for line in (pair / name).read_text().split()}


def meshset(plugin: Path, pair: Path, *names: str) -> Any:
    """A MeshSet holding the named meshes of the pair, as layers 0, 1, ..."""
    ms = pymeshlab.MeshSet()
    for name in names:
        ms.load_new_mesh(str(pair / name))
    return ms


def iou(selected: set, truth: set) -> float:
    return len(selected & truth) / max(1, len(selected | truth))


def test_filter_is_listed_with_the_library_options(plugin: Path, pair: Path, schema: List[Dict[str, Any]]) -> None:
    assert FILTER in pymeshlab.filter_list()
    values = meshset(plugin, pair, "full.off", "partial.off").filter_parameter_values(FILTER)
    names = ["full_mesh", "partial_mesh"] + [s["name"] for s in schema] + ["write_score"]
    assert list(values) == names
    for s in schema:
        default = s["choices"].index(s["default"]) if s["type"] == "choice" else s["default"]
        if s["type"] == "float":
            assert values[s["name"]] == pytest.approx(default, rel=1e-6), s["name"]
        elif s["type"] == "int":
            assert values[s["name"]] == min(default, 2**31 - 1), s["name"]
        else:
            assert values[s["name"]] == default, s["name"]
    # the current layer (the last loaded) is the default full mesh, the other one the partial
    assert (values["full_mesh"], values["partial_mesh"], values["write_score"]) == (1, 0, False)


@pytest.fixture(scope="module")
def region_run(plugin: Path, pair: Path) -> Iterator[Dict[str, Any]]:
    """Two parts located on one full layer (with a loose vertex and a zero-area face the
    library's intake leaves out): partial2, which prepares the full shape, then partial, which
    reuses it and writes the score."""
    ms = meshset(plugin, pair, "full_debris.off", "partial.off", "partial2.off")
    first = ms.apply_filter(FILTER, full_mesh=0, partial_mesh=2, k=K)
    second = ms.apply_filter(FILTER, full_mesh=0, partial_mesh=1, k=K, write_score=True)
    full = ms.mesh(0)
    yield {
        "first": first,
        "second": second,
        "vertices": full.vertex_selection_array().copy(),
        "faces": full.face_selection_array().copy(),
        "face_matrix": full.face_matrix().copy(),
        "quality": full.vertex_scalar_array().copy(),
        "n": full.vertex_number(),
    }


def test_region_is_the_selection_of_the_full_layer(region_run: Dict[str, Any], pair: Path) -> None:
    truth = expected(pair, "expected_region.txt")
    n_full = 10 * 4**LEVEL + 2
    assert region_run["n"] == n_full + 4  # the layer is not renumbered or compacted
    selected = set(np.flatnonzero(region_run["vertices"]).tolist())
    assert not selected & set(range(n_full, n_full + 4)), "a loose or degenerate vertex is selected"
    score = iou(selected, truth)
    print(f"PyMeshLab region IoU {score:.3f} ({len(selected)} selected, {len(truth)} expected)")
    assert score >= MIN_IOU
    assert region_run["second"]["selected_vertices"] == len(selected)
    # faces: exactly those whose three vertices are selected
    inside = region_run["vertices"][region_run["face_matrix"]].all(axis=1)
    assert np.array_equal(region_run["faces"], inside)
    assert region_run["second"]["selected_faces"] == int(inside.sum())


def test_result_numbers_are_returned(region_run: Dict[str, Any]) -> None:
    first, second = region_run["first"], region_run["second"]
    for out in (first, second):
        assert set(out) == {"selected_vertices", "selected_faces", "confidence", "cost", "optimisation_vertices",
                            "seconds", "reused", "warnings"}
        assert 0.0 <= out["confidence"] <= 1.0
        assert out["seconds"] > 0.0
    # the same partial on the same prepared shape: optimised on the same mesh both times
    assert first["optimisation_vertices"] == second["optimisation_vertices"] > 0
    # one preparation of the full shape, then a reuse; the intake's note on the debris
    assert (first["reused"], second["reused"]) == (False, True)
    assert first["warnings"] >= 1


def test_score_is_vertex_quality(region_run: Dict[str, Any], pair: Path) -> None:
    q = region_run["quality"]
    truth = sorted(expected(pair, "expected_region.txt"))
    n_full = 10 * 4**LEVEL + 2
    assert np.all((q >= 0.0) & (q <= 1.0))
    outside = np.setdiff1d(np.arange(n_full), truth)
    assert q[truth].mean() > q[outside].mean()


def failure(plugin: Path, pair: Path, names: List[str], **params: Any) -> str:
    """The message of the PyMeshLab exception the filter raises; the full layer (0) is left
    without a selection."""
    ms = meshset(plugin, pair, *names)
    with pytest.raises(pymeshlab.PyMeshLabException) as raised:
        ms.apply_filter(FILTER, **params)
    assert not ms.mesh(0).vertex_selection_array().any()
    return str(raised.value)


def test_same_layer_twice_is_refused(plugin: Path, pair: Path) -> None:
    message = failure(plugin, pair, ["full.off", "partial.off"], full_mesh=0, partial_mesh=0)
    assert "Localize partial shape: the full and the partial layer are the same layer ('full.off')" in message


def test_point_cloud_is_refused(plugin: Path, pair: Path) -> None:
    message = failure(plugin, pair, ["full.off", "points.off"], full_mesh=0, partial_mesh=1)
    assert "the partial layer 'points.off' has no faces (a point cloud?)" in message


def test_closed_partial_is_refused_with_the_library_message(plugin: Path, pair: Path) -> None:
    message = failure(plugin, pair, ["full.off", "closed.off"], full_mesh=0, partial_mesh=1, k=K)
    assert "localization failed" in message and "the partial shape has no boundary" in message


def test_option_out_of_range_is_refused_with_the_library_message(plugin: Path, pair: Path) -> None:
    message = failure(plugin, pair, ["full.off", "partial.off"], full_mesh=0, partial_mesh=1, k=0)
    assert "k = 0 must be an integer in 1..=500" in message


def test_missing_layer_is_refused(plugin: Path, pair: Path) -> None:
    message = failure(plugin, pair, ["full.off", "partial.off"], full_mesh=0, partial_mesh=7)
    assert "partial_mesh: there is no layer with id 7" in message


def test_search_filter_is_listed_with_the_library_options(plugin: Path, pair: Path, schema: List[Dict[str, Any]]) -> None:
    assert SEARCH in pymeshlab.filter_list()
    values = meshset(plugin, pair, "full.off", "partial.off").filter_parameter_values(SEARCH)
    assert list(values) == ["partial_mesh"] + [s["name"] for s in schema]
    assert values["partial_mesh"] == 1  # the current layer (the last loaded)


def test_search_ranks_visible_mesh_layers_only(plugin: Path, pair: Path) -> None:
    """A hidden layer and a point cloud are not ranked: with only those besides the partial,
    there is nothing to rank (refused before any computation)."""
    ms = meshset(plugin, pair, "full.off", "points.off", "partial.off")
    ms.set_mesh_visibility(0, False)
    with pytest.raises(pymeshlab.PyMeshLabException) as raised:
        ms.apply_filter(SEARCH, partial_mesh=2)
    assert "Rank layers: no visible mesh layer besides the partial layer 'partial.off'" in str(raised.value)
    with pytest.raises(pymeshlab.PyMeshLabException) as raised:
        ms.apply_filter(SEARCH, partial_mesh=1)
    assert "Rank layers: the partial layer 'points.off' has no faces" in str(raised.value)
    assert not any(ms.mesh(i).vertex_selection_array().any() for i in range(3))


def run_readme_example(plugin: Path, pair: Path, tmp_path: Path, filter_name: str, files: Dict[str, str],
                       then: str = "") -> str:
    """Run the README's Python example that applies `filter_name`, as written (then `then`), in
    `tmp_path` holding the plugin under the example's path and the pair's meshes under the
    example's names (`files`: example name -> pair name); its standard output."""
    blocks = [b for b in re.findall(r"```python\n(.*?)```", README.read_text(), re.S) if filter_name in b]
    assert len(blocks) == 1, f"{README}: expected one Python example applying {filter_name}"
    example = blocks[0]
    where = re.search(r'load_plugin\("([^"]+)"\)', example)
    assert where, "the example loads the plugin from a literal path"
    (tmp_path / where.group(1)).parent.mkdir(parents=True)
    (tmp_path / where.group(1)).symlink_to(plugin.resolve())
    for name, source in files.items():
        (tmp_path / name).write_bytes((pair / source).read_bytes())
    run = subprocess.run([sys.executable, "-c", example + then], cwd=tmp_path, capture_output=True, text=True, timeout=900)
    assert run.returncode == 0, run.stdout + run.stderr
    return run.stdout


def test_readme_search_example_ranks_the_model_the_part_was_cut_from_first(plugin: Path, pair: Path, tmp_path: Path) -> None:
    """The README's ranking example on a library of three models: cat (an ellipsoid), dog
    (other bumps) and wolf (full.off, the model the part was cut from); then the returned
    numbers, printed as JSON."""
    files = {"cat.off": "other_ellipsoid.off", "dog.off": "other_bumps.off", "wolf.off": "full.off", "part.off": "partial.off"}
    out = run_readme_example(plugin, pair, tmp_path, SEARCH, files, then="\nimport json\nprint(json.dumps(ranked))\n")
    print(out)
    said = re.search(r"^best: wolf\.off, score ([0-9.]+), confidence ([0-9.]+)$", out, re.M)
    assert said, out
    count = re.search(r"^(\d+) vertices selected$", out, re.M)
    assert count, out
    ranked = json.loads(out.strip().splitlines()[-1])
    assert set(ranked) == {"best_layer", "score", "confidence", "selected_vertices", "selected_faces", "ranked", "prepared", "seconds"}
    assert (ranked["best_layer"], ranked["ranked"], ranked["prepared"]) == (2, 3, 3)
    assert ranked["score"] >= 0.0 and 0.0 <= ranked["confidence"] <= 1.0
    assert ranked["selected_vertices"] == int(count.group(1))
    truth = expected(pair, "expected_region.txt")
    assert 0.5 * len(truth) <= ranked["selected_vertices"] <= 1.5 * len(truth)


def test_readme_example_runs_as_written(plugin: Path, pair: Path, tmp_path: Path) -> None:
    out = run_readme_example(plugin, pair, tmp_path, FILTER, {"full.off": "full.off", "partial.off": "partial.off"})
    said = re.search(r"^(\d+) vertices selected; confidence ([0-9.]+)$", out, re.M)
    assert said, out
    truth = expected(pair, "expected_region.txt")
    assert 0.5 * len(truth) <= int(said.group(1)) <= 1.5 * len(truth)
    assert 0.0 <= float(said.group(2)) <= 1.0
