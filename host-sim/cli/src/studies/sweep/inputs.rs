//! The files a run reads besides its scenario text (the `[support]` records), hashed so that
//! a resumed sweep notices a changed file and runs again the runs that read it.
//!
//! Why per run and not in the sweep's header: an axis may give each run its own record
//! (`axes."support.record" = […]`), and a changed file invalidates only the runs that read it.

use super::runs::fnv1a;
use crate::input::scenario::Scenario;
use crate::Result;

/// FNV-1a over each file's name and bytes, in the order the case reads them; empty when the
/// scenario reads no file (so the records of such runs are as they always were).
pub fn inputs_fnv1a(sc: &Scenario) -> Result<String> {
    let files = sc.support.as_ref().map_or_else(Vec::new, |s| s.files());
    if files.is_empty() {
        return Ok(String::new());
    }
    let mut bytes = Vec::new();
    for f in files {
        bytes.extend_from_slice(f.as_bytes());
        bytes.push(0);
        let text = crate::input::read_text(std::path::Path::new(f))?;
        bytes.extend_from_slice(&(text.len() as u64).to_le_bytes());
        bytes.extend_from_slice(text.as_bytes());
    }
    Ok(format!("{:016x}", fnv1a(&bytes)))
}
