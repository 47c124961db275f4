//! The C and C++ tests of the contract (`tests/c/*.c`, `tests/cpp/*.cpp`), compiled with this
//! machine's C and C++ compilers against the crate's shared library and run.

use std::path::{Path, PathBuf};
use std::process::Command;

/// The directory holding this build's `libharmonic_planner.so` (next to the test binary),
/// built first: cargo builds a `cdylib` for no test, so the test asks for it (the same
/// profile and target directory, so it is a no-op when the library is fresh).
fn library_dir() -> PathBuf {
    let exe = std::env::current_exe().expect("the test binary's path");
    let release = exe.components().any(|c| c.as_os_str() == "release");
    let mut cargo = Command::new(env!("CARGO"));
    cargo.args(["build", "-p", "harmonic-planner-c", "--lib"]);
    if release {
        cargo.arg("--release");
    }
    let status = cargo.status().expect("run cargo");
    assert!(status.success(), "cargo build -p harmonic-planner-c failed");
    let deps = exe.parent().expect("deps").to_path_buf();
    for dir in [
        deps.clone(),
        deps.parent().map(Path::to_path_buf).unwrap_or_default(),
    ] {
        if dir.join("libharmonic_planner.so").exists() {
            return dir;
        }
    }
    panic!("libharmonic_planner.so is not beside {}", deps.display());
}

/// Compiles `source` with `compiler` and `flags`, links the shared library, runs it.
fn compile_and_run(compiler: &str, flags: &[&str], source: &str) {
    let dir = env!("CARGO_MANIFEST_DIR");
    let lib = library_dir();
    let out = std::env::temp_dir().join(format!(
        "hp_capi_{}_{}",
        std::process::id(),
        Path::new(source)
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or("test")
    ));
    let status = Command::new(compiler)
        .args(flags)
        .arg(format!("-I{dir}/include"))
        .arg(format!("{dir}/{source}"))
        .arg(format!("-L{}", lib.display()))
        .arg(format!("-Wl,-rpath,{}", lib.display()))
        .args(["-lharmonic_planner", "-lpthread", "-lm", "-o"])
        .arg(&out)
        .status()
        .unwrap_or_else(|e| panic!("cannot run {compiler}: {e}"));
    assert!(status.success(), "{compiler} failed on {source}");
    let run = Command::new(&out).output().expect("run the test program");
    let _ = std::fs::remove_file(&out);
    print!("{}", String::from_utf8_lossy(&run.stdout));
    assert!(
        run.status.success(),
        "{source} failed:\n{}",
        String::from_utf8_lossy(&run.stderr)
    );
}

#[test]
fn the_c_test_passes() {
    compile_and_run(
        "cc",
        &["-std=c99", "-Wall", "-Wextra", "-Werror", "-O1"],
        "tests/c/plan_test.c",
    );
}

#[test]
fn the_cpp_test_passes() {
    compile_and_run(
        "c++",
        &["-std=c++17", "-Wall", "-Wextra", "-Werror", "-O1"],
        "tests/cpp/plan_test.cpp",
    );
}
