"""End-to-end test of the MeshLab filter plugin in the real meshlabserver (stdlib only).

    python3 tests/meshlab/test_meshlab_filter.py --plugin build/plugins/libfilter_dualspectra.so

meshlabserver loads plugins from `<prefix>/lib/<arch>/meshlab/plugins` next to its own binary
(`<prefix>/bin/meshlabserver`, found through /proc/self/exe, so the binary is copied, not
symlinked), and needs a display: each run is `xvfb-run -a`. The system is left untouched: a
private prefix in a temporary directory holds a copy of meshlabserver, links to the system
libmeshlab-common.so and plugins, and a link to the plugin under test.

Cases (each one meshlabserver run with a .mlx script calling the filter):
  region       full + a plane cut of it (moved rigidly): the selection saved with `-m vf vq sa`
               (selected vertices carry flag bit 0x20) must have IoU >= --min-iou with the
               known region; the score written to vertex quality must be in [0, 1] and higher
               on average inside the known region than outside; the log has the result line.
  same-layer   the full layer picked twice: a clear message in the log, no crash.
  point-cloud  a partial layer without faces: a clear message in the log, no crash.
  bad-k        k = 0: a clear message in the log, no crash.
  bad-mesh     a non-manifold partial layer, rejected by the library (DS_INVALID_MESH): its
               message reaches the log, no crash.
"""

import argparse
import glob
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from read_selection import read_selected  # noqa: E402

FILTER = "Localize partial shape (dual spectra)"
MODES = ["dual", "lbo", "si"]


def mlx(full, partial, mode=0, k=20, alpha=0.33, seed=0, spectral_cuts=0, plane_cuts=6, write_score=False):
    """A filter script with every parameter, in initParameterSet order (meshlabserver 2020.09
    matches the script's parameters to the filter's by position and asserts on the count)."""
    enum_vals = " ".join('enum_val%d="%s"' % (i, m) for i, m in enumerate(MODES))
    return "\n".join([
        "<!DOCTYPE FilterScript>",
        "<FilterScript>",
        ' <filter name="%s">' % FILTER,
        '  <Param type="RichMesh" value="%d" name="FullMesh"/>' % full,
        '  <Param type="RichMesh" value="%d" name="PartialMesh"/>' % partial,
        '  <Param type="RichEnum" value="%d" name="Mode" enum_cardinality="%d" %s/>' % (mode, len(MODES), enum_vals),
        '  <Param type="RichInt" value="%d" name="K"/>' % k,
        '  <Param type="RichFloat" value="%g" name="Alpha"/>' % alpha,
        '  <Param type="RichInt" value="%d" name="Seed"/>' % seed,
        '  <Param type="RichInt" value="%d" name="SpectralCuts"/>' % spectral_cuts,
        '  <Param type="RichInt" value="%d" name="PlaneCuts"/>' % plane_cuts,
        '  <Param type="RichBool" value="%s" name="WriteScore"/>' % ("true" if write_score else "false"),
        " </filter>",
        "</FilterScript>",
        "",
    ])


def make_prefix(root, plugin, meshlabserver, system_lib_dir):
    """Private install prefix: bin/meshlabserver (copy) + lib/<arch>/meshlab/{libmeshlab-common.so,
    plugins/*} (links to the system files and to the plugin under test)."""
    arch_lib = os.path.relpath(system_lib_dir, "/usr")  # e.g. lib/x86_64-linux-gnu/meshlab
    bin_dir = os.path.join(root, "bin")
    lib_dir = os.path.join(root, arch_lib)
    plugin_dir = os.path.join(lib_dir, "plugins")
    os.makedirs(bin_dir)
    os.makedirs(plugin_dir)
    server = os.path.join(bin_dir, "meshlabserver")
    shutil.copy2(meshlabserver, server)
    for lib in glob.glob(os.path.join(system_lib_dir, "*.so*")):
        os.symlink(lib, os.path.join(lib_dir, os.path.basename(lib)))
    for p in glob.glob(os.path.join(system_lib_dir, "plugins", "*.so")):
        if os.path.basename(p) != os.path.basename(plugin):
            os.symlink(p, os.path.join(plugin_dir, os.path.basename(p)))
    os.symlink(os.path.abspath(plugin), os.path.join(plugin_dir, os.path.basename(plugin)))
    return server, plugin_dir


def run_server(server, work, name, meshes, script_text, save_mask=None, timeout=120):
    """Run meshlabserver on `meshes` with the script; return (exit status, log text, output path)."""
    script = os.path.join(work, name + ".mlx")
    with open(script, "w") as f:
        f.write(script_text)
    log_path = os.path.join(work, name + ".log")
    # unbuffered stdout: meshlabserver prints the progress text without newlines
    cmd = ["xvfb-run", "-a"] + (["stdbuf", "-o0"] if shutil.which("stdbuf") else []) + [server]
    for m in meshes:
        cmd += ["-i", m]
    cmd += ["-s", script, "-l", log_path]
    out = None
    if save_mask is not None:
        out = os.path.join(work, name + ".ply")
        cmd += ["-o", out, "-m"] + save_mask
    start = time.time()
    # own process group: on timeout, kill meshlabserver and Xvfb too, not only xvfb-run
    proc = subprocess.Popen(cmd, cwd=work, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, start_new_session=True)
    try:
        stdout, _ = proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        stdout, _ = proc.communicate()
        stdout += b"\nTIMEOUT: meshlabserver killed after %d s\n" % timeout
    text = stdout.decode("utf-8", errors="replace").replace("\r", "\n")
    text = text.replace("Localize partial shape: ", "\nLocalize partial shape: ")
    if os.path.exists(log_path):
        with open(log_path, encoding="utf-8", errors="replace") as f:
            text += "\n" + f.read()
    print("  [%s] meshlabserver exit %d after %.1f s" % (name, proc.returncode, time.time() - start))
    return proc.returncode, text, out


def read_quality(path):
    """Per-vertex `quality` of an ascii PLY, or None if absent."""
    with open(path, encoding="ascii", errors="replace") as f:
        lines = iter(f.read().splitlines())
    props, n, element = [], 0, None
    for line in lines:
        w = line.split()
        if w and w[0] == "element":
            element = w[1]
            if element == "vertex":
                n = int(w[2])
        elif w and w[0] == "property" and element == "vertex":
            props.append(w[-1])
        elif w and w[0] == "end_header":
            break
    if "quality" not in props:
        return None
    col = props.index("quality")
    return [float(next(lines).split()[col]) for _ in range(n)]


class Checks:
    def __init__(self):
        self.failures = []

    def check(self, case, ok, message):
        print("  %s %s: %s" % ("ok  " if ok else "FAIL", case, message))
        if not ok:
            self.failures.append("%s: %s" % (case, message))


def no_crash(checks, case, status, text):
    crashed = status < 0 or 128 < status < 255 or "Aborted" in text or "Segmentation" in text
    checks.check(case, not crashed, "meshlabserver ended normally (exit %d)" % status)


def log_excerpt(text, needle):
    lines = [l.strip() for l in text.splitlines() if needle.lower() in l.lower()]
    return lines[0] if lines else "(no line with '%s')" % needle


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--plugin", required=True, help="libfilter_dualspectra.so to test")
    ap.add_argument("--meshlabserver", default=shutil.which("meshlabserver") or "/usr/bin/meshlabserver")
    ap.add_argument("--meshlab-lib", default=None,
                    help="system directory holding libmeshlab-common.so and plugins/ (default: found)")
    ap.add_argument("--level", type=int, default=int(os.environ.get("DUALSPECTRA_MESHLAB_LEVEL", "3")),
                    help="icosphere level of the generated full mesh")
    ap.add_argument("--k", type=int, default=int(os.environ.get("DUALSPECTRA_MESHLAB_K", "10")))
    ap.add_argument("--min-iou", type=float, default=0.7)
    ap.add_argument("--timeout", type=int, default=int(os.environ.get("DUALSPECTRA_MESHLAB_TIMEOUT", "900")),
                    help="seconds allowed for the region run")
    ap.add_argument("--only", nargs="*", help="run only these cases")
    ap.add_argument("--keep", action="store_true", help="keep the work directory")
    args = ap.parse_args()

    lib_dir = args.meshlab_lib
    if lib_dir is None:
        found = glob.glob("/usr/lib/*/meshlab/libmeshlab-common.so") + glob.glob("/usr/lib/meshlab/libmeshlab-common.so")
        if not found:
            sys.exit("libmeshlab-common.so not found: apt-get install meshlab")
        lib_dir = os.path.dirname(found[0])
    for tool in ("xvfb-run", args.meshlabserver):
        if shutil.which(tool) is None and not os.path.exists(tool):
            sys.exit("%s not found: run scripts/setup.d/60-meshlab.sh" % tool)
    if not os.path.exists(args.plugin):
        sys.exit("plugin %s not found" % args.plugin)

    work = tempfile.mkdtemp(prefix="dualspectra-meshlab-")
    try:
        server, plugin_dir = make_prefix(os.path.join(work, "prefix"), args.plugin, args.meshlabserver, lib_dir)
        subprocess.run([sys.executable, os.path.join(HERE, "make_pair.py"), "--out", work, "--level",
                        str(args.level)], check=True)
        full = os.path.join(work, "full.off")
        partial = os.path.join(work, "partial.off")
        points = os.path.join(work, "points.off")
        with open(os.path.join(work, "expected_region.txt")) as f:
            expected = {int(l) for l in f if l.strip()}
        checks = Checks()
        wanted = lambda case: not args.only or case in args.only  # noqa: E731

        if wanted("same-layer"):
            print("case same-layer: the full layer picked twice")
            status, text, _ = run_server(server, work, "same-layer", [full, partial], mlx(0, 0))
            checks.check("same-layer", "filter %s not found" % FILTER not in text, "plugin loaded from " + plugin_dir)
            checks.check("same-layer", status != 0, "the script fails (exit %d)" % status)
            checks.check("same-layer", "same layer" in text, log_excerpt(text, "same layer"))
            no_crash(checks, "same-layer", status, text)

        if wanted("point-cloud"):
            print("case point-cloud: a partial layer without faces")
            status, text, _ = run_server(server, work, "point-cloud", [full, points], mlx(0, 1))
            checks.check("point-cloud", status != 0, "the script fails (exit %d)" % status)
            checks.check("point-cloud", "has no faces" in text, log_excerpt(text, "has no faces"))
            no_crash(checks, "point-cloud", status, text)

        if wanted("bad-k"):
            print("case bad-k: k = 0")
            status, text, _ = run_server(server, work, "bad-k", [full, partial], mlx(0, 1, k=0))
            checks.check("bad-k", status != 0, "the script fails (exit %d)" % status)
            checks.check("bad-k", "k must be at least 1" in text, log_excerpt(text, "k must be"))
            no_crash(checks, "bad-k", status, text)

        if wanted("bad-cuts"):
            print("case bad-cuts: SpectralCuts = -1")
            status, text, _ = run_server(server, work, "bad-cuts", [full, partial], mlx(0, 1, spectral_cuts=-1))
            checks.check("bad-cuts", status != 0, "the script fails (exit %d)" % status)
            checks.check("bad-cuts", "spectral cuts must be non-negative" in text,
                         log_excerpt(text, "spectral cuts"))
            no_crash(checks, "bad-cuts", status, text)

        if wanted("bad-planes"):
            print("case bad-planes: PlaneCuts = 27 (the library's bound is 26)")
            status, text, _ = run_server(server, work, "bad-planes", [full, partial], mlx(0, 1, plane_cuts=27))
            checks.check("bad-planes", status != 0, "the script fails (exit %d)" % status)
            checks.check("bad-planes", "plane_cuts = 27 must be at most 26" in text,
                         log_excerpt(text, "plane_cuts"))
            no_crash(checks, "bad-planes", status, text)

        if wanted("bad-mesh"):
            print("case bad-mesh: a non-manifold partial layer")
            nonmanifold = os.path.join(work, "nonmanifold.off")
            status, text, _ = run_server(server, work, "bad-mesh", [full, nonmanifold], mlx(0, 1))
            checks.check("bad-mesh", status != 0, "the script fails (exit %d)" % status)
            checks.check("bad-mesh", "partial layer rejected" in text and "DS_INVALID_MESH" in text,
                         log_excerpt(text, "partial layer rejected"))
            no_crash(checks, "bad-mesh", status, text)

        if wanted("region"):
            print("case region: full + a plane cut of it, moved rigidly (%d expected vertices)" % len(expected))
            # meshlabserver saves the current layer, which is the last one loaded: load the
            # partial first (layer 0) so that the full mesh (layer 1) is the one saved.
            status, text, out = run_server(server, work, "region", [partial, full],
                                           mlx(1, 0, k=args.k, write_score=True), save_mask=["vf", "vq", "sa"],
                                           timeout=args.timeout)
            no_crash(checks, "region", status, text)
            ok = status == 0 and out is not None and os.path.exists(out)
            checks.check("region", ok, "filter applied and mesh saved (exit %d)" % status)
            if not ok:
                print("  last lines of meshlabserver's output:")
                for line in [l for l in text.splitlines() if l.strip()][-6:]:
                    print("    " + line.strip())
            if ok:
                checks.check("region", "Localized " in text, log_excerpt(text, "Localized "))
                n, selected = read_selected(out)
                sel = set(selected)
                inter, union = len(sel & expected), len(sel | expected)
                iou = inter / union if union else 0.0
                checks.check("region", n == 4 ** args.level * 10 + 2, "saved mesh has %d vertices" % n)
                checks.check("region", iou >= args.min_iou,
                             "IoU %.3f (>= %.2f): %d selected, %d expected, %d in both"
                             % (iou, args.min_iou, len(sel), len(expected), inter))
                q = read_quality(out)
                checks.check("region", q is not None and len(q) == n, "vertex quality saved")
                if q is not None and len(q) == n:
                    inside = [q[i] for i in expected]
                    outside = [q[i] for i in range(n) if i not in expected]
                    mean_in = sum(inside) / max(1, len(inside))
                    mean_out = sum(outside) / max(1, len(outside))
                    checks.check("region", all(0.0 <= x <= 1.0 for x in q), "score in [0, 1]")
                    checks.check("region", mean_in > mean_out,
                                 "mean score inside %.3f > outside %.3f" % (mean_in, mean_out))

        print()
        if checks.failures:
            print("meshlab: %d check(s) failed:" % len(checks.failures))
            for f in checks.failures:
                print("  " + f)
            print("work directory kept: " + work)
            args.keep = True
            return 1
        print("meshlab: all checks passed")
        return 0
    finally:
        if not args.keep:
            shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
