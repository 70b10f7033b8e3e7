//! End-to-end checks of `localize`, `bench`, `demo` and `similarity` through the binary,
//! on the procedural pair that `dualspectra demo --out` writes (no data files needed).
//! Light localizer settings (`--k 6 --iterations 30`) keep them fast; the
//! checks are on the output schema and the laws of the scores, not on a result value.

mod common;

use common::{bin, run};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

const LIGHT: [&str; 4] = ["--k", "6", "--iterations", "30"];

fn tmp(name: &str) -> PathBuf {
    common::scratch("cli_localize", name)
}

/// The demo folder, built once for all tests.
fn demo_dir() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let d = tmp("demo");
        let out = run(bin().args(["demo", "--quiet", "--out"]).arg(&d).args(LIGHT));
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(text.contains("IoU"), "{text}");
        assert!(text.contains("confidence"), "the demo's summary gives the confidence: {text}");
        for f in [
            "full.off",
            "partial.off",
            "region.ply",
            "ground_truth.ply",
            "demo.png",
            "result.json",
            "dataset/null/figure.off",
        ] {
            assert!(d.join(f).is_file(), "demo did not write {f}");
        }
        d
    })
}

fn n_vertices_off(path: &Path) -> usize {
    let text = std::fs::read_to_string(path).unwrap();
    let mut it = text.split_whitespace();
    assert_eq!(it.next(), Some("OFF"));
    it.next().unwrap().parse().unwrap()
}

#[test]
fn localize_writes_the_json_schema_and_a_ply() {
    let d = demo_dir();
    let out_dir = tmp("localize");
    let (json, ply, png) = (out_dir.join("r.json"), out_dir.join("r.ply"), out_dir.join("r.png"));
    let out = run(bin()
        .args(["localize", "--quiet"])
        .arg(d.join("full.off"))
        .arg(d.join("partial.off"))
        .args(LIGHT)
        .args(["--mode", "dual", "--json"])
        .arg(&json)
        .arg("--ply")
        .arg(&ply)
        .arg("--png")
        .arg(&png));
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let n = n_vertices_off(&d.join("full.off"));
    let region = v["region"].as_array().expect("region array");
    assert!(!region.is_empty());
    let idx: Vec<u64> = region
        .iter()
        .map(|x| x.as_u64().expect("integer index"))
        .collect();
    assert!(idx.iter().all(|&i| (i as usize) < n));
    assert!(
        idx.windows(2).all(|w| w[0] < w[1]),
        "indices sorted and unique"
    );
    assert!(v["cost"].as_f64().unwrap().is_finite());
    let confidence = v["confidence"].as_f64().expect("confidence number");
    assert!((0.0..=1.0).contains(&confidence), "confidence {confidence} outside [0, 1]");
    // The one-line summary says the same region size and confidence as the JSON.
    let summary = String::from_utf8_lossy(&out.stdout);
    let said = format!("region: {} of {n} vertices, confidence {confidence:.2}, cost ", idx.len());
    assert!(summary.starts_with(&said), "{summary:?} does not start with {said:?}");
    assert!(v["seconds"].as_f64().unwrap() >= 0.0);
    assert_eq!(v["options"]["mode"], "dual");
    assert_eq!(v["options"]["k"], 6);
    assert_eq!(v["n_starts"], 3, "the most voted of the 6 plane cuts + 2 descriptor starts");
    assert!(v["timings"]["total"].as_f64().is_some());
    assert_eq!(v["eigenvalues_regular"].as_array().unwrap().len(), 6);
    assert_eq!(v["target_si"].as_array().unwrap().len(), 6);
    let ply_head = std::fs::read(&ply).unwrap();
    let head = String::from_utf8_lossy(&ply_head[..200.min(ply_head.len())]).to_string();
    assert!(
        head.starts_with("ply")
            && head.contains(&format!("element vertex {n}"))
            && head.contains("red"),
        "{head}"
    );
    // The picture: a valid PNG, front and back side by side, the (non-empty) region in red.
    let (w, h, rgb) = common::decode_png(&png);
    assert!(w > 0 && h > 0 && rgb.len() == 3 * w * h);
    assert!(common::red_pixels(&rgb, w, 0, w) > 0, "the region is drawn");
}

#[test]
fn the_demo_picture_shows_the_found_and_the_true_region() {
    // demo.png: two panels of one size (found | ground truth), each with region pixels, in
    // proportion to the regions' sizes within a factor (both regions are most of the arm side).
    let d = demo_dir();
    let (w, _, rgb) = common::decode_png(&d.join("demo.png"));
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(d.join("result.json")).unwrap()).unwrap();
    let found_vertices = v["region"].as_array().unwrap().len();
    let (found, truth) = (common::red_pixels(&rgb, w, 0, w / 2), common::red_pixels(&rgb, w, w / 2, w));
    assert!(found > 0 && truth > 0, "found {found}, true {truth} region pixels");
    let pair = dualspectra::evaluation::synthetic::synthetic_pair(&Default::default()).unwrap();
    let gt_vertices = pair.gt.iter().filter(|&&b| b).count();
    let (pixel_ratio, vertex_ratio) = (found as f64 / truth as f64, found_vertices as f64 / gt_vertices as f64);
    assert!((pixel_ratio / vertex_ratio).ln().abs() < 0.7, "pixels {pixel_ratio:.2} vs vertices {vertex_ratio:.2}");
}

/// `localize` on the demo pair with `--quiet` and `args`; the JSON it wrote.
fn localize_demo_json(name: &str, args: &[&str]) -> serde_json::Value {
    let d = demo_dir();
    let json = tmp(name).join("r.json");
    run(bin()
        .args(["localize", "--quiet"])
        .arg(d.join("full.off"))
        .arg(d.join("partial.off"))
        .args(args)
        .arg("--json")
        .arg(&json));
    serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap()
}

/// `localize a.off b.off` with `args` must be a usage error (exit 2); its stderr.
fn localize_usage_error(args: &[&str]) -> String {
    let out = bin().args(["localize", "a.off", "b.off"]).args(args).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    String::from_utf8_lossy(&out.stderr).into_owned()
}

#[test]
fn every_library_option_is_a_flag_and_reaches_the_library() {
    // The flags are built from the library's option table: each option is recorded in the JSON
    // with the value given; --plane-cuts changes the number of starts (none: the 2 descriptor
    // starts alone); the older spelling --iterations still works.
    let v = localize_demo_json(
        "localize-options",
        &["--k", "6", "--iterations", "3", "--plane-cuts", "0", "--mode", "lbo", "--alpha", "0.5", "--threads", "2"],
    );
    assert_eq!(v["n_starts"], 2);
    let o = &v["options"];
    assert_eq!((o["k"].as_u64(), o["plane_cuts"].as_u64(), o["max_iterations"].as_u64()), (Some(6), Some(0), Some(3)));
    assert_eq!((o["mode"].as_str(), o["alpha"].as_f64(), o["threads"].as_u64()), (Some("lbo"), Some(0.5), Some(2)));
    assert!(v["eigenvalues_si"].as_array().unwrap().is_empty(), "lbo mode matches regular eigenvalues only");
    let help = String::from_utf8_lossy(&bin().args(["localize", "--help"]).output().unwrap().stdout).into_owned();
    for spec in dualspectra::localizer::OPTIONS {
        let flag = format!("--{}", spec.name.replace('_', "-"));
        assert!(help.contains(&flag), "{flag} missing from --help");
    }
    // Out-of-range values are usage errors naming the option and its range; the library's
    // removed options say so; options removed before any release are unknown flags.
    let err = localize_usage_error(&["--plane-cuts", "27"]);
    assert!(err.contains("plane_cuts = 27 must be an integer in 0..=26"), "{err}");
    for (name, version, _) in dualspectra::localizer::REMOVED_OPTIONS {
        let flag = format!("--{}", name.replace('_', "-"));
        let err = localize_usage_error(&[&flag, "2"]);
        assert!(err.contains(&format!("option '{name}' was removed in {version}")), "{flag}: {err}");
        assert!(!help.contains(&flag), "{flag} is in --help");
    }
    let err = localize_usage_error(&["--mode", "both"]);
    assert!(err.contains("dual") && err.contains("lbo"), "{err}");
    for removed in ["--selection", "--starts", "--spectral-cuts", "--finalists"] {
        let err = localize_usage_error(&[removed, "1"]);
        assert!(err.contains("unexpected argument"), "{removed}: {err}");
    }
}

#[test]
fn bench_on_a_one_pair_dataset_prints_the_table_and_json() {
    let d = demo_dir();
    expect_failure(bin().args(["bench", "--quiet", "--stride", "0"]).arg(d.join("dataset")), 2, "--stride");
    let out_dir = tmp("bench");
    let (json, svg) = (out_dir.join("b.json"), out_dir.join("b.svg"));
    let out = run(bin()
        .args(["bench", "--quiet"])
        .arg(d.join("dataset"))
        .args(LIGHT)
        .arg("--json")
        .arg(&json)
        .arg("--svg")
        .arg(&svg));
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("cuts_figure_shape_1")
            && text.contains("IoU_sym")
            && text.contains("mean (1 pairs, 0 failed"),
        "{text}"
    );
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let p = &v["pairs"][0];
    assert_eq!(p["name"], "cuts_figure_shape_1");
    assert!(p["error"].is_null());
    for key in ["precision", "recall", "iou"] {
        let x = p["scores"][key].as_f64().unwrap();
        assert!((0.0..=1.0).contains(&x), "{key} = {x}");
    }
    let iou = p["scores"]["iou"].as_f64().unwrap();
    assert!(
        iou <= p["scores"]["precision"]
            .as_f64()
            .unwrap()
            .min(p["scores"]["recall"].as_f64().unwrap())
            + 1e-12
    );
    assert_eq!(v["summary"]["mean"]["iou"].as_f64().unwrap(), iou);
    assert!(std::fs::read_to_string(&svg).unwrap().starts_with("<svg"));
}

#[test]
fn similarity_of_two_shapes_is_symmetric() {
    let d = demo_dir();
    let out_dir = tmp("similarity");
    let json = out_dir.join("s.json");
    let svg = out_dir.join("s.svg");
    run(bin()
        .args(["similarity", "--quiet", "--k", "5"])
        .arg(d.join("full.off"))
        .arg(d.join("dataset/null/figure.off"))
        .arg(d.join("partial.off"))
        .arg("--json")
        .arg(&json)
        .arg("--svg")
        .arg(&svg));
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let m = &v["dual"]["distances"];
    for i in 0..3 {
        assert_eq!(m[i][i].as_f64().unwrap(), 0.0);
        for j in 0..3 {
            assert_eq!(m[i][j], m[j][i]);
        }
    }
    // The same shape written twice is at distance 0; the partial is not.
    assert!(m[0][1].as_f64().unwrap() < 1e-9);
    assert!(m[0][2].as_f64().unwrap() > 1e-3);
    assert!(std::fs::read_to_string(&svg).unwrap().contains("figure"));
}

fn expect_failure(cmd: &mut Command, code: i32, needle: &str) {
    let out = cmd.output().unwrap();
    assert_eq!(
        out.status.code(),
        Some(code),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let err = String::from_utf8_lossy(&out.stderr);
    let lines: Vec<&str> = err.lines().filter(|l| !l.trim().is_empty()).collect();
    assert_eq!(lines.len(), 1, "one-line message expected: {err}");
    assert!(
        lines[0].starts_with("error: ") && lines[0].contains(needle),
        "{err}"
    );
}

#[test]
fn missing_file_and_empty_partial_are_one_line_errors() {
    let dir = tmp("errors");
    let full = dir.join("full.off");
    std::fs::write(&full, "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n").unwrap();
    let missing = dir.join("nope.off");
    expect_failure(
        bin().args(["localize", "--quiet"]).arg(&full).arg(&missing),
        3,
        "nope.off",
    );
    let empty = dir.join("empty.off");
    std::fs::write(&empty, "OFF\n0 0 0\n").unwrap();
    expect_failure(
        bin().args(["localize", "--quiet"]).arg(&full).arg(&empty),
        3,
        "empty.off",
    );
    expect_failure(
        bin().args(["bench", "--quiet"]).arg(dir.join("no_dataset")),
        3,
        "no_dataset",
    );
    expect_failure(
        bin()
            .args(["localize", "--quiet", "--k", "0"])
            .arg(&full)
            .arg(&full),
        2,
        "--k",
    );
}

/// A partial the localizer cannot use (closed: no Dirichlet spectrum; no interior vertex)
/// is an input error (exit 3, README's table) on one line naming the partial's file, in
/// `localize` and in `search`.
#[test]
fn unusable_partials_are_input_errors_naming_the_file() {
    let dir = tmp("unusable_partials");
    let full = demo_dir().join("full.off");
    let closed = dir.join("closed_partial.off");
    std::fs::copy(&full, &closed).unwrap();
    let needle = format!("error: {}: the partial shape has no boundary (it is closed)", closed.display());
    expect_failure(bin().args(["localize", "--quiet"]).args(LIGHT).arg(&full).arg(&closed), 3, &needle);
    expect_failure(bin().args(["search", "--quiet"]).args(LIGHT).arg(&closed).arg(&full), 3, &needle);
    let triangle = dir.join("one_triangle.off");
    std::fs::write(&triangle, "OFF\n3 1 0\n0 0 0\n0.1 0 0\n0 0.1 0\n3 0 1 2\n").unwrap();
    let needle = format!("error: {}: the partial shape has no interior vertex", triangle.display());
    expect_failure(bin().args(["localize", "--quiet"]).args(LIGHT).arg(&full).arg(&triangle), 3, &needle);
}

#[test]
fn bench_locates_two_partials_with_one_prepared_shape_as_localize_does() {
    // Two parts cut off one figure (the demo's cut and the opposite side): bench prepares the
    // figure once (its second pair reports no preparation time) and finds the same regions as
    // two separate `localize` runs.
    use dualspectra_lab::datasets::write_shrec16_pair;
    use dualspectra::evaluation::synthetic::{synthetic_pair, SyntheticParams};
    let root = tmp("bench-two");
    let dataset = root.join("dataset");
    let mut partials = Vec::new();
    for (index, offset) in [(1, -0.35), (2, 0.2)] {
        let pair = synthetic_pair(&SyntheticParams { level: 3, cut_offset: offset, ..SyntheticParams::default() }).unwrap();
        write_shrec16_pair(&dataset, "figure", index, &pair.full, &pair.partial, &pair.barycentric_gt(), None).unwrap();
        partials.push(dataset.join("cuts").join(format!("cuts_figure_shape_{index}.off")));
    }
    let json = root.join("b.json");
    run(bin().args(["bench", "--quiet"]).arg(&dataset).args(LIGHT).arg("--json").arg(&json));
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let pairs = v["pairs"].as_array().unwrap();
    assert_eq!(pairs.len(), 2);
    assert!(pairs[0]["timings"]["preparation"].as_f64().unwrap() > 0.0);
    assert!(pairs[1]["timings"]["preparation"].as_f64().unwrap() < 0.5 * pairs[0]["timings"]["preparation"].as_f64().unwrap());
    for (pair, partial) in pairs.iter().zip(&partials) {
        assert!(pair["error"].is_null(), "{pair}");
        let out = root.join(format!("{}.json", pair["name"].as_str().unwrap()));
        run(bin().args(["localize", "--quiet"]).arg(dataset.join("null").join("figure.off")).arg(partial).args(LIGHT).arg("--json").arg(&out));
        let one: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
        assert_eq!(one["region"], pair["region"], "{}", pair["name"]);
    }
}

#[test]
fn bench_all_runs_every_dev_set_layout_and_scores_one_pair_alike_in_each() {
    // The same full shape, partial and region written in the SHREC'16 layout (barycentric
    // ground truth) and the PFAUST layout (vertex ground truth): `bench --all` finds both
    // sets, and both score the pair identically (same meshes, same region).
    use dualspectra_lab::datasets::{write_shrec16_pair, Dataset};
    use dualspectra::evaluation::synthetic::{synthetic_pair, SyntheticParams};
    let root = tmp("bench-all");
    let pair = synthetic_pair(&SyntheticParams { level: 3, ..SyntheticParams::default() }).unwrap();
    let shrec = root.join("shrec16");
    write_shrec16_pair(&shrec, "figure", 1, &pair.full, &pair.partial, &pair.barycentric_gt(), None).unwrap();
    let loaded = Dataset::open(&shrec).unwrap().pairs().unwrap()[0].load().unwrap();
    let region: String = loaded.gt.iter().enumerate().filter(|(_, &g)| g).map(|(i, _)| format!("{i}\n")).collect();
    let pfaust = root.join("pfaust_m");
    std::fs::create_dir_all(pfaust.join("null")).unwrap();
    std::fs::create_dir_all(pfaust.join("partials")).unwrap();
    std::fs::copy(shrec.join("null/figure.off"), pfaust.join("null/tr_reg_010.off")).unwrap();
    std::fs::copy(shrec.join("cuts/cuts_figure_shape_1.off"), pfaust.join("partials/tr_reg_011.off")).unwrap();
    std::fs::write(pfaust.join("partials/tr_reg_011.vertex_gt"), region).unwrap();
    let json = root.join("all.json");
    let out = run(bin().args(["bench", "--quiet", "--all"]).arg(&root).args(LIGHT).arg("--json").arg(&json).arg("--svg").arg(root.join("all.svg")));
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("== summary") && text.contains("mean of sets") && text.contains("pfaust_m"), "{text}");
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let sets = v["sets"].as_array().unwrap();
    assert_eq!(sets.iter().map(|s| s["set"].as_str().unwrap()).collect::<Vec<_>>(), ["shrec16", "pfaust_m"]);
    let (a, b) = (&sets[0]["pairs"][0], &sets[1]["pairs"][0]);
    assert!(a["error"].is_null() && b["error"].is_null(), "{a} {b}");
    assert_eq!(a["gt_size"], b["gt_size"]);
    assert_eq!(a["scores"], b["scores"]);
    assert!(root.join("all-shrec16.svg").is_file() && root.join("all-pfaust_m.svg").is_file());
    let mean = v["mean_of_sets"]["mean"]["iou"].as_f64().unwrap();
    assert!((mean - a["scores"]["iou"].as_f64().unwrap()).abs() < 1e-12);
    // No folder and no environment: a usage error naming the variable.
    let e = bin().args(["bench", "--all", "--quiet"]).env_remove("DUALSPECTRA_DATA").output().unwrap();
    assert_eq!(e.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&e.stderr).contains("DUALSPECTRA_DATA"));
}

#[test]
fn issue23_outputs_are_checked_before_the_localization() {
    // An output naming an input, a directory or a device fails at once (exit 5), before any
    // work, and the input is untouched.
    let d = demo_dir();
    let full = d.join("full.off");
    let before = std::fs::read(&full).unwrap();
    for (out, needle) in [(full.clone(), "is an input"), (d.to_path_buf(), "is a directory"), ("/dev/full".into(), "not a regular file")] {
        let t = std::time::Instant::now();
        let o = bin().args(["localize", "--quiet"]).arg(&full).arg(d.join("partial.off")).arg("--json").arg(&out).output().unwrap();
        assert_eq!(o.status.code(), Some(5), "{}", String::from_utf8_lossy(&o.stderr));
        assert!(String::from_utf8_lossy(&o.stderr).contains(needle), "{}", String::from_utf8_lossy(&o.stderr));
        assert!(t.elapsed().as_secs_f64() < 30.0, "checked before the work");
    }
    assert_eq!(std::fs::read(&full).unwrap(), before);
}
