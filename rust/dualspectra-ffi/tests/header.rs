//! The committed C header `cpp/include/dualspectra/dualspectra.h` must be exactly what cbindgen
//! generates from `src/c_abi.rs` with `cbindgen.toml`. This is how the header is "checked
//! against the Rust side": any change of a signature, constant or struct on either side fails
//! here. Set `DS_BLESS_HEADER=1` to rewrite the committed header instead.

use std::path::PathBuf;

#[test]
fn committed_header_matches_cbindgen_output() {
    let crate_dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let header = crate_dir.join("../../cpp/include/dualspectra/dualspectra.h");
    let config = cbindgen::Config::from_file(crate_dir.join("cbindgen.toml")).expect("cbindgen.toml parses");
    let mut generated = Vec::new();
    cbindgen::Builder::new()
        .with_crate(&crate_dir)
        .with_config(config)
        .generate()
        .expect("cbindgen generates the header")
        .write(&mut generated);
    let generated = String::from_utf8(generated).expect("header is UTF-8");
    if std::env::var_os("DS_BLESS_HEADER").is_some() {
        std::fs::write(&header, &generated).expect("write header");
        return;
    }
    let committed = std::fs::read_to_string(&header).unwrap_or_default();
    if committed != generated {
        let first_diff = committed
            .lines()
            .zip(generated.lines())
            .position(|(a, b)| a != b)
            .unwrap_or(committed.lines().count().min(generated.lines().count()));
        panic!(
            "{} is stale (first difference at line {}); regenerate with \
             `DS_BLESS_HEADER=1 cargo test -p dualspectra-ffi --test header`",
            header.display(),
            first_diff + 1
        );
    }
}
