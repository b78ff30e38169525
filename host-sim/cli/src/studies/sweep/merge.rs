//! `sweep merge`: the shards' directories combined into one, as if the sweep had run whole.
//!
//! Why the merged results.csv is byte-identical to an unsharded run's: it is built by the
//! same function from the same records (each run's record is the same whichever process ran
//! it), in the product order that `sweep.json` fixes. The merged directory is written aside
//! and renamed into place (output/staging.rs), so it holds one complete merge or nothing.

use super::runs;
use super::store::{self, write_atomic, Header, Record};
use crate::output::Staging;
use crate::{Error, Result};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Merges sweep directories `dirs` (the shards of one spec) into `out`; returns the number of
/// runs. Every run of the spec must have a record in some shard.
pub fn merge(dirs: &[PathBuf], out: &Path) -> Result<usize> {
    let Some(first) = dirs.first() else {
        return Err(Error::invalid("sweep merge", "name at least one directory"));
    };
    let header: Header = store::read_header(first)?;
    let mut records: BTreeMap<String, (Record, &Path)> = BTreeMap::new();
    for d in dirs {
        let h = store::read_header(d)?;
        if h != header {
            return Err(Error::invalid(
                "sweep merge",
                format!(
                    "{} holds a sweep of another spec than {}; shards must come from one spec",
                    d.display(),
                    first.display()
                ),
            ));
        }
        for (id, r) in store::read_records(d)? {
            match records.get(&id) {
                Some((old, from)) if old.values != r.values || old.status != r.status => {
                    return Err(Error::invalid(
                        "sweep merge",
                        format!(
                            "run {id} has different results in {} and {}",
                            from.display(),
                            d.display()
                        ),
                    ))
                }
                Some(_) => {}
                None => {
                    records.insert(id, (r, d.as_path()));
                }
            }
        }
    }
    let spec = &header.spec;
    let all = runs::all(spec);
    let missing: Vec<&str> = all
        .iter()
        .filter(|r| !records.contains_key(&r.id))
        .map(|r| r.id.as_str())
        .collect();
    if let Some(m) = missing.first() {
        return Err(Error::invalid(
            "sweep merge",
            format!(
                "{} of {} runs have no record in the shards given (the first: {m})",
                missing.len(),
                all.len()
            ),
        ));
    }
    let records: BTreeMap<String, Record> = all
        .iter()
        .map(|r| (r.id.clone(), records[&r.id].0.clone()))
        .collect();
    let staging = Staging::sweep(out)?;
    let dir = staging.path("");
    let runs_dir = dir.join("runs");
    std::fs::create_dir_all(&runs_dir).map_err(|e| Error::io(&runs_dir, e))?;
    for run in &all {
        let json = serde_json::to_string_pretty(&records[&run.id])
            .map_err(|e| Error::parse("run record", e))?;
        write_atomic(&runs_dir.join(run.file_name()), (json + "\n").as_bytes())?;
    }
    let json = serde_json::to_string_pretty(&header).map_err(|e| Error::parse("sweep.json", e))?;
    write_atomic(&dir.join("sweep.json"), (json + "\n").as_bytes())?;
    super::publish(&dir, spec, &all, &records)?;
    staging.finish()?;
    Ok(all.len())
}
