//! What the command-line tests share: running the built `hplan`.
#![allow(dead_code)]

use assert_cmd::Command;
use serde_json::Value;

/// The built `hplan` binary, ready for arguments.
pub fn hplan() -> Command {
    Command::cargo_bin("hplan").expect("the hplan binary is built")
}

/// Runs `hplan ARGS`, which must succeed, and parses its standard output as one JSON object.
pub fn run_json(args: &[&str]) -> Value {
    let out = hplan().args(args).output().expect("hplan runs");
    assert!(
        out.status.success(),
        "hplan {args:?} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("stdout is one JSON object")
}
