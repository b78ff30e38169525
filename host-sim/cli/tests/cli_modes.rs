//! `maglev modes`: its JSON and CSV against the closed-form Timoshenko frequencies, and its
//! one-line errors.

#[path = "../../sim/tests/timoshenko/mod.rs"]
mod timoshenko;
use maglev_sim::physics::guideway::BeamSection;
use std::f64::consts::PI;
use timoshenko::{lateral_omega, rel, vertical_omega, L};

/// `maglev modes --format json`: keys exactly `index`, `frequency_hz`, `kind`; the first
/// bending and torsion frequencies within 0.01 % and 0.2 % of the closed forms.
#[test]
fn modes_cli_json_matches_closed_form() {
    use maglev::cli::modes::{render, Args, Format};
    let args = Args {
        elements: 20,
        count: 12,
        format: Format::Json,
        viaduct: None,
        scenario: None,
        sets: Vec::new(),
    };
    let v: serde_json::Value = serde_json::from_str(&render(&args).unwrap()).unwrap();
    let rows = v.as_array().unwrap();
    assert_eq!(rows.len(), 12);
    for (i, r) in rows.iter().enumerate() {
        let o = r.as_object().unwrap();
        let mut keys: Vec<&str> = o.keys().map(|k| k.as_str()).collect();
        keys.sort();
        assert_eq!(keys, ["frequency_hz", "index", "kind"]);
        assert_eq!(o["index"].as_u64(), Some(i as u64 + 1));
    }
    let first = |kind: &str| {
        rows.iter()
            .find(|r| r["kind"] == kind)
            .and_then(|r| r["frequency_hz"].as_f64())
            .unwrap()
    };
    let s = BeamSection::paper_4_2();
    let rho = s.mass_per_length / s.area;
    let torsion = (s.shear_modulus * s.torsion_constant / (rho * (s.iy + s.iz))).sqrt() / (2.0 * L);
    let bending = vertical_omega(&s, 1) / (2.0 * PI);
    assert!(rel(first("bending-z"), bending) < 1e-4);
    assert!(rel(first("bending-y"), lateral_omega(&s, 1) / (2.0 * PI)) < 1e-4);
    assert!(rel(first("torsion"), torsion) < 2e-3);
    let csv = render(&Args {
        elements: 20,
        count: 3,
        format: Format::Csv,
        viaduct: None,
        scenario: None,
        sets: Vec::new(),
    })
    .unwrap();
    assert_eq!(csv.lines().next(), Some("index,frequency_hz,kind"));
    assert_eq!(csv.lines().count(), 4);
}

/// Bad arguments give one-line errors.
#[test]
fn modes_cli_rejects_bad_arguments() {
    use maglev::cli::modes::{render, Args, Format};
    for (elements, count) in [(0, 12), (20, 0), (20, 120), (2, 12)] {
        let e = render(&Args {
            elements,
            count,
            format: Format::Csv,
            viaduct: None,
            scenario: None,
            sets: Vec::new(),
        })
        .unwrap_err();
        assert!(matches!(e, maglev_sim::Error::Invalid { .. }), "{e:?}");
        assert!(!e.to_string().contains('\n'), "{e}");
    }
    // 119 free DOFs with 20 elements: the largest valid count.
    assert!(render(&Args {
        elements: 20,
        count: 119,
        format: Format::Csv,
        viaduct: None,
        scenario: None,
        sets: Vec::new(),
    })
    .is_ok());
}
