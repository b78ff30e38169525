//! Verdicts: a receiver's levels held against two published sets of criteria (docs/ground.md,
//! "Verdicts", which gives the tables, their sources and what the model leaves out).
//!
//! Why two: the FTA manual judges annoyance of people (rms velocity level in VdB, by land use
//! and how often events occur); DIN 4150-3 judges damage to buildings (peak particle velocity
//! at the foundation, by building type and frequency). An assessment of a new line reports
//! both.
//!
//! - **FTA** (Transit Noise and Vibration Impact Assessment Manual, FTA Report No. 0123,
//!   2018, Table 6-3, ground-borne vibration impact criteria for the general assessment):
//!   the overall maximum 1-s rms velocity level (VdB) against [`FTA_GENERAL_VDB`]. A level
//!   above the criterion is an impact; at or below it, none.
//! - **DIN 4150-3** (Table 1, short-term vibration, foundation): the PPV against the
//!   guideline value at the dominant frequency, [`din_guideline`] (linear between the table's
//!   frequencies). Above the guideline value: exceeded.

use super::levels::{vdb, ReceiverLevels};
use serde::Serialize;
use serde_json::{json, Map, Value};

/// FTA land-use categories 1, 2, 3 (rows) × frequent, occasional, infrequent events (columns),
/// VdB re 1 µin/s.
pub const FTA_GENERAL_VDB: [[f64; 3]; 3] =
    [[65.0, 65.0, 65.0], [72.0, 75.0, 80.0], [75.0, 78.0, 83.0]];
/// The land-use categories' short names, as in summary.json.
pub const FTA_CATEGORIES: [&str; 3] = ["category_1", "category_2", "category_3"];
/// The event frequencies (frequent > 70 events a day, occasional 30–70, infrequent < 30).
pub const FTA_EVENTS: [&str; 3] = ["frequent", "occasional", "infrequent"];

/// DIN 4150-3 Table 1, foundation, short-term vibration: per building type 1, 2, 3 the
/// guideline PPV (m/s) at (and below) 10 Hz, at 50 Hz and at 100 Hz.
pub const DIN_FOUNDATION: [[f64; 3]; 3] = [
    [20e-3, 40e-3, 50e-3],
    [5e-3, 15e-3, 20e-3],
    [3e-3, 8e-3, 10e-3],
];
/// The building types' short names, as in summary.json.
pub const DIN_TYPES: [&str; 3] = ["type_1", "type_2", "type_3"];

/// The DIN 4150-3 guideline PPV (m/s) for building type `t` (0, 1, 2) at frequency `f` (Hz):
/// the table's value at 10 Hz below 10 Hz, linear from 10 to 50 and from 50 to 100 Hz, the
/// 100 Hz value above.
pub fn din_guideline(t: usize, f: f64) -> f64 {
    let [v10, v50, v100] = DIN_FOUNDATION[t];
    if f <= 10.0 {
        v10
    } else if f <= 50.0 {
        v10 + (v50 - v10) * (f - 10.0) / 40.0
    } else if f <= 100.0 {
        v50 + (v100 - v50) * (f - 50.0) / 50.0
    } else {
        v100
    }
}

/// One verdict: the criterion, the measured value, and whether it is exceeded.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Verdict {
    pub criterion: f64,
    pub value: f64,
    pub exceeds: bool,
}

impl Verdict {
    fn new(value: f64, criterion: f64) -> Self {
        Verdict {
            criterion,
            value,
            exceeds: value > criterion,
        }
    }
}

/// The FTA verdicts of an overall maximum 1-s level `vdb`, [category][events].
pub fn fta(vdb: f64) -> [[Verdict; 3]; 3] {
    FTA_GENERAL_VDB.map(|row| row.map(|c| Verdict::new(vdb, c)))
}

/// The DIN 4150-3 verdicts of a PPV `ppv` (m/s) at dominant frequency `f` (Hz), per
/// building type.
pub fn din(ppv: f64, f: f64) -> [Verdict; 3] {
    [0, 1, 2].map(|t| Verdict::new(ppv, din_guideline(t, f)))
}

/// summary.json's `ground`: per receiver its name, position, overall levels, PPV and the
/// verdicts, and the sources of the criteria.
pub fn summary(names: &[String], points: &[[f64; 2]], levels: &[ReceiverLevels]) -> Value {
    let receivers: Vec<Value> = names
        .iter()
        .zip(points)
        .zip(levels)
        .map(|((name, p), l)| {
            let running = l.overall_max_running_db;
            let fta_v = running.map(|db| {
                let v = fta(vdb(db));
                let mut m = Map::new();
                for (c, row) in FTA_CATEGORIES.iter().zip(v) {
                    let mut e = Map::new();
                    for (ev, verdict) in FTA_EVENTS.iter().zip(row) {
                        e.insert(ev.to_string(), json!(verdict));
                    }
                    m.insert(c.to_string(), Value::Object(e));
                }
                Value::Object(m)
            });
            let din_v = l.dominant_hz.map(|f| {
                let mut m = Map::new();
                for (t, v) in DIN_TYPES.iter().zip(din(l.ppv, f)) {
                    m.insert(t.to_string(), json!(v));
                }
                Value::Object(m)
            });
            json!({
                "name": name,
                "x_m": p[0],
                "y_m": p[1],
                "overall_max_1s_vdb": running.map(vdb),
                "overall_max_1s_db_re_1e-9_m_per_s": running,
                "overall_record_vdb": l.overall_record_db.map(vdb),
                "ppv_m_per_s": l.ppv,
                "ppv_t_s": l.ppv_t,
                "dominant_band_hz": l.dominant_hz,
                "fta_vdb": fta_v,
                "din4150_3_m_per_s": din_v,
            })
        })
        .collect();
    json!({
        "levels": "ground-levels.csv",
        "levels_method": crate::ground::levels::levels_method(),
        "fta": "FTA Report No. 0123 (2018), Table 6-3, general assessment: overall maximum 1-s rms level (VdB re 1 uin/s) > criterion = impact; categories 1, 2, 3 x frequent, occasional, infrequent events",
        "din4150_3": "DIN 4150-3 Table 1, foundation, short-term: PPV (vertical) > guideline value at the dominant band's frequency = exceeded; building types 1, 2, 3",
        "receivers": receivers,
    })
}
