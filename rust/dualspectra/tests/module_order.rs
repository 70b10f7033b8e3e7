//! The pipeline is the module tree: a module uses only the modules before it in
//! [`ORDER`] (unit tests excepted). Reads the sources, so a new backward import fails here.

use std::path::{Path, PathBuf};

/// The modules of `src/`, in pipeline order; `error` and `progress` serve every stage.
const ORDER: &[&str] = &[
    "error", "progress", "mesh", "geometry", "operators", "spectra", "shape", "alignment", "region", "selection",
    "localizer", "search", "evaluation",
];

fn rank(module: &str) -> Option<usize> {
    match module {
        "error" | "progress" => Some(0),
        _ => ORDER.iter().position(|m| *m == module),
    }
}

fn sources(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            sources(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// Every `crate::name` in `code`.
fn crate_paths(code: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut rest = code;
    while let Some(i) = rest.find("crate::") {
        rest = &rest[i + 7..];
        let name: String = rest.chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
        out.push(name);
    }
    out
}

#[test]
fn no_module_uses_a_later_one() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    sources(&src, &mut files);
    let mut violations = Vec::new();
    for file in &files {
        let relative = file.strip_prefix(&src).unwrap();
        let first = relative.components().next().unwrap().as_os_str().to_string_lossy().trim_end_matches(".rs").to_string();
        if first == "lib" {
            continue;
        }
        let own = rank(&first).unwrap_or_else(|| panic!("{first} (src/{}) is not in ORDER", relative.display()));
        let text = std::fs::read_to_string(file).unwrap();
        // Unit tests may use anything.
        let code = text.split("#[cfg(test)]").next().unwrap();
        // Doc comments and comments may name anything.
        let code: String = code.lines().filter(|l| !l.trim_start().starts_with("//")).collect::<Vec<_>>().join("\n");
        for used in crate_paths(&code) {
            if let Some(r) = rank(&used) {
                if r > own {
                    violations.push(format!("src/{} uses crate::{used}", relative.display()));
                }
            }
        }
    }
    assert!(violations.is_empty(), "backward imports:\n{}", violations.join("\n"));
    assert!(files.len() > 30, "read {} files", files.len());
}
