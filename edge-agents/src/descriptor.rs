//! Reading a sensor's descriptor from a `--descriptor` file and checking it before anything is published.
//!
//! The file holds a protocol `SensorDescriptor` in its JSON form (`.json`) or the same fields in TOML (any
//! other extension). `version` may be omitted (1), and so may `site` (then `--site`, else `default`).

use std::path::Path;

use protocol::{SensorDescriptor, SensorKind, Site};
use serde_json::Value;

use crate::error::AgentError;

/// Reads the descriptor in `path`, fills in `version` and `site` when absent, and checks that it is valid and
/// of the `expected` kind. `site` is `--site`: when both it and the file name a site they must agree.
pub fn load_descriptor(
    path: &Path,
    site: Option<&Site>,
    expected: SensorKind,
) -> Result<SensorDescriptor, AgentError> {
    let file_error = |reason: String| AgentError::DescriptorFile {
        path: path.to_path_buf(),
        reason,
    };
    let text = std::fs::read_to_string(path).map_err(|e| file_error(e.to_string()))?;
    let is_json = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"));
    let mut value: Value = if is_json {
        serde_json::from_str(&text).map_err(|e| file_error(format!("not valid JSON: {e}")))?
    } else {
        let table: toml::Value =
            toml::from_str(&text).map_err(|e| file_error(format!("not valid TOML: {e}")))?;
        serde_json::to_value(table).map_err(|e| file_error(e.to_string()))?
    };
    let object = value
        .as_object_mut()
        .ok_or_else(|| file_error("expected a table/object of descriptor fields".into()))?;
    object
        .entry("version")
        .or_insert_with(|| Value::from(protocol::PROTOCOL_VERSION));
    match (object.get("site").and_then(Value::as_str), site) {
        (Some(in_file), Some(flag)) if in_file != flag.as_str() => {
            return Err(file_error(format!(
                "its site `{in_file}` differs from --site `{flag}`"
            )));
        }
        (Some(_), _) => {}
        (None, flag) => {
            let site = flag.cloned().unwrap_or_default();
            object.insert("site".into(), Value::from(site.as_str()));
        }
    }
    let descriptor: SensorDescriptor = serde_json::from_value(value)
        .map_err(|e| file_error(format!("not a sensor descriptor: {e}")))?;
    if descriptor.model.kind() != expected {
        return Err(file_error(format!(
            "its model kind is `{}`, this agent needs `{expected}`",
            descriptor.model.kind()
        )));
    }
    validate_descriptor(&descriptor)?;
    Ok(descriptor)
}

/// Applies the protocol's validation to a descriptor about to be published or written.
pub fn validate_descriptor(descriptor: &SensorDescriptor) -> Result<(), AgentError> {
    descriptor
        .validate()
        .map_err(|source| AgentError::InvalidDescriptor {
            sensor: descriptor.sensor.to_string(),
            source,
        })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    fn file_with(extension: &str, text: &str) -> tempfile::NamedTempFile {
        let mut file = tempfile::Builder::new()
            .suffix(extension)
            .tempfile()
            .expect("temp file");
        file.write_all(text.as_bytes()).expect("write");
        file
    }

    const CAMERA_TOML: &str = r#"
        sensor = "cam1"
        detection_probability = 0.95
        clutter_rate = 2.0
        [model]
        kind = "camera"
        projection = [[800, 0, 320, -400], [0, 800, 240, -300], [0, 0, 1, -2]]
        image_size = [640, 480]
        noise_std = [3.0, 3.0]
    "#;

    #[test]
    fn toml_descriptor_gets_version_and_site() {
        let file = file_with(".toml", CAMERA_TOML);
        let site = Site::new("lab").unwrap();
        let d = load_descriptor(file.path(), Some(&site), SensorKind::Camera).unwrap();
        assert_eq!(d.version, 1);
        assert_eq!(d.site.as_str(), "lab");
        assert_eq!(d.sensor.as_str(), "cam1");
        assert_eq!(d.detection_probability, 0.95);
    }

    #[test]
    fn wrong_kind_conflicting_site_and_invalid_values_are_refused() {
        let file = file_with(".toml", CAMERA_TOML);
        let wrong_kind = load_descriptor(file.path(), None, SensorKind::Lidar).unwrap_err();
        assert!(
            wrong_kind.to_string().contains("needs `lidar`"),
            "{wrong_kind}"
        );

        let with_site = file_with(
            ".json",
            r#"{"site": "a", "sensor": "m1", "detection_probability": 0.9,
            "clutter_rate": 0.5, "model": {"kind": "mic_pair", "mics": [[0,0,1],[0.5,0,1]], "noise_std": 1e-5}}"#,
        );
        let other = Site::new("b").unwrap();
        let conflict = load_descriptor(with_site.path(), Some(&other), SensorKind::MicPair);
        assert!(conflict
            .unwrap_err()
            .to_string()
            .contains("differs from --site"));
        assert!(load_descriptor(with_site.path(), None, SensorKind::MicPair).is_ok());

        let bad = file_with(".toml", &CAMERA_TOML.replace("0.95", "1.5"));
        let error = load_descriptor(bad.path(), None, SensorKind::Camera).unwrap_err();
        assert!(
            matches!(error, AgentError::InvalidDescriptor { .. }),
            "{error}"
        );
    }
}
