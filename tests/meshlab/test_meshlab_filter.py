"""End-to-end test of the MeshLab filter plugin in the real meshlabserver (stdlib only).

    python3 tests/meshlab/test_meshlab_filter.py --plugin build/plugins/libfilter_dualspectra.so
        [--ffi-lib target/debug/deps/libdualspectra_ffi.so]
    python3 tests/meshlab/test_meshlab_filter.py --write-script meshlab_filter/localize.mlx

meshlabserver loads plugins from `<prefix>/lib/<arch>/meshlab/plugins` next to its own binary
(`<prefix>/bin/meshlabserver`, found through /proc/self/exe, so the binary is copied, not
symlinked), and needs a display: each run is `xvfb-run -a`. The system is left untouched: a
private prefix in a temporary directory holds a copy of meshlabserver, links to the system
libmeshlab-common.so and plugins, and a link to the plugin under test.

The filter's parameters are the library's options: the scripts are written from its option
table (`ds_options_schema_json`, read with ctypes from the dualspectra-ffi shared library the
plugin was linked from, --ffi-lib), in the plugin's order: FullMesh, PartialMesh, the options,
WriteScore. `--write-script PATH` writes the example script meshlab_filter/localize.mlx.

Cases (each one meshlabserver run):
  parameters   `meshlabserver -d` lists the filter's parameters: the two meshes, one per option of
               the table (type and label), WriteScore, and the ranking filter's: the partial
               mesh and the options; and meshlab_filter/localize.mlx is the script of the
               defaults (else regenerate it with --write-script).
  region       one script, two filter calls on the same full layer (a full mesh with a loose
               vertex and a zero-area face): partial2, then partial; the first call prepares the
               full shape, the second reuses it (the log says both, and each result's
               confidence, in [0, 1]); the intake's warning is logged; the selection saved
               with `-m vf vq sa` (selected vertices carry flag bit 0x20) must have IoU >=
               --min-iou with partial's known region and leave the loose/degenerate vertices
               out; the score written to vertex quality must be in [0, 1] and higher on
               average inside the known region than outside.
  same-layer   the full layer picked twice: a clear message in the log, no crash.
  point-cloud  a partial layer without faces: a clear message in the log, no crash.
  bad-k, bad-planes, bad-threads
               an option out of range: the library's message naming it and its range, no crash.
  bad-enum     a choice index out of range: a clear message, no crash.
  fin          a non-manifold partial layer (the part with a fin: three triangles on one edge):
               the library's intake splits it (its warning is logged), the fin falls off as
               a separate piece (logged too), and the region has IoU >= --min-iou as in
               `region`.
  bad-mesh     a closed partial layer (an octahedron: no boundary), which the library refuses:
               its message reaches the log, no crash.
  rank         the ranking filter on a library of three layers (full.off among two other
               models) for partial.off, with light options (k, 2 start centres): the log ranks
               full.off first (a line per layer, with its score and confidence), and the saved
               full layer's selection overlaps partial's known region (IoU >= 0.5; the
               region's quality is the other cases' business).
  readme       the headless command line of meshlab_filter/README.md, run as written there (read
               from the README: the one line of its sh blocks that runs meshlabserver), in a
               directory holding full.off, partial.off and meshlab_filter/localize.mlx: it must
               save the full mesh with the selection, with IoU >= --min-iou; and the options
               the README names are the library's.
"""

import argparse
import ctypes
import glob
import json
import os
import re
import shlex
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
SEARCH = "Rank layers by partial similarity (dual spectra)"
REPO = os.path.dirname(os.path.dirname(HERE))
SHIPPED_SCRIPT = os.path.join(REPO, "meshlab_filter", "localize.mlx")
README = os.path.join(REPO, "meshlab_filter", "README.md")
RICH_TYPE = {"int": "RichInt", "float": "RichFloat", "choice": "RichEnum"}


def load_schema(ffi_lib):
    """The library's option table (a list of dicts), from `ds_options_schema_json`."""
    lib = ctypes.CDLL(ffi_lib)
    lib.ds_options_schema_json.restype = ctypes.c_char_p
    return json.loads(lib.ds_options_schema_json().decode("utf-8"))


def option_param(spec, value):
    """The script line of one option; `value` is the option's value (a choice by name)."""
    name, kind = spec["name"], spec["type"]
    if kind == "choice":
        choices = spec["choices"]
        index = choices.index(value) if value in choices else value  # an int: an index as given
        vals = " ".join('enum_val%d="%s"' % (i, c) for i, c in enumerate(choices))
        return '  <Param type="RichEnum" value="%d" name="%s" enum_cardinality="%d" %s/>' % (
            index, name, len(choices), vals)
    text = "%d" % value if kind == "int" else "%g" % value
    return '  <Param type="%s" value="%s" name="%s"/>' % (RICH_TYPE[kind], text, name)


def filter_call(schema, full, partial, write_score=False, **options):
    """One filter call with every parameter, in initParameterSet order (meshlabserver 2020.09
    matches the script's parameters to the filter's by position and asserts on the count).
    Options not given take the library's defaults."""
    unknown = set(options) - {s["name"] for s in schema}
    if unknown:
        raise ValueError("not options of the library: %s" % ", ".join(sorted(unknown)))
    lines = [' <filter name="%s">' % FILTER,
             '  <Param type="RichMesh" value="%d" name="FullMesh"/>' % full,
             '  <Param type="RichMesh" value="%d" name="PartialMesh"/>' % partial]
    lines += [option_param(s, options.get(s["name"], s["default"])) for s in schema]
    lines += ['  <Param type="RichBool" value="%s" name="WriteScore"/>' % ("true" if write_score else "false"),
              " </filter>"]
    return lines


def rank_call(schema, partial, **options):
    """One call of the ranking filter: PartialMesh, then every option (the library's defaults
    for those not given)."""
    lines = [' <filter name="%s">' % SEARCH, '  <Param type="RichMesh" value="%d" name="PartialMesh"/>' % partial]
    lines += [option_param(s, options.get(s["name"], s["default"])) for s in schema]
    return lines + [" </filter>"]


def mlx(*calls):
    """A filter script of `calls` (each from filter_call)."""
    return "\n".join(["<!DOCTYPE FilterScript>", "<FilterScript>"] + [l for c in calls for l in c]
                     + ["</FilterScript>", ""])


def readme_command():
    """The README's headless command line: the one line of its ```sh blocks running
    meshlabserver, as an argument list."""
    with open(README, encoding="utf-8") as f:
        text = f.read()
    lines = [l.strip() for block in re.findall(r"```sh\n(.*?)```", text, re.S) for l in block.splitlines()
             if "meshlabserver" in l and not l.strip().startswith("#")]
    if len(lines) != 1:
        raise ValueError("%s: expected one meshlabserver command line in its sh blocks, found %d: %s"
                         % (README, len(lines), lines))
    return shlex.split(lines[0])


def readme_options():
    """The option names the README's parameter table lists (the row of the options)."""
    with open(README, encoding="utf-8") as f:
        row = next((l for l in f if l.startswith("| *the options*")), "")
    return re.findall(r"`(\w+)`", row.split("(", 1)[1]) if "(" in row else []


def find_ffi_lib():
    for d in ("target/debug/deps", "target/debug", "target/release"):
        p = os.path.join(REPO, d, "libdualspectra_ffi.so")
        if os.path.exists(p):
            return p
    return None


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


def run_server(server, work, name, meshes, script_text, save_mask=None, timeout=120, save_layer=None):
    """Run meshlabserver on `meshes` with the script; return (exit status, log text, output path).
    The output is the current layer, or the layer at position `save_layer`."""
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
        cmd += ["-o", out] + (["-l", str(save_layer)] if save_layer is not None else []) + ["-m"] + save_mask
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
    text = text.replace("Localize partial shape: ", "\nLocalize partial shape: ").replace("Rank layers: ", "\nRank layers: ")
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


def log_lines(text, needle):
    """The distinct lines of `text` holding `needle`, in order (the log's " LOG: n " prefix off)."""
    out = []
    for line in text.splitlines():
        if needle in line:
            line = re.sub(r"^LOG: \d+ ", "", line.strip())
            if line not in out:
                out.append(line)
    return out


def iou_of(selected, expected):
    union = len(selected | expected)
    return len(selected & expected) / union if union else 0.0


def log_excerpt(text, needle):
    lines = [l.strip() for l in text.splitlines() if needle.lower() in l.lower()]
    return lines[0] if lines else "(no line with '%s')" % needle


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--plugin", help="libfilter_dualspectra.so to test (required unless --write-script)")
    ap.add_argument("--meshlabserver", default=shutil.which("meshlabserver") or "/usr/bin/meshlabserver")
    ap.add_argument("--meshlab-lib", default=None,
                    help="system directory holding libmeshlab-common.so and plugins/ (default: found)")
    ap.add_argument("--level", type=int, default=int(os.environ.get("DUALSPECTRA_MESHLAB_LEVEL", "3")),
                    help="icosphere level of the generated full mesh")
    ap.add_argument("--k", type=int, default=int(os.environ.get("DUALSPECTRA_MESHLAB_K", "10")))
    ap.add_argument("--min-iou", type=float, default=0.7)
    ap.add_argument("--timeout", type=int, default=int(os.environ.get("DUALSPECTRA_MESHLAB_TIMEOUT", "900")),
                    help="seconds allowed for the region run")
    ap.add_argument("--ffi-lib", default=None,
                    help="libdualspectra_ffi.so the plugin was built from (its option table; default: found in target/)")
    ap.add_argument("--write-script", metavar="PATH", help="write the example script (defaults) to PATH and exit")
    ap.add_argument("--only", nargs="*", help="run only these cases")
    ap.add_argument("--keep", action="store_true", help="keep the work directory")
    args = ap.parse_args()

    ffi_lib = args.ffi_lib or find_ffi_lib()
    if ffi_lib is None or not os.path.exists(ffi_lib):
        sys.exit("libdualspectra_ffi.so not found: cargo build -p dualspectra-ffi, or pass --ffi-lib")
    schema = load_schema(ffi_lib)
    if args.write_script:
        with open(args.write_script, "w") as f:
            f.write(mlx(filter_call(schema, 0, 1)))
        print("wrote %s (%d options)" % (args.write_script, len(schema)))
        return 0

    lib_dir = args.meshlab_lib
    if lib_dir is None:
        found = glob.glob("/usr/lib/*/meshlab/libmeshlab-common.so") + glob.glob("/usr/lib/meshlab/libmeshlab-common.so")
        if not found:
            sys.exit("libmeshlab-common.so not found: apt-get install meshlab")
        lib_dir = os.path.dirname(found[0])
    for tool in ("xvfb-run", args.meshlabserver):
        if shutil.which(tool) is None and not os.path.exists(tool):
            sys.exit("%s not found: run scripts/setup.d/60-meshlab.sh" % tool)
    if not args.plugin or not os.path.exists(args.plugin):
        sys.exit("plugin %s not found (--plugin)" % args.plugin)

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

        if wanted("parameters"):
            print("case parameters: the filter's parameters are the library's options")
            dump = os.path.join(work, "filters.txt")
            cmd = ["xvfb-run", "-a", server, "-d", dump]
            proc = subprocess.run(cmd, cwd=work, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=120)
            rows, search_rows = [], []
            if os.path.exists(dump):
                with open(dump, encoding="utf-8", errors="replace") as f:
                    text = f.read()

                def parameter_rows(name):
                    section = text.split("%s \n" % name, 1)[1].split("\\section", 1)[0] if name + " \n" in text else ""
                    return re.findall(r"<TR><TD> \\c (\w+)\s*</TD> <TD> (.*?) </TD>", section)

                rows, search_rows = parameter_rows(FILTER), parameter_rows(SEARCH)
            want = ([("Mesh", "Full mesh"), ("Mesh", "Partial mesh")]
                    + [({"int": "Int", "float": "Float", "choice": "Enum"}[s["type"]], s["label"]) for s in schema]
                    + [("Bool", "Score to vertex quality and colour")])
            checks.check("parameters", rows == want, "meshlabserver -d lists %d parameters (%s)%s" % (
                len(rows), ", ".join(label for _, label in rows),
                "" if rows == want else "; expected %s; exit %d" % (want, proc.returncode)))
            want = [("Mesh", "Partial mesh")] + want[2:-1]
            checks.check("parameters", search_rows == want, "the ranking filter lists %d parameters%s" % (
                len(search_rows), "" if search_rows == want else ": %s; expected %s" % (search_rows, want)))
            shipped = open(SHIPPED_SCRIPT).read() if os.path.exists(SHIPPED_SCRIPT) else ""
            checks.check("parameters", shipped == mlx(filter_call(schema, 0, 1)),
                         "%s is the script of the defaults (regenerate: %s --write-script %s)"
                         % (os.path.relpath(SHIPPED_SCRIPT, REPO), os.path.relpath(__file__, REPO),
                            os.path.relpath(SHIPPED_SCRIPT, REPO)))

        if wanted("same-layer"):
            print("case same-layer: the full layer picked twice")
            status, text, _ = run_server(server, work, "same-layer", [full, partial], mlx(filter_call(schema, 0, 0)))
            checks.check("same-layer", "filter %s not found" % FILTER not in text, "plugin loaded from " + plugin_dir)
            checks.check("same-layer", status != 0, "the script fails (exit %d)" % status)
            checks.check("same-layer", "same layer" in text, log_excerpt(text, "same layer"))
            no_crash(checks, "same-layer", status, text)

        if wanted("point-cloud"):
            print("case point-cloud: a partial layer without faces")
            status, text, _ = run_server(server, work, "point-cloud", [full, points], mlx(filter_call(schema, 0, 1)))
            checks.check("point-cloud", status != 0, "the script fails (exit %d)" % status)
            checks.check("point-cloud", "has no faces" in text, log_excerpt(text, "has no faces"))
            no_crash(checks, "point-cloud", status, text)

        # An option out of range: the library refuses it, naming the option and its range.
        for case, options, says in [
            ("bad-k", {"k": 0}, "k = 0 must be an integer in 1..=500"),
            ("bad-planes", {"plane_cuts": 27}, "plane_cuts = 27 must be an integer in 0..=26"),
            ("bad-threads", {"threads": -1}, "threads = -1 must be an integer in 0..=256"),
            ("bad-enum", {"mode": 7}, "mode: choice 7 is out of range (3 choices: dual, lbo, si)"),
        ]:
            if not wanted(case):
                continue
            print("case %s: %s" % (case, options))
            status, text, _ = run_server(server, work, case, [full, partial], mlx(filter_call(schema, 0, 1, **options)))
            checks.check(case, status != 0, "the script fails (exit %d)" % status)
            checks.check(case, says in text, log_excerpt(text, says))
            no_crash(checks, case, status, text)

        if wanted("fin"):
            print("case fin: a non-manifold partial layer (the part with a fin on one of its edges)")
            fin = os.path.join(work, "fin.off")
            # the full layer last, so that it is the layer saved (see `region`)
            status, text, out = run_server(server, work, "fin", [fin, full], mlx(filter_call(schema, 1, 0, k=args.k)),
                                           save_mask=["vf", "sa"], timeout=args.timeout)
            no_crash(checks, "fin", status, text)
            ok = status == 0 and out is not None and os.path.exists(out)
            checks.check("fin", ok, "the filter call applied and mesh saved (exit %d)" % status)
            said = "partial mesh: split 1 non-manifold edge(s) and 2 non-manifold vertex(es) (2 vertex copies"
            checks.check("fin", said in text, log_excerpt(text, "non-manifold"))
            # the part's vertices, of the part's + the fin's tip + the two copies
            with open(partial) as f:
                n_part = int(f.read().split()[1])
            checks.check("fin", "only its largest component (%d of %d vertices)" % (n_part, n_part + 3) in text,
                         log_excerpt(text, "largest component"))
            if ok:
                sel = set(read_selected(out)[1])
                inter, union = len(sel & expected), len(sel | expected)
                checks.check("fin", union > 0 and inter / union >= args.min_iou,
                             "IoU %.3f (>= %.2f): %d selected, %d expected"
                             % (inter / max(1, union), args.min_iou, len(sel), len(expected)))

        if wanted("bad-mesh"):
            print("case bad-mesh: a closed partial layer (no boundary)")
            closed = os.path.join(work, "closed.off")
            status, text, _ = run_server(server, work, "bad-mesh", [full, closed], mlx(filter_call(schema, 0, 1, k=args.k)),
                                         timeout=args.timeout)
            checks.check("bad-mesh", status != 0, "the script fails (exit %d)" % status)
            checks.check("bad-mesh", "localization failed" in text and "the partial shape has no boundary" in text,
                         log_excerpt(text, "no boundary"))
            no_crash(checks, "bad-mesh", status, text)

        if wanted("rank"):
            print("case rank: partial.off against a library of three layers (full.off is the second)")
            library = [os.path.join(work, n) for n in ("other_ellipsoid.off", "full.off", "other_bumps.off")]
            status, text, out = run_server(server, work, "rank", library + [partial], mlx(rank_call(schema, 3, k=args.k)),
                                           save_mask=["vf", "sa"], timeout=args.timeout, save_layer=1)
            no_crash(checks, "rank", status, text)
            ok = status == 0 and out is not None and os.path.exists(out)
            checks.check("rank", ok, "the filter call applied and the full layer saved (exit %d)" % status)
            ranks = log_lines(text, "Rank ")
            ranks = [l for l in ranks if re.match(r"Rank \d: ", l)]
            checks.check("rank", len(ranks) == 3 and ranks[0].startswith("Rank 1: 'full.off' score "),
                         " | ".join(ranks) or log_excerpt(text, "Rank layers"))
            if ok:
                sel = set(read_selected(out)[1])
                checks.check("rank", iou_of(sel, expected) >= 0.5,
                             "IoU %.3f (>= 0.5) on the best layer: %d selected, %d expected"
                             % (iou_of(sel, expected), len(sel), len(expected)))

        if wanted("readme"):
            print("case readme: the headless command line of %s, as written" % os.path.relpath(README, REPO))
            names = [spec["name"] for spec in schema]
            checks.check("readme", readme_options() == names,
                         "the README names the options %s (the library's: %s)" % (readme_options(), names))
            cmd = readme_command()
            print("  " + " ".join(cmd))
            out = os.path.join(work, "readme", cmd[cmd.index("-o") + 1]) if "-o" in cmd else None
            run_dir = os.path.join(work, "readme")
            os.makedirs(run_dir)
            for name in ("full.off", "partial.off"):
                shutil.copy(os.path.join(work, name), run_dir)
            os.symlink(os.path.join(REPO, "meshlab_filter"), os.path.join(run_dir, "meshlab_filter"))
            cmd = [server if c == "meshlabserver" else c for c in cmd]
            start = time.time()
            proc = subprocess.Popen(cmd, cwd=run_dir, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                    start_new_session=True)
            try:
                stdout, _ = proc.communicate(timeout=args.timeout)
            except subprocess.TimeoutExpired:
                os.killpg(proc.pid, signal.SIGKILL)
                stdout, _ = proc.communicate()
            text = stdout.decode("utf-8", errors="replace").replace("\r", "\n")
            print("  [readme] meshlabserver exit %d after %.1f s" % (proc.returncode, time.time() - start))
            no_crash(checks, "readme", proc.returncode, text)
            ok = proc.returncode == 0 and out is not None and os.path.exists(out)
            checks.check("readme", ok, "the command applied the script and saved %s (exit %d)" % (out, proc.returncode))
            if ok:
                n, selected = read_selected(out)
                sel = set(selected)
                n_full = 4 ** args.level * 10 + 2
                checks.check("readme", n == n_full, "the saved mesh is the full mesh (%d vertices, full: %d)" % (n, n_full))
                checks.check("readme", iou_of(sel, expected) >= args.min_iou,
                             "IoU %.3f (>= %.2f): %d selected, %d expected"
                             % (iou_of(sel, expected), args.min_iou, len(sel), len(expected)))
            else:
                for line in [l for l in text.splitlines() if l.strip()][-6:]:
                    print("    " + line.strip())

        if wanted("region"):
            full_debris = os.path.join(work, "full_debris.off")
            partial2 = os.path.join(work, "partial2.off")
            print("case region: a full mesh (+ a loose vertex and a zero-area face) and two plane cuts of it, "
                  "moved rigidly; one prepared full shape (%d expected vertices)" % len(expected))
            # meshlabserver saves the current layer, which is the last one loaded: load the
            # partials first (layers 0, 1) so that the full mesh (layer 2) is the one saved.
            script = mlx(filter_call(schema, 2, 1, k=args.k), filter_call(schema, 2, 0, write_score=True, k=args.k))
            status, text, out = run_server(server, work, "region", [partial, partial2, full_debris], script,
                                           save_mask=["vf", "vq", "sa"], timeout=args.timeout)
            no_crash(checks, "region", status, text)
            ok = status == 0 and out is not None and os.path.exists(out)
            checks.check("region", ok, "both filter calls applied and mesh saved (exit %d)" % status)
            if not ok:
                print("  last lines of meshlabserver's output:")
                for line in [l for l in text.splitlines() if l.strip()][-6:]:
                    print("    " + line.strip())
            if ok:
                # (meshlabserver prints the log and saves it: each line is in `text` twice)
                results = log_lines(text, "Localized ")
                checks.check("region", len(results) == 2 and "partial2.off" in results[0] and "'partial.off'" in results[1],
                             " | ".join(results))
                confidences = [float(m.group(1)) for m in (re.search(r"; confidence ([0-9.]+);", r) for r in results) if m]
                checks.check("region", len(confidences) == 2 and all(0.0 <= c <= 1.0 for c in confidences),
                             "each result line gives a confidence in [0, 1]: %s" % confidences)
                optimised_on = [int(m.group(1)) for m in (re.search(r"; optimised on (\d+) vertices;", r) for r in results) if m]
                checks.check("region", len(optimised_on) == 2 and all(v > 0 for v in optimised_on),
                             "each result line gives the optimisation mesh's vertices: %s" % optimised_on)
                prepared, reused = log_lines(text, "prepared the full shape"), log_lines(text, "reused the full shape")
                checks.check("region", len(prepared) == 1 and len(reused) == 1,
                             "one preparation, one reuse: %s" % " | ".join(prepared + reused))
                checks.check("region", "full mesh: left out 1 degenerate face(s) and 4 vertex(es)" in text,
                             log_excerpt(text, "left out"))
                n_full = 4 ** args.level * 10 + 2
                n, selected = read_selected(out)
                sel = set(selected)
                inter, union = len(sel & expected), len(sel | expected)
                iou = inter / union if union else 0.0
                checks.check("region", n == n_full + 4, "saved mesh has %d vertices (%d + 4 debris)" % (n, n_full))
                checks.check("region", not sel & set(range(n_full, n)), "no loose or degenerate vertex selected")
                checks.check("region", iou >= args.min_iou,
                             "IoU %.3f (>= %.2f): %d selected, %d expected, %d in both"
                             % (iou, args.min_iou, len(sel), len(expected), inter))
                q = read_quality(out)
                checks.check("region", q is not None and len(q) == n, "vertex quality saved")
                if q is not None and len(q) == n:
                    inside = [q[i] for i in expected]
                    outside = [q[i] for i in range(n_full) if i not in expected]
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
