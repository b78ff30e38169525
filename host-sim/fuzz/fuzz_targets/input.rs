//! Scenario TOML and `--set` overrides through `scenario::parse` and `Case::new`: never a
//! panic, a hang or a runaway allocation; errors are one line (`maglev_sim_fuzz`).
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| maglev_sim_fuzz::check(data));
