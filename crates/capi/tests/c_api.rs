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

/// Compiles `source` (relative to the crate) with `compiler` and `flags`, links the shared
/// library, runs it with `args`; its standard output.
fn compile_and_run(compiler: &str, flags: &[&str], source: &str) -> String {
    compile_and_run_with(compiler, flags, source, &[])
}

fn compile_and_run_with(compiler: &str, flags: &[&str], source: &str, args: &[&str]) -> String {
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
    let run = Command::new(&out)
        .args(args)
        .output()
        .expect("run the test program");
    let _ = std::fs::remove_file(&out);
    let stdout = String::from_utf8_lossy(&run.stdout).to_string();
    assert!(
        run.status.success(),
        "{source} failed:\n{stdout}{}",
        String::from_utf8_lossy(&run.stderr)
    );
    stdout
}

#[test]
fn the_c_test_passes() {
    print!(
        "{}",
        compile_and_run(
            "cc",
            &["-std=c99", "-Wall", "-Wextra", "-Werror", "-O1"],
            "tests/c/plan_test.c",
        )
    );
}

#[test]
fn the_cpp_test_passes() {
    print!(
        "{}",
        compile_and_run(
            "c++",
            &["-std=c++17", "-Wall", "-Wextra", "-Werror", "-O1"],
            "tests/cpp/plan_test.cpp",
        )
    );
}

/// `examples/c/plan_costmap.c` on the bundled warehouse map: a Nav2-like inflated costmap of
/// a map_server map, planned through the C interface; the path leaves from the start and
/// ends on the goal.
#[test]
fn the_costmap_example_plans_on_the_bundled_map() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    let yaml = format!("{root}/meshes/warehouse_map.yaml");
    let out = compile_and_run_with(
        "cc",
        &["-std=c99", "-Wall", "-Wextra", "-Werror", "-O2"],
        "../../examples/c/plan_costmap.c",
        &[&yaml, "16.5", "1.5", "-0.75", "-0.5"],
    );
    let poses: Vec<Vec<f64>> = out
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| {
            l.split_whitespace()
                .filter_map(|v| v.parse().ok())
                .collect()
        })
        .collect();
    println!("{}", out.lines().next().unwrap_or_default());
    assert!(poses.len() >= 2, "{out}");
    let (first, last) = (&poses[0], &poses[poses.len() - 1]);
    assert!(
        (first[0] + 0.75).abs() < 1e-4 && (first[1] + 0.5).abs() < 1e-4,
        "{first:?}"
    );
    assert!(
        (last[0] - 16.5).abs() < 1e-4 && (last[1] - 1.5).abs() < 1e-4,
        "{last:?}"
    );
}

/// `tests/c/random_test.c`: random costmaps (1×1 to 300×300), costs, options and poses (NaN,
/// infinities, huge values; resolutions of zero, below zero, 1e-12 and 1e9): every call
/// returns a status of the contract, never a crash. Three seeds.
#[test]
fn random_costmaps_and_poses_always_get_a_status() {
    for seed in ["1", "2", "3"] {
        let out = compile_and_run_with(
            "cc",
            &["-std=c99", "-Wall", "-Wextra", "-Werror", "-O1"],
            "tests/c/random_test.c",
            &[seed],
        );
        print!("seed {seed}: {out}");
    }
}
