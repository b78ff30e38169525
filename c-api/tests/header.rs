//! The committed header `include/maglev.h` is what cbindgen makes of the sources now: CI's
//! check that it is current (`cargo test --workspace` runs it). After an API change,
//! regenerate it with `MAGLEV_UPDATE_HEADER=1 cargo test -p maglev-c-api --test header` and
//! commit it.

use std::path::Path;

#[test]
fn committed_header_is_current() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let config = cbindgen::Config::from_file(dir.join("cbindgen.toml")).expect("cbindgen.toml");
    let bindings = cbindgen::Builder::new()
        .with_crate(dir)
        .with_config(config)
        .generate()
        .expect("cbindgen parses the crate");
    let mut fresh = Vec::new();
    bindings.write(&mut fresh);
    let path = dir.join("include/maglev.h");
    if std::env::var_os("MAGLEV_UPDATE_HEADER").is_some() {
        std::fs::write(&path, &fresh).expect("write the header");
    }
    let committed = std::fs::read(&path).unwrap_or_default();
    if committed != fresh {
        let fresh = String::from_utf8_lossy(&fresh);
        let committed = String::from_utf8_lossy(&committed);
        let first = fresh
            .lines()
            .zip(committed.lines())
            .position(|(a, b)| a != b)
            .unwrap_or(fresh.lines().count().min(committed.lines().count()));
        panic!(
            "c-api/include/maglev.h is not what cbindgen makes of c-api/src (first difference at \
             line {}: generated {:?}, committed {:?}); regenerate it with \
             MAGLEV_UPDATE_HEADER=1 cargo test -p maglev-c-api --test header",
            first + 1,
            fresh.lines().nth(first),
            committed.lines().nth(first)
        );
    }
}
