//! The input fuzz target's harness: how a fuzz input becomes a scenario text and `--set`
//! overrides, and what must hold for every input (docs/scenarios.md, "Fuzzing the input path").
//!
//! Input shape: `TEXT [0x00 SET (\n SET)*]`. `TEXT` (UTF-8, invalid bytes replaced) is the
//! scenario's TOML, or the name of a bundled scenario (`paper-5`), which stands for its text as
//! on the command line (`maglev run paper-5 --set ...`). After the first NUL byte, every
//! non-empty line is one `--set key=value` (NUL cannot occur in a TOML text or in an argument,
//! so the split is unambiguous).
//!
//! Properties, for every input: `scenario::parse` and `Case::new` return without panicking,
//! within the per-input time limit and the allocation limit `.ci/fuzz` gives libFuzzer; an
//! error is one line (`maglev_sim::Error`: "every failure a user can meet ends as one
//! line on stderr"); a case that resolves can be recorded (`Case::record`, the run record).
//!
//! The designs (`law = "gap-loop"`, `[controller.state] design = true`) are not part of the
//! input path: `Case::new` records them as data and `maglev_sim::studies::design::resolve` runs
//! them afterwards (a search over the vehicle's linear model, 0.1 s to minutes), so the
//! target exercises every key and check of the case at the input path's own speed.
use maglev_sim::input::case::Case;
use maglev_sim::input::scenario::{self, BUNDLED};

/// The scenario text (or bundled name) and the `--set` lines of a fuzz input.
pub fn split(data: &[u8]) -> (String, Vec<String>) {
    let (text, sets) = match data.iter().position(|&b| b == 0) {
        Some(i) => (&data[..i], &data[i + 1..]),
        None => (data, &[][..]),
    };
    let sets = String::from_utf8_lossy(sets)
        .split('\n')
        .filter(|s| !s.is_empty())
        .map(str::to_owned)
        .collect();
    (String::from_utf8_lossy(text).into_owned(), sets)
}

/// Runs one input through the input path and checks the properties (module docs).
pub fn check(data: &[u8]) {
    let (text, sets) = split(data);
    let (name, text) = match BUNDLED.iter().find(|(n, _)| *n == text.trim()) {
        Some((n, t)) => (*n, t.to_string()),
        None => ("fuzz-input", text),
    };
    match scenario::parse(&text, name, &sets).and_then(|sc| Case::new(sc)) {
        Ok(case) => {
            let _ = case.record();
        }
        Err(e) => {
            let msg = e.to_string();
            assert!(
                !msg.contains('\n'),
                "an error of more than one line: {msg:?}"
            );
        }
    }
}
