//! The input's cost is known before it is paid (docs/scenarios.md, "Input size"): a 60 MB
//! scenario, under the 64 MiB file cap, is refused in one line within a 2 GiB address-space
//! limit (the code of 4d4c133 parsed it whole and aborted there, after 4.5 GB unlimited).

use std::process::Command;

#[test]
fn a_60_mb_scenario_is_refused_in_one_line_within_2_gib() {
    let dir = std::env::temp_dir().join(format!("maglev-input-size-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("big.toml");
    let base = include_str!("../../sim/scenarios/paper-4.2.toml");
    let n = 60_000_000 / 2;
    let mut text = String::with_capacity(2 * n + base.len() + 16);
    text.push_str("zz = [");
    for _ in 0..n {
        text.push_str("1,");
    }
    text.push_str("1]\n");
    text.push_str(base);
    std::fs::write(&path, &text).unwrap();
    drop(text);
    let out = Command::new("sh")
        .arg("-c")
        .arg("ulimit -v 2097152 && exec \"$0\" run \"$1\" --out \"$2\"")
        .arg(env!("CARGO_BIN_EXE_maglev"))
        .arg(&path)
        .arg(dir.join("out"))
        .output()
        .unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains("more than the 4 MiB a TOML input may have"),
        "{err}"
    );
}
