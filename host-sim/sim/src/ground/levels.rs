//! Levels at a ground receiver: what an environmental vibration assessment reads off a
//! receiver's vertical velocity (docs/ground.md, "Levels").
//!
//! Why here and not in `bands`: the band integration, the running rms and the references are
//! [`crate::bands`]'s (one way to do each); this module only chooses what an assessment
//! needs of them — 1/3-octave velocity levels both as the whole-record rms and as the maximum
//! 1-s running rms, in dB re 1e-9 m/s (ISO 1683) and in VdB (re 1 µin/s = 2.54e-8 m/s, the
//! FTA manual's unit), the overall (broadband) level, and the peak particle velocity with the
//! frequency of the strongest band (what DIN 4150-3 is read with).
//!
//! - **Band levels**: [`bands::analyse`] of the velocity, whole record and maximum running
//!   rms over a linear (rectangular) window of [`RUNNING_WINDOW_S`].
//! - **Overall level**: the record's mean removed, the rms over the whole record and the
//!   maximum running rms over the same window ([`bands::max_running_mean_square`]), all
//!   frequencies up to Nyquist (the signal a meter without a band filter sees).
//! - **VdB** = dB re 1e-9 m/s + 20·log10(1e-9/2.54e-8) = dB re 1e-9 m/s − 28.0967 dB.
//! - **PPV**: max |v| over the record (vertical component only: the model has no other).

use crate::bands::{self, Averaging, Band, BandsError, Level, Motion, Settings, REF_VELOCITY};

/// The VdB reference velocity, 1 µin/s in m/s.
pub const VDB_REFERENCE: f64 = 2.54e-8;
/// The running-rms window of the maximum levels (s): the FTA manual's 1-s rms.
pub const RUNNING_WINDOW_S: f64 = 1.0;

/// A level in dB re 1e-9 m/s as VdB (re 2.54e-8 m/s).
pub fn vdb(db_re_1e9: f64) -> f64 {
    db_re_1e9 + 20.0 * (REF_VELOCITY / VDB_REFERENCE).log10()
}

/// The level (dB re 1e-9 m/s) of an rms velocity (m/s); `None` for no motion.
pub fn db_re_1e9(rms: f64) -> Option<f64> {
    (rms > 0.0).then(|| 20.0 * (rms / REF_VELOCITY).log10())
}

/// One band's levels, dB re 1e-9 m/s (`None`: no energy in the band, or the record is
/// shorter than the running window).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BandRow {
    pub band: Band,
    pub record_db: Option<f64>,
    pub max_running_db: Option<f64>,
}

/// A receiver's levels.
#[derive(Clone, Debug, PartialEq)]
pub struct ReceiverLevels {
    pub bands: Vec<BandRow>,
    /// Overall rms over the whole record, dB re 1e-9 m/s.
    pub overall_record_db: Option<f64>,
    /// Overall maximum running rms, dB re 1e-9 m/s (`None` when the record is shorter than
    /// the window).
    pub overall_max_running_db: Option<f64>,
    /// Peak particle velocity |v|max (m/s) and its time (s from the record's start).
    pub ppv: f64,
    pub ppv_t: f64,
    /// Exact mid-band frequency (Hz) of the band with the highest whole-record level.
    pub dominant_hz: Option<f64>,
}

/// The levels of a velocity record `v` (m/s) sampled at `dt` (s).
pub fn of_velocity(v: &[f64], dt: f64) -> Result<ReceiverLevels, BandsError> {
    let settings = |averaging| Settings {
        input: Motion::Velocity,
        level: Level::Velocity,
        averaging,
    };
    let record = bands::analyse(v, dt, &settings(Averaging::WholeRecord))?;
    let window = (RUNNING_WINDOW_S / dt).round() as usize;
    let fits = window >= 1 && window <= v.len();
    let running = if fits {
        let s = settings(Averaging::MaxRunning {
            window_s: RUNNING_WINDOW_S,
        });
        Some(bands::analyse(v, dt, &s)?)
    } else {
        None
    };
    let rows = record
        .iter()
        .enumerate()
        .map(|(i, b)| BandRow {
            band: b.band,
            record_db: b.level_db,
            max_running_db: running.as_ref().and_then(|r| r[i].level_db),
        })
        .collect();
    let dominant_hz = record
        .iter()
        .filter_map(|b| Some((b.band, b.level_db?)))
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(b, _)| b.exact_hz());
    let mean = v.iter().sum::<f64>() / v.len() as f64;
    let dev: Vec<f64> = v.iter().map(|x| x - mean).collect();
    let ms = dev.iter().map(|x| x * x).sum::<f64>() / dev.len() as f64;
    let (j, ppv) = v
        .iter()
        .map(|x| x.abs())
        .enumerate()
        .fold((0, 0.0), |a, (j, x)| if x > a.1 { (j, x) } else { a });
    Ok(ReceiverLevels {
        bands: rows,
        overall_record_db: db_re_1e9(ms.sqrt()),
        overall_max_running_db: fits
            .then(|| db_re_1e9(bands::max_running_mean_square(&dev, window).sqrt()))
            .flatten(),
        ppv,
        ppv_t: j as f64 * dt,
        dominant_hz,
    })
}

/// How ground-levels.csv's levels are made: summary.json's `ground.levels_method` (the CSV
/// holds numbers under a plain header, so a bare `pandas.read_csv` reads it).
pub fn levels_method() -> String {
    format!(
        "vertical velocity at each receiver; IEC 61260-1 base-10 1/3-octave bands (centre_hz \
         nominal) by maglev bands' band integration; record = rms over the whole record, \
         max_1s = maximum running rms, linear window {RUNNING_WINDOW_S} s; vdb = VdB re \
         2.54e-8 m/s (1 uin/s); the overall levels (all frequencies to Nyquist) are each \
         receiver's overall_* in summary.json"
    )
}

/// ground-levels.csv: one row per receiver and band (the overall levels are in summary.json);
/// levels to 0.01 dB, an empty cell where there is no level.
pub fn csv(names: &[String], levels: &[ReceiverLevels]) -> String {
    use std::fmt::Write as _;
    let mut s = String::from(
        "receiver,centre_hz,max_1s_vdb,max_1s_db_re_1e-9_m_per_s,record_vdb,record_db_re_1e-9_m_per_s\n",
    );
    let cell = |x: Option<f64>| x.map_or(String::new(), |d| format!("{d:.2}"));
    let row = |s: &mut String, name: &str, band: &str, run: Option<f64>, rec: Option<f64>| {
        let _ = writeln!(
            s,
            "{name},{band},{},{},{},{}",
            cell(run.map(vdb)),
            cell(run),
            cell(rec.map(vdb)),
            cell(rec)
        );
    };
    for (name, l) in names.iter().zip(levels) {
        for b in &l.bands {
            let hz = format!("{}", b.band.nominal_hz());
            row(&mut s, name, &hz, b.max_running_db, b.record_db);
        }
    }
    s
}
