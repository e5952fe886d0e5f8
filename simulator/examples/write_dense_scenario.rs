//! Writes `scenarios/dense.toml` from `simulator::dense()` (run after changing the preset:
//! `cargo run -p simulator --release --example write_dense_scenario`).

use std::path::Path;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let header = "\
# The dense benchmark scenario: 50 targets in a 40 m × 40 m × 10 m volume, 8 sensors at
# 30 Hz each (4 cameras, 2 LIDARs, 2 position sensors), 20 clutter points per set.
#
# Generated from `simulator::dense()` by `cargo run -p simulator --release --example
# write_dense_scenario`; a test checks that the two stay identical. The format is
# documented in simulator/SCENARIOS.md.

";
    let body = simulator::dense().to_toml_string()?;
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/dense.toml");
    std::fs::write(&path, format!("{header}{body}"))?;
    println!("wrote {}", path.display());
    Ok(())
}
