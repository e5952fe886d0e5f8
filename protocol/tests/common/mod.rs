//! Code shared by the integration tests: contract-form JSON comparison and round-trip assertions.

// Each test binary uses only some of this module.
#![allow(dead_code)]

pub mod documents;
pub mod strategies;

use protocol::{decode, encode, WireFormat};
use serde::de::DeserializeOwned;
use serde::Serialize;
use serde_json::Value;
use std::fmt::Debug;

/// Compares two JSON documents exactly (same keys, same nulls, same array lengths), except that numbers are
/// compared by value: the contract's examples write `800` where the type holds the f64 `800.0`.
pub fn json_difference(actual: &Value, expected: &Value, path: &str) -> Option<String> {
    match (actual, expected) {
        (Value::Number(a), Value::Number(e)) => {
            (a.as_f64() != e.as_f64()).then(|| format!("{path}: {a} != {e}"))
        }
        (Value::Array(a), Value::Array(e)) => {
            if a.len() != e.len() {
                return Some(format!("{path}: {} elements != {}", a.len(), e.len()));
            }
            a.iter()
                .zip(e)
                .enumerate()
                .find_map(|(i, (a, e))| json_difference(a, e, &format!("{path}[{i}]")))
        }
        (Value::Object(a), Value::Object(e)) => {
            // Sorted, so the comparison does not depend on serde_json's map order.
            let mut a_keys: Vec<_> = a.keys().collect();
            let mut e_keys: Vec<_> = e.keys().collect();
            a_keys.sort();
            e_keys.sort();
            if a_keys != e_keys {
                return Some(format!("{path}: keys {a_keys:?} != {e_keys:?}"));
            }
            a.iter()
                .find_map(|(k, v)| json_difference(v, &e[k], &format!("{path}.{k}")))
        }
        _ => (actual != expected).then(|| format!("{path}: {actual} != {expected}")),
    }
}

/// Decodes `literal` as JSON into `T`, re-encodes it, and checks the result is the literal (numbers by value);
/// also checks that decoding the re-encoded bytes gives the same value. Returns the decoded value.
pub fn assert_json_round_trip<T>(literal: &str) -> T
where
    T: Serialize + DeserializeOwned + PartialEq + Debug,
{
    let decoded: T = decode(literal.as_bytes(), WireFormat::Json)
        .unwrap_or_else(|e| panic!("literal does not decode: {e}\n{literal}"));
    let bytes = encode(&decoded, WireFormat::Json).expect("encode");
    let written: Value = serde_json::from_slice(&bytes).expect("encoded JSON parses");
    let expected: Value = serde_json::from_str(literal).expect("literal parses");
    if let Some(difference) = json_difference(&written, &expected, "$") {
        panic!("re-encoded JSON differs from the literal at {difference}\nwritten: {written}");
    }
    let again: T = decode(&bytes, WireFormat::Json).expect("re-encoded JSON decodes");
    assert_eq!(again, decoded);
    decoded
}

/// Encodes `value` with postcard and checks that decoding gives it back.
pub fn assert_postcard_round_trip<T>(value: &T)
where
    T: Serialize + DeserializeOwned + PartialEq + Debug,
{
    let bytes = encode(value, WireFormat::Postcard).expect("postcard encode");
    let back: T = decode(&bytes, WireFormat::Postcard).expect("postcard decode");
    assert_eq!(&back, value);
}
