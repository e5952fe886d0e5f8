//! Key builders and parsers, and the identifier rules they rely on.

use protocol::keys::{
    self as keys, alive_key, all_alive_key, all_descriptors_key, all_measurements_key,
    all_sensors_key, descriptor_key, measurements_key, sensor_key, site_key, status_key,
    tracks_json_key, tracks_key, truth_key,
};
use protocol::{
    parse_sensor_key, parse_site_key, InstanceId, ProtocolError, SensorId, SensorKeyKind, Site,
    SiteKeyKind, DEFAULT_SITE,
};

fn ids() -> (Site, SensorId) {
    (Site::new("lab-2").unwrap(), SensorId::new("cam_1").unwrap())
}

#[test]
fn sensor_keys_have_the_contract_form() {
    let (site, sensor) = ids();
    assert_eq!(
        descriptor_key(&site, &sensor),
        "fusion/lab-2/sensors/cam_1/descriptor"
    );
    assert_eq!(
        measurements_key(&site, &sensor),
        "fusion/lab-2/sensors/cam_1/measurements"
    );
    assert_eq!(
        alive_key(&site, &sensor),
        "fusion/lab-2/sensors/cam_1/alive"
    );
    assert_eq!(
        sensor_key(&site, &sensor, SensorKeyKind::Measurements),
        measurements_key(&site, &sensor)
    );
}

#[test]
fn site_and_wildcard_keys_have_the_contract_form() {
    let site = Site::default();
    assert_eq!(site.as_str(), DEFAULT_SITE);
    assert_eq!(tracks_key(&site), "fusion/default/tracks");
    assert_eq!(tracks_json_key(&site), "fusion/default/tracks/json");
    assert_eq!(status_key(&site), "fusion/default/status");
    assert_eq!(truth_key(&site), "fusion/default/truth");
    assert_eq!(site_key(&site, SiteKeyKind::Truth), truth_key(&site));
    assert_eq!(
        all_measurements_key(&site),
        "fusion/default/sensors/*/measurements"
    );
    assert_eq!(
        all_descriptors_key(&site),
        "fusion/default/sensors/*/descriptor"
    );
    assert_eq!(all_alive_key(&site), "fusion/default/sensors/*/alive");
    assert_eq!(
        all_sensors_key(&site, SensorKeyKind::Alive),
        all_alive_key(&site)
    );
}

#[test]
fn every_built_key_parses_back() {
    let (site, sensor) = ids();
    for kind in SensorKeyKind::ALL {
        let key = sensor_key(&site, &sensor, kind);
        assert_eq!(
            parse_sensor_key(&key).unwrap(),
            (site.clone(), sensor.clone(), kind)
        );
    }
    for kind in SiteKeyKind::ALL {
        let key = site_key(&site, kind);
        assert_eq!(parse_site_key(&key).unwrap(), (site.clone(), kind));
    }
}

fn sensor_key_error(key: &str) -> String {
    parse_sensor_key(key).expect_err(key).to_string()
}

#[test]
fn malformed_sensor_keys_are_rejected_with_the_reason() {
    assert_eq!(
        sensor_key_error("zenoh/default/sensors/cam1/alive"),
        r#"key "zenoh/default/sensors/cam1/alive" is not a sensor key: it does not start with "fusion/""#
    );
    assert_eq!(
        sensor_key_error("fusion/default/sensor/cam1/alive"),
        r#"key "fusion/default/sensor/cam1/alive" is not a sensor key: chunk "sensor" should be "sensors""#
    );
    assert_eq!(
        sensor_key_error("fusion/default/sensors/cam1/tracks"),
        r#"key "fusion/default/sensors/cam1/tracks" is not a sensor key: last chunk "tracks" is not descriptor, measurements or alive"#
    );
    assert_eq!(
        sensor_key_error("fusion/default/sensors/a/b/alive"),
        r#"key "fusion/default/sensors/a/b/alive" is not a sensor key: it has 4 chunks after the site, expected 3"#
    );
    assert_eq!(
        sensor_key_error("fusion/default/sensors/*/alive"),
        r#"sensor chunk "*" contains '*'"#
    );
    assert_eq!(
        sensor_key_error("fusion//sensors/x/alive"),
        "site chunk is empty"
    );
    assert_eq!(
        sensor_key_error(""),
        r#"key "" is not a sensor key: it does not start with "fusion/""#
    );
}

#[test]
fn malformed_site_keys_are_rejected_with_the_reason() {
    let error = parse_site_key("fusion/default/tracks/extra")
        .unwrap_err()
        .to_string();
    assert_eq!(
        error,
        r#"key "fusion/default/tracks/extra" is not a site key: it has 2 chunks after the site, expected 1"#
    );
    let error = parse_site_key("fusion/default/alive")
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("last chunk \"alive\" is not tracks, status or truth"),
        "{error}"
    );
}

#[test]
fn bad_chunks_are_rejected_with_typed_errors() {
    let error = SensorId::new("a/b").unwrap_err();
    assert_eq!(error.to_string(), r#"sensor chunk "a/b" contains '/'"#);
    assert!(matches!(
        error,
        ProtocolError::ChunkBadCharacter { bad: '/', .. }
    ));

    assert_eq!(
        Site::new("").unwrap_err().to_string(),
        "site chunk is empty"
    );
    assert_eq!(
        SensorId::new("cam 1").unwrap_err().to_string(),
        r#"sensor chunk "cam 1" contains ' '"#
    );
    assert_eq!(
        SensorId::new("caméra").unwrap_err().to_string(),
        r#"sensor chunk "caméra" contains 'é'"#
    );
    assert_eq!(
        Site::new("a$b").unwrap_err().to_string(),
        r#"site chunk "a$b" contains '$'"#
    );

    let long = "x".repeat(65);
    assert_eq!(
        SensorId::new(long.clone()).unwrap_err().to_string(),
        format!("sensor chunk \"{long}\" has 65 characters, at most 64 are allowed")
    );
    assert!(SensorId::new("x".repeat(64)).is_ok());
    assert!(SensorId::new("A-z_09").is_ok());
}

#[test]
fn identifiers_check_themselves_when_deserialised() {
    let ok: SensorId = serde_json::from_str(r#""cam1""#).unwrap();
    assert_eq!(ok.as_str(), "cam1");
    let error = serde_json::from_str::<SensorId>(r#""a/b""#)
        .unwrap_err()
        .to_string();
    assert!(
        error.contains(r#"sensor chunk "a/b" contains '/'"#),
        "{error}"
    );
    let parsed: Site = "north".parse().unwrap();
    assert_eq!(parsed.to_string(), "north");
}

#[test]
fn server_keys_have_their_form_and_the_active_token_parses_back() {
    let site = Site::new("room").unwrap();
    let a = InstanceId::new("a").unwrap();
    assert_eq!(
        keys::server_active_token(&site, &a),
        "fusion/room/server/active/a"
    );
    assert_eq!(
        keys::all_server_active_tokens(&site),
        "fusion/room/server/active/*"
    );
    assert_eq!(
        keys::server_status_key(&site, &a),
        "fusion/room/server/a/status"
    );
    assert_eq!(
        keys::server_checkpoint_key(&site, &a),
        "fusion/room/server/a/checkpoint"
    );
    let (parsed_site, parsed) =
        keys::parse_server_active_token(&keys::server_active_token(&site, &a)).unwrap();
    assert_eq!((parsed_site, parsed), (site, a));
    for bad in [
        "fusion/room/server/active",
        "fusion/room/server/a/status",
        "fusion/room/server/active/a/b",
        "fusion/room/server/active/a b",
    ] {
        assert!(keys::parse_server_active_token(bad).is_err(), "{bad}");
    }
}
