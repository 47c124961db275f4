//! `include/harmonic_planner.h` is generated from the crate by cbindgen and committed; this
//! test regenerates it and fails when the committed one differs
//! (`HP_BLESS_HEADER=1 cargo test --release -p harmonic-planner-c --test header` rewrites it).

#[test]
fn the_committed_header_is_the_generated_one() {
    let dir = env!("CARGO_MANIFEST_DIR");
    let config =
        cbindgen::Config::from_file(format!("{dir}/cbindgen.toml")).expect("cbindgen.toml");
    let mut generated = Vec::new();
    cbindgen::Builder::new()
        .with_crate(dir)
        .with_config(config)
        .generate()
        .expect("cbindgen generates the header")
        .write(&mut generated);
    let path = format!("{dir}/include/harmonic_planner.h");
    if std::env::var_os("HP_BLESS_HEADER").is_some() {
        std::fs::write(&path, &generated).expect("write the header");
        return;
    }
    let committed = std::fs::read(&path).unwrap_or_default();
    assert!(
        committed == generated,
        "{path} is out of date: run HP_BLESS_HEADER=1 cargo test --release -p harmonic-planner-c --test header"
    );
}
