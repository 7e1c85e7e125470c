//! `fixplan bench-cluster` (below).
use anyhow::Result;

#[derive(clap::Args, Debug, Clone)]
pub struct BenchArgs {}

pub fn bench_main(_a: &BenchArgs) -> Result<()> {
    Ok(())
}
