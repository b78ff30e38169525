//! Cross-check of the QEMU golden files against the host build of the core.
//!
//! `golden/qemu-m4.txt` and `golden/qemu-m0.txt` are what the bare-metal images print in QEMU
//! (CI diffs the images' output against them). Here every trace line is recomputed on the
//! host, directly with `maglev_core` (not through `board::selftest::run`): the gap is read
//! from the line itself, the controller is compiled from the line's configuration, and the
//! state and output bits must match exactly. I4F28 is integer arithmetic, so bit-identity is
//! required by construction; f32 is required bit-identical too, because the update uses only
//! IEEE +, −, ×, ÷ (correctly rounded on the Cortex-M4 FPU and on the host's SSE alike) and
//! Rust never fuses a multiply and an add into an FMA on its own (docs/hil.md).
use maglev_core::scalar::I4F28;
use maglev_core::{Levitation, Output, Scalar, State};
use maglev_firmware_sim::board::selftest::{gap, Bits, Config, STEPS};

const M4: &str = include_str!("../golden/qemu-m4.txt");
const M0: &str = include_str!("../golden/qemu-m0.txt");

/// One parsed trace line: `<type>/<tag> <k> h=.. x=.. y=.. v=.. F=.. i=.. st=..`.
struct Line<'a> {
    scalar: &'a str,
    tag: &'a str,
    k: usize,
    fields: [u32; 7],
}

fn parse(line: &str) -> Option<Line<'_>> {
    let mut words = line.split(' ');
    let (scalar, tag) = words.next()?.split_once('/')?;
    let k = words.next()?.parse().ok()?;
    let mut fields = [0u32; 7];
    let names = ["h", "x", "y", "v", "F", "i", "st"];
    for (slot, name) in fields.iter_mut().zip(names) {
        let (n, hex) = words.next()?.split_once('=')?;
        assert_eq!(n, name, "field order in {line:?}");
        *slot = u32::from_str_radix(hex, 16).ok()?;
    }
    Some(Line {
        scalar,
        tag,
        k,
        fields,
    })
}

fn lines<'a>(golden: &'a str, scalar: &str, tag: &str) -> Vec<Line<'a>> {
    golden
        .lines()
        .filter_map(parse)
        .filter(|l| l.scalar == scalar && l.tag == tag)
        .collect()
}

/// Recomputes both runs of scalar `S` from their golden lines; returns the lines checked.
fn check_runs<S: Bits>(golden: &str, which: &str, from_bits: fn(u32) -> S) -> usize {
    let mut checked = 0;
    for cfg in Config::ALL {
        let run = lines(golden, S::NAME, cfg.tag());
        let name = format!("{which}: {}/{}", S::NAME, cfg.tag());
        assert_eq!(run.len(), STEPS, "{name}: lines");
        let p = cfg.params();
        let ctrl: Levitation<S> = p.compile().expect("compiles on the host");
        let mut st: State<S> = ctrl.initial_state(p.h0);
        for (n, l) in run.iter().enumerate() {
            assert_eq!(l.k, n + 1, "{name}: step numbering");
            let out: Output<S> = ctrl.update(&mut st, from_bits(l.fields[0]));
            let want = [
                st.x.bits(),
                st.y.bits(),
                st.v.bits(),
                out.force.bits(),
                out.current.bits(),
                out.status.0 as u32,
            ];
            // Bit 0x80 of st= (the image's conversion of the gap saturated) is not the core's.
            let f = &l.fields;
            let got = [f[1], f[2], f[3], f[4], f[5], f[6] & 0x7f];
            assert_eq!(got, want, "{name} step {}", l.k);
            checked += 1;
        }
    }
    checked
}

fn i4f28(b: u32) -> I4F28 {
    I4F28::from_bits(b as i32)
}

#[test]
fn m4_golden_matches_host_f32_bit_for_bit() {
    assert_eq!(check_runs::<f32>(M4, "qemu-m4", f32::from_bits), 2 * STEPS);
}

#[test]
fn m4_golden_matches_host_i4f28_bit_for_bit() {
    assert_eq!(check_runs::<I4F28>(M4, "qemu-m4", i4f28), 2 * STEPS);
}

#[test]
fn m0_golden_matches_host_i4f28_bit_for_bit() {
    assert_eq!(check_runs::<I4F28>(M0, "qemu-m0", i4f28), 2 * STEPS);
}

#[test]
fn m0_and_m4_fixed_point_lines_are_identical() {
    let fixed = |g: &str| -> Vec<String> {
        g.lines()
            .filter(|l| l.starts_with("i4f28/"))
            .map(str::to_owned)
            .collect()
    };
    assert_eq!(fixed(M0).len(), 2 * STEPS);
    assert_eq!(fixed(M0), fixed(M4));
}

#[test]
fn golden_gaps_are_the_trace() {
    // The h= field is the trace converted once; a golden file of another trace fails here.
    for l in M4.lines().chain(M0.lines()).filter_map(parse) {
        let mut ov = false;
        let want = match l.scalar {
            "f32" => f32::from_f64(gap(l.k), &mut ov).bits(),
            _ => I4F28::from_f64(gap(l.k), &mut ov).bits(),
        };
        assert_eq!(l.fields[0], want, "step {}", l.k);
        assert_eq!(l.fields[6] & 0x80 != 0, ov, "step {}", l.k);
    }
}

#[test]
fn golden_files_report_calibration_and_counts() {
    for (g, runs) in [(M4, 4), (M0, 2)] {
        assert!(g.contains("500 nops - 100 nops = 400 (want 400)"));
        let counted = g
            .lines()
            .filter(|l| l.starts_with("insns ") && l.contains(" update: nominal "))
            .count();
        assert_eq!(counted, runs);
    }
}
