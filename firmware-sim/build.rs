//! Bare-metal link setup for the QEMU images (`src/bin/qemu-*.rs`), keyed on the target so that
//! one crate builds both boards and host builds are untouched:
//! `thumbv7em-none-eabihf` → mps2-an386 (Cortex-M4), `thumbv6m-none-eabi` → lm3s6965evb
//! (Cortex-M0). The board's `memory.x` is copied where cortex-m-rt's `link.x` finds it, and the
//! linker scripts are passed to the QEMU images only (`nostd-link` brings its own `_start`).
use std::{env, fs, path::PathBuf};

/// Images linked with cortex-m-rt, and whether each also logs through defmt.
const IMAGES: &[(&str, bool)] = &[
    ("qemu-m4", false),
    ("qemu-m0", false),
    ("qemu-m4-link", false),
    ("qemu-m4-defmt", true),
    ("qemu-m4-server", false),
    ("qemu-m4-server-semi", false),
];

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed=memory");
    let target = env::var("TARGET").unwrap_or_default();
    let memory = if target.starts_with("thumbv7em") {
        "memory/mps2-an386.x"
    } else if target.starts_with("thumbv6m") {
        "memory/lm3s6965.x"
    } else {
        return; // host (or another target): nothing to link specially
    };
    let out = PathBuf::from(env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    fs::copy(memory, out.join("memory.x")).expect("copy memory.x");
    println!("cargo:rustc-link-search={}", out.display());
    for (bin, defmt) in IMAGES {
        println!("cargo:rustc-link-arg-bin={bin}=-Tlink.x");
        if *defmt {
            println!("cargo:rustc-link-arg-bin={bin}=-Tdefmt.x");
        }
    }
}
