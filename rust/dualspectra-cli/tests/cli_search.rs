//! End-to-end checks of `search` and `prepare` through the binary, on a generated library
//! (no data files): the figure a partial was cut from and two other models. The partial's
//! model ranks first, prepared shapes (.dsprep) rank and score as the meshes they were
//! prepared from, and a stale or foreign .dsprep is a one-line error naming it.

use dualspectra::evaluation::synthetic::{figure, horned_limbs, quadruped_limbs, synthetic_pair, SyntheticParams};
use dualspectra::mesh::io::write_off;
use serde_json::Value;
mod common;

use common::{bin, run};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

const LIGHT: [&str; 6] = ["--k", "6", "--iterations", "10", "--threads", "2"];

fn tmp(name: &str) -> PathBuf {
    common::scratch("cli_search", name)
}

fn read_json(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// `partial.off` and `library/` (figure.off, horned.off, quadruped.off), written once.
fn library() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let d = tmp("library");
        let pair = synthetic_pair(&SyntheticParams { level: 3, ..SyntheticParams::default() }).unwrap();
        std::fs::create_dir_all(d.join("library")).unwrap();
        write_off(&d.join("partial.off"), &pair.partial).unwrap();
        write_off(&d.join("library/figure.off"), &pair.full).unwrap();
        write_off(&d.join("library/quadruped.off"), &figure(3, &quadruped_limbs()).unwrap()).unwrap();
        write_off(&d.join("library/horned.off"), &figure(3, &horned_limbs()).unwrap()).unwrap();
        // Not a mesh: a folder's other files are left out.
        std::fs::write(d.join("library/notes.txt"), "not a mesh").unwrap();
        d
    })
}

/// `search partial.off library/` with JSON and PLY output, run once: (stdout, JSON, PLY dir).
fn searched() -> &'static (String, Value, PathBuf) {
    static OUT: OnceLock<(String, Value, PathBuf)> = OnceLock::new();
    OUT.get_or_init(|| {
        let d = library();
        let out_dir = tmp("search");
        let json = out_dir.join("ranking.json");
        let out = run(bin()
            .args(["search", "--quiet"])
            .arg(d.join("partial.off"))
            .arg(d.join("library"))
            .args(LIGHT)
            .arg("--json")
            .arg(&json)
            .arg("--ply-dir")
            .arg(out_dir.join("regions"))
            .arg("--png")
            .arg(out_dir.join("ranking.png")));
        (String::from_utf8_lossy(&out.stdout).into_owned(), read_json(&json), out_dir.join("regions"))
    })
}

fn names(ranking: &Value) -> Vec<String> {
    ranking["ranking"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| Path::new(r["shape"].as_str().unwrap()).file_name().unwrap().to_string_lossy().into_owned())
        .collect()
}

#[test]
fn search_ranks_the_model_the_partial_was_cut_from_first() {
    let (stdout, v, plys) = searched();
    assert_eq!(names(v)[0], "figure.off", "{stdout}");
    // The table: a header, one row per shape best first, a closing line.
    let lines: Vec<&str> = stdout.lines().collect();
    assert!(lines[0].contains("rank") && lines[0].contains("score") && lines[0].contains("region") && lines[0].contains("confidence"), "{stdout}");
    assert!(lines[1].trim_start().starts_with("1  figure.off"), "{stdout}");
    assert_eq!(lines.len(), 6, "{stdout}");
    assert!(lines[5].starts_with("3 shapes searched in"), "{stdout}");
    // The JSON: every shape searched (the folder's meshes by name), the ranking with scores
    // ascending, and each region as sorted vertex indices of its file.
    let shapes: Vec<&str> = v["shapes"].as_array().unwrap().iter().map(|s| s.as_str().unwrap()).collect();
    assert_eq!(shapes.len(), 3);
    assert!(shapes[0].ends_with("figure.off") && shapes[2].ends_with("quadruped.off"), "{shapes:?}");
    let ranking = v["ranking"].as_array().unwrap();
    let scores: Vec<f64> = ranking.iter().map(|r| r["score"].as_f64().expect("a score")).collect();
    assert!(scores.windows(2).all(|w| w[0] <= w[1]), "{scores:?}");
    for (i, r) in ranking.iter().enumerate() {
        assert_eq!(r["rank"], i + 1);
        let region: Vec<u64> = r["region"].as_array().unwrap().iter().map(|x| x.as_u64().unwrap()).collect();
        let n = r["n_vertices"].as_u64().unwrap();
        assert_eq!(r["region_vertices"].as_u64().unwrap() as usize, region.len());
        assert!(!region.is_empty() && region.windows(2).all(|w| w[0] < w[1]) && *region.last().unwrap() < n);
        let confidence = r["confidence"].as_f64().unwrap();
        assert!((0.0..=1.0).contains(&confidence));
        assert!(r["error"].is_null());
    }
    // A PLY per ranked shape, named by rank.
    for (i, name) in names(v).iter().enumerate() {
        let stem = name.trim_end_matches(".off");
        let ply = std::fs::read(plys.join(format!("{}_{stem}.ply", i + 1))).unwrap();
        assert!(ply.starts_with(b"ply"));
    }
    // The picture: a valid PNG with the three shapes in one row of equal cells, each with
    // its region in red; stdout says what it shows.
    let (w, _, rgb) = common::decode_png(&plys.with_file_name("ranking.png"));
    let cell = w / 3;
    for i in 0..3 {
        assert!(common::red_pixels(&rgb, w, i * cell, (i + 1) * cell) > 0, "shape {} has no region pixel", i + 1);
    }
    assert!(stdout.contains("ranking.png: ranks 1 to 3"), "{stdout}");
}

#[test]
fn prepared_shapes_rank_and_score_as_their_meshes() {
    let d = library();
    let prep = tmp("prepared");
    for name in ["figure", "horned", "quadruped"] {
        let out = run(bin()
            .args(["prepare", "--quiet"])
            .arg(d.join(format!("library/{name}.off")))
            .arg("-o")
            .arg(prep.join(format!("{name}.dsprep")))
            .args(LIGHT));
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(text.starts_with("prepared ") && text.contains(&format!("{name}.dsprep")), "{text}");
    }
    let json = prep.join("ranking.json");
    run(bin().args(["search", "--quiet"]).arg(d.join("partial.off")).arg(&prep).arg("--top").arg("2").arg("--json").arg(&json));
    let v = read_json(&json);
    let (_, fresh, _) = searched();
    let stems = |v: &Value| names(v).iter().map(|n| n.split('.').next().unwrap().to_string()).collect::<Vec<_>>();
    assert_eq!(stems(&v), stems(fresh)[..2], "--top 2 keeps the two best");
    for (a, b) in v["ranking"].as_array().unwrap().iter().zip(fresh["ranking"].as_array().unwrap()) {
        assert_eq!(a["score"], b["score"], "bit-identical scores from a prepared shape");
        assert_eq!(a["region"], b["region"]);
    }
    // The search's --scale applies to prepared shapes (prepared with the default `same`): a
    // partial in other units is localized on them, not refused as larger than the model.
    let partial = dualspectra::mesh::io::read_mesh(&d.join("partial.off")).unwrap();
    let in_mm = tmp("units").join("partial_mm.off");
    std::fs::create_dir_all(in_mm.parent().unwrap()).unwrap();
    write_off(&in_mm, &partial.map_positions(|p| p.map(|c| c * 1000.0)).unwrap()).unwrap();
    let json_auto = in_mm.with_file_name("ranking.json");
    run(bin().args(["search", "--quiet", "--scale", "auto"]).arg(&in_mm).arg(&prep).arg("--json").arg(&json_auto));
    let v = read_json(&json_auto);
    assert_eq!(names(&v)[0], "figure.dsprep", "{v}");
    for r in v["ranking"].as_array().unwrap() {
        assert!(r["error"].is_null() && r["score"].as_f64().is_some(), "{r}");
    }
    // A default output name beside the mesh.
    let copy = prep.join("copy.off");
    std::fs::copy(d.join("library/horned.off"), &copy).unwrap();
    run(bin().args(["prepare", "--quiet"]).arg(&copy).args(LIGHT));
    assert!(prep.join("copy.dsprep").is_file());
}

/// `search` on `file`: it must fail with exit code 3 and one line naming the file; the line.
fn search_error(file: &Path) -> String {
    let out = bin().args(["search", "--quiet"]).arg(library().join("partial.off")).arg(file).output().unwrap();
    assert_eq!(out.status.code(), Some(3), "{}", String::from_utf8_lossy(&out.stderr));
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.starts_with("error: ") && err.contains(&file.display().to_string()), "{err}");
    err
}

#[test]
fn a_stale_or_foreign_prepared_file_is_a_clear_error() {
    let d = tmp("stale");
    let good = d.join("good.dsprep");
    run(bin().args(["prepare", "--quiet"]).arg(library().join("library/horned.off")).arg("-o").arg(&good).args(LIGHT));
    let mut bytes = std::fs::read(&good).unwrap();
    let version = u32::from_le_bytes(bytes[8..12].try_into().unwrap());
    bytes[8..12].copy_from_slice(&(version + 1).to_le_bytes());
    let stale = d.join("stale.dsprep");
    std::fs::write(&stale, &bytes).unwrap();
    let err = search_error(&stale);
    assert!(err.contains("stale prepared shape") && err.contains("prepare the shape again"), "{err}");
    let foreign = d.join("mesh.dsprep");
    std::fs::copy(library().join("partial.off"), &foreign).unwrap();
    assert!(search_error(&foreign).contains("not a dualspectra prepared shape"));
    let truncated = d.join("cut.dsprep");
    std::fs::write(&truncated, &std::fs::read(&good).unwrap()[..1000]).unwrap();
    assert!(search_error(&truncated).contains("truncated"));
    // Shapes are opened one at a time, but a missing one is reported before any work.
    let out = bin().args(["search", "--quiet"]).arg(library().join("partial.off")).arg(&good).arg(d.join("missing.off")).output().unwrap();
    assert_eq!(out.status.code(), Some(3));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.starts_with("error: ") && err.contains("missing.off"), "{err}");
}

/// `index` describes the library once; `search` on the .dsscreen with `--shortlist 1`
/// localizes only the shape the screen ranks best (the partial's own figure), lists the
/// others as screened out, and finds the same region as the full search.
#[test]
fn an_indexed_library_is_screened_and_only_the_shortlist_localized() {
    let d = library();
    let out_dir = tmp("screened");
    let screen = out_dir.join("library.dsscreen");
    let out = run(bin().args(["index", "--quiet"]).arg(d.join("library")).arg("-o").arg(&screen));
    assert!(String::from_utf8_lossy(&out.stdout).contains("3 shapes described"), "{}", String::from_utf8_lossy(&out.stdout));
    let json = out_dir.join("ranking.json");
    let out = run(bin()
        .args(["search", "--quiet", "--shortlist", "1"])
        .arg(d.join("partial.off"))
        .arg(&screen)
        .args(LIGHT)
        .arg("--json")
        .arg(&json));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("3 shapes screened, the 1 best localized"), "{stdout}");
    assert_eq!(stdout.matches("screened out").count(), 2, "{stdout}");
    let output = read_json(&json);
    assert_eq!(names(&output)[0], "figure.off");
    let ranking = output["ranking"].clone();
    assert!(ranking[0]["screen_score"].is_number() && ranking[0]["score"].is_number());
    assert!(ranking[1]["score"].is_null() && ranking[1]["error"].is_null() && ranking[1]["screen_score"].is_number());
    let full = &searched().1["ranking"][0];
    assert_eq!(ranking[0]["region"], full["region"], "the shortlisted shape's region is the full search's");
    // A .dsscreen is the whole library; a wrong extension or a damaged file is a clear error.
    let both = bin().args(["search", "--quiet"]).arg(d.join("partial.off")).arg(&screen).arg(d.join("library")).output().unwrap();
    assert_eq!(both.status.code(), Some(2), "{}", String::from_utf8_lossy(&both.stderr));
    let bad = out_dir.join("bad.dsscreen");
    std::fs::write(&bad, b"DSSCREEN-truncated").unwrap();
    let damaged = bin().args(["search", "--quiet"]).arg(d.join("partial.off")).arg(&bad).output().unwrap();
    assert!(!damaged.status.success());
    assert!(String::from_utf8_lossy(&damaged.stderr).contains("bad.dsscreen"), "{}", String::from_utf8_lossy(&damaged.stderr));
}

/// A shortlist of 3 of 4 shapes (the partial's own figure twice) is localized quickly and
/// the best two (tied, so the second is close behind) again in full: the table marks the quick
/// one, the JSON says which is which.
#[test]
fn a_shortlist_is_localized_quickly_and_its_best_two_in_full() {
    let d = library();
    let json = tmp("two-stage").join("ranking.json");
    let lib = d.join("library");
    let out = run(bin()
        .args(["search", "--quiet", "--shortlist", "3"])
        .arg(d.join("partial.off"))
        .args([lib.join("figure.off"), lib.join("quadruped.off"), lib.join("horned.off"), lib.join("figure.off")])
        .args(LIGHT)
        .arg("--json")
        .arg(&json));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("4 shapes screened, the 3 best localized quickly and the 2 best of those in full"), "{stdout}");
    assert_eq!(stdout.matches("(quick)").count(), 1, "{stdout}");
    let ranking = read_json(&json)["ranking"].clone();
    let quick: Vec<bool> = (0..4).map(|i| ranking[i]["quick"].as_bool().unwrap()).collect();
    assert_eq!(quick, [false, false, true, false], "{ranking}");
    assert!(ranking[0]["shape"].as_str().unwrap().ends_with("figure.off") && ranking[1]["shape"].as_str().unwrap().ends_with("figure.off"));
    assert!(ranking[3]["score"].is_null() && ranking[3]["screen_score"].is_number());
    // The search's confidence beside the localization's own; none for a shape screened out.
    for i in 0..3 {
        let (c, own) = (ranking[i]["confidence"].as_f64().unwrap(), ranking[i]["localization_confidence"].as_f64().unwrap());
        assert!((0.0..=1.0).contains(&c) && (0.0..=1.0).contains(&own), "{ranking}");
    }
    assert!(ranking[3]["confidence"].is_null() && ranking[3]["localization_confidence"].is_null());
}
