//! The top-level lists of a glTF document held as JSON (`nodes`,
//! `meshes`, `bufferViews`...): read, made where absent, appended to.

use serde_json::{Map, Value};

/// The array `key` of `object`, or an empty one.
pub(super) fn array<'a>(object: &'a Map<String, Value>, key: &str) -> &'a [Value] {
    object
        .get(key)
        .and_then(Value::as_array)
        .map_or(&[], Vec::as_slice)
}

/// The array `key` of `object`, made if absent.
pub(super) fn array_mut<'a>(object: &'a mut Map<String, Value>, key: &str) -> &'a mut Vec<Value> {
    let value = object
        .entry(key)
        .or_insert_with(|| Value::Array(Vec::new()));
    if !value.is_array() {
        *value = Value::Array(Vec::new());
    }
    value.as_array_mut().expect("an array")
}

/// Appends `value` to the array `key` of `object`, giving its index.
pub(super) fn push(object: &mut Map<String, Value>, key: &str, value: Value) -> usize {
    let list = array_mut(object, key);
    list.push(value);
    list.len() - 1
}
