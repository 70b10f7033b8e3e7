//! Builds the C++ reference (cpp/reference.{h,cpp}: CGAL 5.5 + Eigen 3, bound by autocxx) when
//! its headers and libclang are found, and then sets `cfg(has_cpp_reference)`. Otherwise the
//! crate builds without it and its reference tests are skipped with a message; with
//! `DUALSPECTRA_REQUIRE_CPP_REFERENCE=1` (CI) a missing reference is a build error instead.
//! `DUALSPECTRA_NO_CPP_REFERENCE=1` builds without it (to check the skip path).
//! Search paths: `CGAL_INCLUDE_DIR`, `EIGEN3_INCLUDE_DIR`, `LIBCLANG_PATH`, then the system ones.

use std::path::{Path, PathBuf};

fn main() {
    println!("cargo::rustc-check-cfg=cfg(has_cpp_reference)");
    for f in ["cpp/reference.h", "cpp/reference.cpp", "src/lib.rs"] {
        println!("cargo:rerun-if-changed={f}");
    }
    for v in ["CGAL_INCLUDE_DIR", "EIGEN3_INCLUDE_DIR", "LIBCLANG_PATH", "DUALSPECTRA_REQUIRE_CPP_REFERENCE", "DUALSPECTRA_NO_CPP_REFERENCE"] {
        println!("cargo:rerun-if-env-changed={v}");
    }
    let required = std::env::var("DUALSPECTRA_REQUIRE_CPP_REFERENCE").is_ok_and(|v| v == "1");
    match build() {
        Ok(()) => println!("cargo:rustc-cfg=has_cpp_reference"),
        Err(why) if required => panic!("the C++ reference is required (DUALSPECTRA_REQUIRE_CPP_REFERENCE=1): {why}"),
        Err(why) => println!(
            "cargo:warning=dualspectra-reference: C++ reference (CGAL, Eigen) not built: {why}; \
             its tests are skipped (scripts/setup.sh installs what it needs)"
        ),
    }
}

fn build() -> Result<(), String> {
    if std::env::var("DUALSPECTRA_NO_CPP_REFERENCE").is_ok_and(|v| v == "1") {
        return Err("DUALSPECTRA_NO_CPP_REFERENCE=1".into());
    }
    let cgal = find_include("CGAL_INCLUDE_DIR", &["/usr/include", "/usr/local/include"], "CGAL/Weights/cotangent_weights.h")
        .ok_or("CGAL 5.5 headers not found (CGAL/Weights/cotangent_weights.h; Debian: libcgal-dev)")?;
    let eigen = find_include("EIGEN3_INCLUDE_DIR", &["/usr/include/eigen3", "/usr/local/include/eigen3"], "Eigen/Dense")
        .ok_or("Eigen 3 headers not found (Eigen/Dense; Debian: libeigen3-dev)")?;
    if !libclang_found() {
        return Err("libclang not found (set LIBCLANG_PATH; Debian: libclang-dev)".into());
    }
    let cpp = PathBuf::from("cpp");
    let mut b = autocxx_build::Builder::new("src/lib.rs", [&cpp])
        .extra_clang_args(&["-std=c++17"])
        .build()
        .map_err(|e| format!("autocxx could not bind cpp/reference.h: {e}"))?;
    b.flag_if_supported("-std=c++17")
        .flag_if_supported("-Wno-deprecated-declarations")
        .include(&cpp)
        .include(&cgal)
        .include(&eigen)
        .file("cpp/reference.cpp")
        .try_compile("dualspectra_reference_cpp")
        .map_err(|e| format!("cpp/reference.cpp did not compile: {e}"))?;
    Ok(())
}

/// The first of `$env` and `defaults` that holds `probe`.
fn find_include(env: &str, defaults: &[&str], probe: &str) -> Option<PathBuf> {
    let from_env = std::env::var_os(env).map(PathBuf::from);
    from_env
        .into_iter()
        .chain(defaults.iter().map(PathBuf::from))
        .find(|dir| dir.join(probe).is_file())
}

/// libclang where bindgen (clang-sys, loaded at run time) looks for it.
fn libclang_found() -> bool {
    let mut dirs: Vec<PathBuf> = std::env::var_os("LIBCLANG_PATH").map(PathBuf::from).into_iter().collect();
    for root in ["/usr/lib", "/usr/local/lib", "/usr/lib64"] {
        dirs.push(PathBuf::from(root));
        dirs.push(Path::new(root).join("x86_64-linux-gnu"));
        dirs.push(Path::new(root).join("aarch64-linux-gnu"));
        if let Ok(entries) = std::fs::read_dir(root) {
            dirs.extend(entries.flatten().map(|e| e.path().join("lib")).filter(|p| p.to_string_lossy().contains("llvm")));
        }
    }
    dirs.iter().any(|d| {
        std::fs::read_dir(d).is_ok_and(|entries| {
            entries.flatten().any(|e| {
                let name = e.file_name().to_string_lossy().into_owned();
                name.starts_with("libclang") && name.contains(".so") && !name.starts_with("libclang-cpp")
            })
        })
    })
}
