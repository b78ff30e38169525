//! The host static library from C: the system C compiler (`$CC`, else `cc`) builds
//! `tests/c/trace.c` and the docs' example (`examples/host/example.c`, included verbatim in
//! docs/c-api.md) against `include/maglev.h` and `libmaglev_c_api.a`, runs them, and their
//! output must be what `maglev_core::Law` gives on the same inputs, bit for bit. The expected
//! lines are computed here from the core directly (its own parameter constructors, its own
//! `Law::update`), not through the C API's Rust code.

use maglev_core::gap::Geometry;
use maglev_core::gap_control::GapParams;
use maglev_core::law::state::StateParams;
use maglev_core::scalar::I4F28;
use maglev_core::{Law, LawKind, LawParams, Measurement, Output, ParamError, Params, Scalar};
use std::fmt::Write;
use std::path::{Path, PathBuf};
use std::process::Command;

const STEPS: usize = 200;

/// The staticlib cargo built with this test: the newest `libmaglev_c_api-*.a` beside the
/// test binary (the lib is rebuilt before its tests whenever it changed).
fn staticlib() -> PathBuf {
    let exe = std::env::current_exe().expect("test binary path");
    let deps = exe.parent().expect("deps directory");
    let mut libs: Vec<_> = std::fs::read_dir(deps)
        .expect("read deps")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            let name = p.file_name().and_then(|n| n.to_str()).unwrap_or("");
            name.starts_with("libmaglev_c_api-") && name.ends_with(".a")
        })
        .collect();
    libs.sort_by_key(|p| std::fs::metadata(p).and_then(|m| m.modified()).ok());
    libs.pop()
        .expect("cargo builds libmaglev_c_api.a (crate-type staticlib) for the tests")
}

/// Compiles and links one C file against the header and the staticlib; returns its stdout.
fn build_and_run(src: &Path, name: &str) -> String {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let exe = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let cc = std::env::var("CC").unwrap_or_else(|_| "cc".into());
    let status = Command::new(&cc)
        .args(["-std=c11", "-O2", "-Wall", "-Wextra", "-Werror", "-I"])
        .arg(dir.join("include"))
        .arg(src)
        .arg(staticlib())
        // `cargo rustc -p maglev-c-api --crate-type staticlib -- --print native-static-libs`
        .args([
            "-lgcc_s",
            "-lutil",
            "-lrt",
            "-lpthread",
            "-lm",
            "-ldl",
            "-lc",
            "-o",
        ])
        .arg(&exe)
        .status()
        .unwrap_or_else(|e| panic!("run the C compiler {cc}: {e}"));
    assert!(status.success(), "{cc} failed on {}", src.display());
    let out = Command::new(&exe).output().expect("run the C program");
    assert!(out.status.success(), "{} exited with {}", name, out.status);
    String::from_utf8(out.stdout).expect("ASCII output")
}

fn gap(k: usize) -> f64 {
    match k {
        150 => 0.0,
        170 => 100.0,
        180 => f64::NAN,
        _ => 1.0 + 0.002 * (((k * 37) % 41) as f64 - 20.0),
    }
}

fn accel(k: usize) -> f64 {
    0.01 * (((k * 13) % 17) as f64 - 8.0)
}

/// The README's state gains, EMS, at the default rates.
fn readme_state() -> StateParams {
    StateParams {
        kp: 51600.0,
        kd: 1600.0,
        ka: 40.0,
        ki: 4300.0,
        kc: 10.0,
        v_max: 500.0,
        rate_hz: StateParams::RATE_HZ,
        observer_hz: StateParams::OBSERVER_HZ,
        geometry: Geometry::Ems,
    }
}

/// The trace's laws as the core builds them: the README's state gains, and smaller ones with a
/// 40 Hz observer that Q4.28 can carry.
fn laws() -> [(&'static str, LawParams); 4] {
    let magnet = Params::paper_wheel(1e-3);
    let state = readme_state();
    [
        ("paper", LawKind::Paper),
        ("gap-loop", LawKind::GapLoop(GapParams::designed())),
        ("state", LawKind::State(state)),
        (
            "state-small",
            LawKind::State(StateParams {
                kp: 20000.0,
                kd: 1000.0,
                ka: 20.0,
                ki: 3000.0,
                kc: 5.0,
                v_max: 300.0,
                observer_hz: 40.0,
                ..state
            }),
        ),
    ]
    .map(|(n, kind)| (n, LawParams { magnet, kind }))
}

/// Q4.28 of `x` computed here (round half away from zero, saturating).
fn q28(x: f64) -> I4F28 {
    I4F28::from_bits((x * (1u64 << 28) as f64).round() as i32)
}

fn expected<S: Scalar>(
    name: &str,
    tag: &str,
    lp: &LawParams,
    conv: fn(f64) -> S,
    bits: fn(S) -> u32,
) -> String {
    let mut s = String::new();
    let law: Law<S> = match lp.compile() {
        Ok(law) => law,
        // MAGLEV_ERROR_STATE_UNREPRESENTABLE in include/maglev.h: a state-law coefficient.
        Err(ParamError::Unrepresentable { field, .. })
            if field.law == Some(maglev_core::LawName::State) =>
        {
            return format!("{name} {tag} init 34\n")
        }
        // MAGLEV_ERROR_UNREPRESENTABLE in include/maglev.h.
        Err(ParamError::Unrepresentable { .. }) => return format!("{name} {tag} init 29\n"),
        Err(e) => panic!("{name} {tag}: {e}"),
    };
    let mut st = law.equilibrium_state(lp.magnet.h0);
    writeln!(s, "{name} {tag} init 0").unwrap();
    for k in 1..=STEPS {
        let m = Measurement {
            gap: conv(gap(k)),
            accel: Some(conv(accel(k))),
            current: None,
        };
        let o: Output<S> = law.update(&mut st, m);
        writeln!(
            s,
            "{name} {tag} {k:03} rc=0 g={:08x} F={:08x} i={:08x} v={:08x} st={:02x}",
            bits(o.g),
            bits(o.force),
            bits(o.current),
            bits(o.voltage),
            o.status.0
        )
        .unwrap();
    }
    s
}

#[test]
fn c_trace_through_the_api_equals_the_rust_law_bit_for_bit() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let got = build_and_run(&dir.join("tests/c/trace.c"), "maglev-c-trace");
    let mut want = String::new();
    for (name, lp) in laws() {
        want += &expected::<f32>(name, "f32", &lp, |x| x as f32, f32::to_bits);
        want += &expected::<I4F28>(name, "q28", &lp, q28, |x| x.to_bits() as u32);
    }
    // Every law runs in both variants but the README's state gains in Q4.28 (refused).
    assert_eq!(want.lines().count(), 7 * (STEPS + 1) + 1);
    assert!(want.contains("state q28 init 34\n"));
    for (i, (g, w)) in got.lines().zip(want.lines()).enumerate() {
        assert_eq!(g, w, "line {}", i + 1);
    }
    assert_eq!(got.lines().count(), want.lines().count());
    // The trace reaches the events it was built for, in every law.
    for ev in ["st=01", "st=10"] {
        assert!(got.contains(ev), "no step with {ev}");
    }
}

#[test]
fn the_docs_example_is_the_compiled_file_and_gives_the_law_s_numbers() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let src = dir.join("examples/host/example.c");
    let text = std::fs::read_to_string(&src).expect("example.c");
    let docs = std::fs::read_to_string(dir.join("../docs/c-api.md")).expect("docs/c-api.md");
    assert!(
        docs.contains(&format!("```c\n{text}```")),
        "docs/c-api.md must hold examples/host/example.c verbatim in a ```c block"
    );
    assert!(text.lines().count() <= 20);
    let got = build_and_run(&src, "maglev-c-example");
    let lp = LawParams {
        magnet: Params::paper(36787.5, 1e-3),
        kind: LawKind::GapLoop(GapParams::designed()),
    };
    let law: Law<f32> = lp.compile().unwrap();
    let mut st = law.equilibrium_state(lp.magnet.h0);
    let mut want = String::new();
    for k in 1..=5 {
        let o = law.update(&mut st, Measurement::gap(1.0f32 + 0.01f32 * k as f32));
        let (f, i) = (o.force as f64 * 36787.5, o.current as f64 * 43.0);
        writeln!(want, "{k} {f:.3} N {i:.4} A").unwrap();
    }
    assert_eq!(got, want);
}

/// `tests/c/guidance.c`: the guidance law through the C API equals the core's `GuidanceLaw`
/// on the same trace, bit for bit (one control period per update: the firmware's case), and
/// the refusals name their fields.
#[test]
fn c_guidance_trace_equals_the_core_guidance_law_bit_for_bit() {
    use maglev_core::law::guidance::{GuidanceParams, PairMeasurement};
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let got = build_and_run(&dir.join("tests/c/guidance.c"), "maglev-c-guidance");
    let magnet = Params::paper(10000.0, 1e-4);
    let timing = readme_state();
    let gains = GuidanceParams {
        kp: 20000.0,
        kd: 900.0,
        ka: 25.0,
        ki: 3000.0,
        kc: 8.0,
    };
    let law = gains.compile::<f32>(&timing, &magnet).unwrap();
    let mut st = law.equilibrium(1e-4);
    let mut want = String::from("guidance init 0\n");
    let mut moved = 0.0f32;
    for k in 1..=STEPS {
        let d = 0.01 + 0.004 * (((k * 37) % 41) as f64 - 20.0) / 20.0;
        let a = 0.01 * (((k * 13) % 17) as f64 - 8.0);
        let m = PairMeasurement {
            d: d as f32,
            accel: (k % 3 != 0).then_some(a as f32),
        };
        let o = law.update(&mut st, m, Geometry::Ems);
        moved = moved.max((o.left.voltage - o.right.voltage).abs());
        writeln!(
            want,
            "guidance {k:03} rc=0 vl={:08x} vr={:08x} Fl={:08x} Fr={:08x} Fy={:08x} st={:02x}",
            o.left.voltage.to_bits(),
            o.right.voltage.to_bits(),
            o.left.force.to_bits(),
            o.right.force.to_bits(),
            o.force_y.to_bits(),
            o.status.0
        )
        .unwrap();
    }
    // MAGLEV_ERROR_GUIDANCE_KD and MAGLEV_ERROR_LAW in include/maglev.h; an uninitialised
    // law (the failed init marked it) is MAGLEV_ERROR_NOT_INITIALIZED.
    want += "bad kd 37 guidance.kd_V_s_per_m\npaper law 14 law\nuninitialised 31\n";
    assert!(moved > 0.01, "the trace moves the pair: {moved}");
    for (i, (g, w)) in got.lines().zip(want.lines()).enumerate() {
        assert_eq!(g, w, "line {}", i + 1);
    }
    assert_eq!(got.lines().count(), want.lines().count());
}
