//! Environment variables `FUSION__SECTION__KEY` override the configuration file. In a test
//! binary of its own, because the environment is shared by every test of a process.

use std::path::Path;

use fusion_server::config::ServerConfig;

fn example() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/fusion.example.toml"))
}

#[test]
fn environment_variables_override_the_file() {
    std::env::set_var("FUSION__FILTER__MAX_COMPONENTS", "250");
    std::env::set_var(
        "FUSION__ZENOH__CONNECT",
        "tcp/10.0.0.1:7447,tcp/10.0.0.2:7447",
    );
    std::env::set_var("FUSION__OUTPUT__JSON", "false");
    std::env::set_var("FUSION__OUTPUT__HISTORY_S", "30");
    let loaded = ServerConfig::load(Some(example()));
    std::env::remove_var("FUSION__FILTER__MAX_COMPONENTS");
    std::env::remove_var("FUSION__ZENOH__CONNECT");
    std::env::remove_var("FUSION__OUTPUT__JSON");
    std::env::remove_var("FUSION__OUTPUT__HISTORY_S");
    let loaded = loaded.unwrap();
    assert_eq!(loaded.filter.max_components, 250);
    assert!(
        !loaded.output.json,
        "output.json = false turns the JSON puts off"
    );
    assert_eq!(loaded.output.history_s, 30.0);
    assert_eq!(
        loaded.zenoh.connect,
        vec!["tcp/10.0.0.1:7447", "tcp/10.0.0.2:7447"]
    );
}
