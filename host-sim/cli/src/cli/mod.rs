//! One module per `maglev` subcommand. Each exposes `Args` (clap) and `run(Args)` returning
//! `crate::Result` or `anyhow::Result`;
//! errors are one line naming what is wrong.
pub mod accelerogram;
pub mod bands;
pub mod control;
pub mod envelope;
pub mod ground;
pub mod hil;
pub mod irregularity;
pub mod modes;
pub mod progress;
pub mod report;
pub mod run;
pub mod stability;
pub mod stdout;
pub mod sweep;
pub mod validate;

/// A core type from the word a scenario writes for it (`paper`, `accurate`, `gap-loop`, …), by
/// the type's own serde names: the command line and the scenario accept the same words.
pub fn core_word<T: serde::de::DeserializeOwned>(word: &str) -> Result<T, String> {
    use serde::de::IntoDeserializer;
    T::deserialize(word.into_deserializer()).map_err(|e: serde::de::value::Error| e.to_string())
}
