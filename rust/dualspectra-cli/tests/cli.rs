//! The `dualspectra` binary run as a user would: `spectrum` and `curvature` outputs
//! checked against analytic laws (sphere and disk spectra, Gauss-Bonnet, scaling), and
//! bad inputs giving a one-line error that names the file, with a non-zero exit code.

use dualspectra::mesh::generate::{disk, icosphere};
use dualspectra::mesh::io::{read_mesh, write_off, write_ply};
use dualspectra::operators::lumped_mass;
use dualspectra::TriMesh;
use serde_json::Value;
use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_dualspectra"))
}

fn run(args: &[&str]) -> Output {
    bin().args(args).output().expect("the binary runs")
}

fn tmp(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli");
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/data")
        .join(name)
}

fn write_mesh(name: &str, mesh: &TriMesh) -> String {
    let p = tmp(name);
    write_off(&p, mesh).unwrap();
    p.to_str().unwrap().to_string()
}

fn json(out: &Output) -> Value {
    assert!(out.status.success(), "stderr: {}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).expect("stdout is JSON")
}

fn f64s(v: &Value) -> Vec<f64> {
    v.as_array()
        .expect("an array")
        .iter()
        .map(|x| x.as_f64().expect("a number"))
        .collect()
}

fn eigenvalues(out: &Output) -> Vec<f64> {
    let v = json(out);
    let obj = v.as_object().unwrap();
    assert_eq!(obj.keys().collect::<Vec<_>>(), ["eigenvalues"]);
    let ev = f64s(&v["eigenvalues"]);
    assert!(ev.windows(2).all(|w| w[0] <= w[1]), "ascending: {ev:?}");
    ev
}

#[test]
fn sphere_spectrum_is_l_times_l_plus_1() {
    // Unit sphere: eigenvalues l(l+1) with multiplicity 2l+1: 0, 2 (x3), 6 (x5).
    let sphere = write_mesh("sphere.off", &icosphere(3));
    let ev = eigenvalues(&run(&["spectrum", &sphere, "--k", "9"]));
    assert_eq!(ev.len(), 9);
    let exact = [0.0, 2.0, 2.0, 2.0, 6.0, 6.0, 6.0, 6.0, 6.0];
    assert!(ev[0].abs() < 1e-8, "{ev:?}");
    for (e, x) in ev.iter().zip(exact).skip(1) {
        assert!((e - x).abs() < 0.02 * x, "{ev:?}");
    }
}

#[test]
fn disk_spectrum_is_dirichlet_on_the_boundary() {
    // Unit disk, Dirichlet: j_{0,1}^2 = 5.7832, then j_{1,1}^2 = 14.682 twice.
    let d = write_mesh("disk.off", &disk(1.0, 12));
    let ev = eigenvalues(&run(&["spectrum", &d, "--k", "3"]));
    for (e, x) in ev.iter().zip([5.783186, 14.681971, 14.681971]) {
        assert!((e - x).abs() < 0.03 * x, "{ev:?}");
    }
}

#[test]
fn spectrum_json_file_equals_stdout_and_default_k_is_20() {
    let sphere = write_mesh("sphere_json.off", &icosphere(2));
    let out_path = tmp("spectrum.json");
    let _ = std::fs::remove_file(&out_path);
    let out = run(&["spectrum", &sphere, "--k", "20", "--json", out_path.to_str().unwrap()]);
    let ev = eigenvalues(&out);
    assert_eq!(ev.len(), 20);
    assert_eq!(std::fs::read(&out_path).unwrap(), out.stdout);
    assert_eq!(eigenvalues(&run(&["spectrum", &sphere])), ev);
}

#[test]
fn scaling_the_mesh_by_c_divides_the_regular_spectrum_by_c_squared() {
    let mesh = icosphere(2);
    let small = write_mesh("sphere_1.off", &mesh);
    let big = write_mesh("sphere_3.off", &mesh.map_positions(|p| p.map(|x| 3.0 * x)).unwrap());
    let a = eigenvalues(&run(&["spectrum", &small, "--k", "6"]));
    let b = eigenvalues(&run(&["spectrum", &big, "--k", "6"]));
    for (x, y) in a.iter().zip(&b).skip(1) {
        assert!((x / 9.0 - y).abs() < 1e-8 * x, "{a:?} {b:?}");
    }
}

#[test]
fn si_metric_with_alpha_0_is_the_regular_metric() {
    let d = write_mesh(
        "disk_si.off",
        &disk(1.0, 6)
            .map_positions(|p| [p[0], p[1], 0.3 * (p[0] * p[0] - p[1] * p[1])])
            .unwrap(),
    );
    let regular = eigenvalues(&run(&["spectrum", &d, "--k", "5", "--metric", "regular"]));
    let si0 = eigenvalues(&run(&["spectrum", &d, "--k", "5", "--metric", "si", "--alpha", "0"]));
    for (x, y) in regular.iter().zip(&si0) {
        assert!((x - y).abs() < 1e-10 * x, "{regular:?} {si0:?}");
    }
    let si = eigenvalues(&run(&["spectrum", &d, "--k", "5", "--metric", "si"]));
    assert_eq!(si.len(), 5);
    assert!(
        si.iter().zip(&regular).any(|(a, b)| (a - b).abs() > 1e-6 * b),
        "alpha = 0.33 changes the spectrum"
    );
}

/// Run `curvature`, check the JSON shape, return (K, smoothed K).
fn curvature(path: &str) -> (Vec<f64>, Vec<f64>) {
    let v = json(&run(&["curvature", path]));
    let mut keys: Vec<_> = v.as_object().unwrap().keys().cloned().collect();
    keys.sort();
    assert_eq!(keys, ["gaussian_curvature", "smoothed", "warnings"]);
    assert_eq!(v["warnings"], serde_json::json!([]), "nothing dropped");
    (f64s(&v["gaussian_curvature"]), f64s(&v["smoothed"]))
}

#[test]
fn curvature_obeys_gauss_bonnet() {
    for (name, mesh, total) in [
        ("gb_sphere.off", icosphere(3), 4.0 * PI),
        (
            "gb_ellipsoid.off",
            icosphere(2).map_positions(|p| [2.0 * p[0], p[1], 0.5 * p[2]]).unwrap(),
            4.0 * PI,
        ),
        ("gb_disk.off", disk(2.0, 5), 2.0 * PI),
    ] {
        let path = write_mesh(name, &mesh);
        let (k, smoothed) = curvature(&path);
        assert_eq!((k.len(), smoothed.len()), (mesh.n_vertices(), mesh.n_vertices()));
        let area = lumped_mass(&mesh);
        let sum: f64 = k.iter().zip(&area).map(|(k, a)| k * a).sum();
        assert!((sum - total).abs() < 1e-9 * total, "{name}: {sum} vs {total}");
    }
    // A unit sphere: K close to 1 everywhere (within 15% at the 12 valence-5 vertices),
    // its one-ring mean closer.
    let (k, smoothed) = curvature(&write_mesh("unit.off", &icosphere(3)));
    let worst = |v: &[f64]| v.iter().map(|x| (x - 1.0).abs()).fold(0.0, f64::max);
    assert!(
        worst(&k) < 0.15 && worst(&smoothed) < 0.05,
        "{} {}",
        worst(&k),
        worst(&smoothed)
    );
}

#[test]
fn curvature_json_file_and_polygon_input() {
    let out_path = tmp("curv.json");
    let out = run(&[
        "curvature",
        data("square_pyramid.ply").to_str().unwrap(),
        "--json",
        out_path.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(out.stdout.is_empty());
    let v: Value = serde_json::from_slice(&std::fs::read(&out_path).unwrap()).unwrap();
    let k = f64s(&v["gaussian_curvature"]);
    let area = lumped_mass(&read_mesh(&data("square_pyramid.off")).unwrap());
    let sum: f64 = k.iter().zip(&area).map(|(k, a)| k * a).sum();
    assert!((sum - 4.0 * PI).abs() < 1e-12);
}

#[test]
fn binary_ply_input_gives_the_same_spectrum_as_off() {
    let mesh = icosphere(2);
    let off = write_mesh("same.off", &mesh);
    let ply = tmp("same.ply");
    write_ply(&ply, &mesh, None, true).unwrap();
    let a = eigenvalues(&run(&["spectrum", &off, "--k", "5"]));
    let b = eigenvalues(&run(&["spectrum", ply.to_str().unwrap(), "--k", "5"]));
    assert_eq!(a, b);
}

/// Run, expect failure with `code`, a single stderr line `error: ...`, nothing on stdout.
fn fails(args: &[&str], code: i32) -> String {
    let out = run(args);
    assert_eq!(
        out.status.code(),
        Some(code),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out.stdout.is_empty());
    let err = String::from_utf8(out.stderr).unwrap();
    assert_eq!(err.lines().count(), 1, "one line: {err}");
    assert!(err.starts_with("error: "), "{err}");
    err.trim_end().to_string()
}

#[test]
fn bad_files_fail_with_one_line_naming_the_file() {
    let bad = data("bad.off");
    let b = bad.to_str().unwrap();
    for cmd in ["spectrum", "curvature"] {
        assert_eq!(
            fails(&[cmd, b], 3),
            format!("error: {b}: face 3 refers to vertex 99, but the mesh has 4 vertices")
        );
    }
    for (name, expect) in [
        ("nan.off", "vertex 2 has a non-finite coordinate"),
        ("truncated.off", "the file ends after 2 of 4 faces (truncated?)"),
        ("degenerate.off", "face 1 has zero area (degenerate)"),
        ("no_faces.off", "mesh has no faces"),
        ("bad_header.ply", "unsupported format line"),
        (
            "bad_index.obj",
            "line 6: face 1 refers to vertex 9, but the file has 4 vertices",
        ),
    ] {
        let p = data(name);
        let msg = fails(&["spectrum", p.to_str().unwrap()], 3);
        assert!(
            msg.starts_with(&format!("error: {}: ", p.display())) && msg.contains(expect),
            "{msg}"
        );
    }
    let missing = tmp("missing.off");
    let msg = fails(&["curvature", missing.to_str().unwrap()], 3);
    assert!(msg.starts_with(&format!("error: {}: ", missing.display())), "{msg}");
    let msg = fails(&["curvature", "mesh.stl"], 3);
    assert!(msg.contains("mesh.stl: unknown mesh format '.stl'"), "{msg}");
}

#[test]
fn isolated_vertices_fail_with_a_hint_or_are_dropped_on_request() {
    let p = data("isolated.off");
    let p = p.to_str().unwrap();
    let msg = fails(&["curvature", p], 3);
    assert!(
        msg.contains("vertex 2 belongs to no face") && msg.contains("--drop-isolated"),
        "{msg}"
    );
    let v = json(&run(&["curvature", p, "--drop-isolated"]));
    let k = v["gaussian_curvature"].as_array().unwrap();
    assert_eq!(k.len(), 5);
    assert!(k[2].is_null() && k.iter().enumerate().all(|(i, x)| i == 2 || x.is_f64()));
    assert_eq!(
        eigenvalues(&run(&["spectrum", p, "--k", "2", "--drop-isolated"])).len(),
        2
    );
}

#[test]
fn non_manifold_files_are_read_split_with_a_warning() {
    // Three triangles on the edge (0, 1): the third gets copies of 0 and 1 (a loose
    // triangle); the file's vertices 0 and 1 take their first copy's values.
    let p = data("nonmanifold_edge.off");
    let p = p.to_str().unwrap();
    let out = run(&["curvature", p]);
    let v = json(&out);
    let k = v["gaussian_curvature"].as_array().unwrap();
    assert_eq!(k.len(), 5);
    assert!(k.iter().all(Value::is_f64));
    let warnings = v["warnings"].as_array().unwrap();
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    let w = warnings[0].as_str().unwrap();
    assert!(w.contains("split 1 non-manifold edge(s) and 2 non-manifold vertex(es): 2 vertex copies"), "{w}");
    let stderr = String::from_utf8(out.stderr).unwrap();
    assert_eq!(stderr.lines().collect::<Vec<_>>(), [format!("warning: {p}: {w}")]);
    // The spectrum command says it on stderr too (its JSON holds only the eigenvalues): a
    // disk with a fin on its edge (0, 1).
    let d = disk(1.0, 3);
    let mut text = format!("OFF\n{} {} 0\n", d.n_vertices() + 1, d.n_faces() + 1);
    d.vertices().iter().for_each(|p| text += &format!("{} {} {}\n", p[0], p[1], p[2]));
    text += "0.05 0 1\n";
    d.faces().iter().for_each(|f| text += &format!("3 {} {} {}\n", f[0], f[1], f[2]));
    text += &format!("3 0 1 {}\n", d.n_vertices());
    let fin = tmp("disk_with_fin.off");
    std::fs::write(&fin, text).unwrap();
    let out = run(&["spectrum", fin.to_str().unwrap(), "--k", "2"]);
    assert_eq!(eigenvalues(&out).len(), 2);
    assert!(String::from_utf8_lossy(&out.stderr).contains("split 1 non-manifold edge(s)"), "{out:?}");
}

#[test]
fn issue23_curvature_warns_about_dropped_flap_vertices() {
    // flap.off: a tetrahedron with a two-sided flap whose tip (vertex 4) is in no other face;
    // reading removes the flap and the tip, whose values are null: say so, and why.
    let flap = data("flap.off");
    let out = run(&["curvature", flap.to_str().unwrap()]);
    let v = json(&out);
    let k = v["gaussian_curvature"].as_array().unwrap();
    assert_eq!(k.len(), 5);
    assert!(k[4].is_null() && v["smoothed"][4].is_null());
    assert!(k[..4].iter().all(Value::is_f64));
    let warnings = v["warnings"].as_array().unwrap();
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    let w = warnings[0].as_str().unwrap();
    assert!(w.contains("dropped 1 vertices") && w.contains("two-sided flaps") && w.contains("2 repeated triangles"), "{w}");
    let stderr = String::from_utf8(out.stderr).unwrap();
    assert_eq!(stderr.lines().collect::<Vec<_>>(), [format!("warning: {}: {w}", flap.display())]);
    // Also with --json OUT: the warning on stderr and in the file.
    let out_path = tmp("flap_curvature.json");
    let out = run(&["curvature", flap.to_str().unwrap(), "--json", out_path.to_str().unwrap()]);
    assert!(out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("dropped 1 vertices"));
    let v: Value = serde_json::from_slice(&std::fs::read(&out_path).unwrap()).unwrap();
    assert_eq!(v["warnings"].as_array().unwrap().len(), 1);
    // Isolated vertices dropped on request: the other reason.
    let v = json(&run(&["curvature", data("isolated.off").to_str().unwrap(), "--drop-isolated"]));
    let w = v["warnings"][0].as_str().unwrap();
    assert!(w.contains("dropped 1 vertices that belong to no face"), "{w}");
}

#[test]
fn bad_arguments_are_usage_errors() {
    let tet = data("tetrahedron.off");
    let t = tet.to_str().unwrap();
    let msg = fails(&["spectrum", t, "--k", "20"], 2);
    assert!(msg.contains(t) && msg.contains("k = 20"), "{msg}");
    assert!(fails(&["spectrum", t, "--k", "0"], 2).contains("--k must be at least 1"));
    assert!(fails(&["spectrum", t, "--k", "2", "--alpha", "0.5"], 2).contains("--alpha applies only to --metric si"));
    // clap's own errors: exit 2, usage on stderr.
    let out = run(&["spectrum", t, "--metric", "riemann"]);
    assert_eq!(out.status.code(), Some(2));
    let out = run(&["spectrum"]);
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn unwritable_output_is_exit_5() {
    let sphere = write_mesh("sphere_out.off", &icosphere(1));
    let dir = tmp("no_such_dir").join("out.json");
    let msg = fails(&["curvature", &sphere, "--json", dir.to_str().unwrap()], 5);
    assert!(msg.contains("cannot write"), "{msg}");
}

#[test]
fn a_closed_output_pipe_is_not_a_crash() {
    use std::process::Stdio;
    let sphere = write_mesh("sphere_pipe.off", &icosphere(5));
    let mut child = bin()
        .args(["curvature", &sphere])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take()); // the reader goes away before the ~1 MB of JSON is written
    let out = child.wait_with_output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(out.stderr.is_empty(), "{}", String::from_utf8_lossy(&out.stderr));
}

/// A report printed line by line into a pipe the reader has closed (`dualspectra similarity
/// ... | head -c 0`) ends quietly with success too, never with a panic.
#[test]
fn a_closed_pipe_under_a_line_report_is_not_a_crash() {
    use std::process::Stdio;
    let a = write_mesh("pipe_a.off", &icosphere(2));
    let b = write_mesh("pipe_b.off", &icosphere(3));
    let mut child = bin().args(["similarity", "--quiet", "--k", "5", &a, &b]).stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().unwrap();
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(out.stderr.is_empty(), "{}", String::from_utf8_lossy(&out.stderr));
}
