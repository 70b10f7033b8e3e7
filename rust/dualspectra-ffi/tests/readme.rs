//! The README's C and C++ samples are the programs `cpp/examples/readme.c` and `readme.cpp`,
//! verbatim: the only ```c block and the only ```cpp block are those files. CTest compiles
//! and runs the files (`readme_c`, `readme_cpp` in cpp/tests/CMakeLists.txt), so what the
//! README shows compiles and runs.

use std::path::Path;

/// The fenced blocks of `markdown` opened by a line "```<tag>", each block's text.
fn blocks(markdown: &str, tag: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut current: Option<String> = None;
    for line in markdown.lines() {
        match &mut current {
            None if line.strip_prefix("```") == Some(tag) => current = Some(String::new()),
            Some(_) if line.starts_with("```") => out.extend(current.take()),
            Some(text) => {
                text.push_str(line);
                text.push('\n');
            }
            None => {}
        }
    }
    out
}

#[test]
fn readme_c_and_cpp_samples_are_the_example_programs() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    for (tag, file) in [("c", "cpp/examples/readme.c"), ("cpp", "cpp/examples/readme.cpp")] {
        let program = std::fs::read_to_string(root.join(file)).unwrap();
        let shown = blocks(&readme, tag);
        assert_eq!(shown.len(), 1, "README.md should have one ```{tag} block (the program {file}), has {}", shown.len());
        assert!(
            shown[0] == program,
            "README.md's ```{tag} block differs from {file}: copy the file into the README (first differing line: {:?})",
            shown[0].lines().zip(program.lines()).find(|(a, b)| a != b)
        );
        assert!(program.contains("read"), "{file} reads its meshes from files");
    }
}

#[test]
fn the_block_reader_finds_blocks_by_tag() {
    let md = "text\n```c\nint a;\n```\n```cpp\nint b;\n\nint c;\n```\n```c\nx\n```\n";
    assert_eq!(blocks(md, "c"), ["int a;\n", "x\n"]);
    assert_eq!(blocks(md, "cpp"), ["int b;\n\nint c;\n"]);
    assert!(blocks(md, "rust").is_empty());
}
