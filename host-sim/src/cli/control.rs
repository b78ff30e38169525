//! Placeholder.
#[derive(clap::Args, Debug)]
pub struct Args {}
pub fn run(_a: Args) -> Result<(), String> {
    Err("not implemented yet".into())
}
