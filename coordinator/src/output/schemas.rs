//! The JSON Schemas embedded in a results file, one per channel of
//! [`super::channels`]: what lets a generic MCAP viewer decode them.

use super::messages::Message;
use schemars::{generate::SchemaSettings, JsonSchema};

/// The JSON Schema of `T`, generated from the type (serde attributes and
/// doc comments included): draft 2020-12, every subschema inline (no
/// `$ref`, which simple viewers do not follow), optional fields not
/// nullable (the messages leave an absent value out), titled `title`.
pub fn schema_of<T: JsonSchema>(title: &str) -> serde_json::Value {
    let generator = SchemaSettings::draft2020_12()
        .with(|s| s.inline_subschemas = true)
        .into_generator();
    let mut v: serde_json::Value = generator.into_root_schema_for::<T>().into();
    optional_not_nullable(&mut v);
    if let Some(o) = v.as_object_mut() {
        o.insert("title".into(), title.into());
    }
    v
}

/// The schema of JSON message `M` as a results file embeds it: generated
/// ([`schema_of`]), titled with its schema name, pretty-printed.
pub fn generated_schema<M: Message>() -> Vec<u8> {
    serde_json::to_vec_pretty(&schema_of::<M>(M::SCHEMA)).unwrap_or_default()
}

/// The official `foxglove.SceneUpdate` JSON Schema, vendored byte for byte
/// from `@foxglove/schemas` 2.1.0 (MIT; see `coordinator/schemas/foxglove/`).
pub const FOXGLOVE_SCENE_UPDATE: &[u8] = include_bytes!("../../schemas/foxglove/SceneUpdate.json");

/// The schema of `/fixplan/scene`: the official `foxglove.SceneUpdate`
/// schema ([`FOXGLOVE_SCENE_UPDATE`]), which Foxglove and Lichtblick parse.
pub fn scene_schema() -> Vec<u8> {
    FOXGLOVE_SCENE_UPDATE.to_vec()
}

/// What the viewers' JSON-schema parser (Foxglove Studio's and
/// Lichtblick's `parseJsonSchema`, `mcap-support`) refuses in `schema`,
/// one line per field, empty when it reads the schema. The parser walks
/// the `properties` of the root object and of every nested object and
/// array item, and takes a field only with one `type` among `boolean`,
/// `string`, `number`, `integer`, `object` and `array` (whose `items` is a
/// boolean, string, number or object), or as a `oneOf` whose alternatives
/// all have a numeric `const`: no type lists (nullable fields), no string
/// `oneOf`, no arrays of arrays. `tests/tests/viewers.rs` runs the
/// parser itself on real files; this is the same rule, checked without
/// node.
pub fn viewer_refusals(schema: &serde_json::Value) -> Vec<String> {
    let mut found = Vec::new();
    object_refusals(schema, "(root)", &mut found);
    found
}

fn object_refusals(schema: &serde_json::Value, path: &str, found: &mut Vec<String>) {
    if schema["type"] != "object" {
        found.push(format!("{path}: type {} is not \"object\"", schema["type"]));
        return;
    }
    let Some(properties) = schema["properties"].as_object() else {
        found.push(format!("{path}: an object without properties"));
        return;
    };
    for (name, field) in properties {
        let at = format!("{path}.{name}");
        if let Some(alternatives) = field.get("oneOf") {
            let numeric = |a: &serde_json::Value| a["const"].is_number();
            if !alternatives
                .as_array()
                .is_some_and(|a| a.iter().all(numeric))
            {
                found.push(format!("{at}: oneOf alternatives without number values"));
            }
            continue;
        }
        match field["type"].as_str() {
            Some("boolean" | "number" | "integer") => {}
            Some("string") => string_refusals(field, &at, found),
            Some("object") => object_refusals(field, &at, found),
            Some("array") => {
                let items = &field["items"];
                match items["type"].as_str() {
                    Some("boolean" | "number" | "integer") => {}
                    Some("string") if items.get("contentEncoding").is_none() => {}
                    Some("object") => object_refusals(items, &at, found),
                    _ => found.push(format!("{at}: array items of type {}", items["type"])),
                }
            }
            _ => found.push(format!("{at}: type {}", field["type"])),
        }
    }
}

fn string_refusals(field: &serde_json::Value, at: &str, found: &mut Vec<String>) {
    match field.get("contentEncoding") {
        None => {}
        Some(e) if e == "base64" => {}
        Some(e) => found.push(format!("{at}: contentEncoding {e}")),
    }
}

/// Makes the optional fields of every object in `schema` (those not in
/// its `required`) non-nullable: the messages leave an absent value out
/// rather than writing `null`, and the viewers' parser refuses a field
/// whose `type` is a list (`["number", "null"]`) or an `anyOf` with null.
fn optional_not_nullable(schema: &mut serde_json::Value) {
    use serde_json::Value;
    let Value::Object(o) = schema else {
        if let Value::Array(items) = schema {
            items.iter_mut().for_each(optional_not_nullable);
        }
        return;
    };
    let required: Vec<Value> = o
        .get("required")
        .and_then(Value::as_array)
        .cloned()
        .unwrap_or_default();
    if let Some(Value::Object(properties)) = o.get_mut("properties") {
        for (name, field) in properties.iter_mut() {
            if !required.contains(&Value::from(name.as_str())) {
                drop_null(field);
            }
        }
    }
    o.values_mut().for_each(optional_not_nullable);
}

/// `field` without its `null` alternative.
fn drop_null(field: &mut serde_json::Value) {
    use serde_json::Value;
    let Value::Object(o) = field else { return };
    if let Some(Value::Array(types)) = o.get_mut("type") {
        types.retain(|t| t != "null");
        if types.len() == 1 {
            let only = types.remove(0);
            o.insert("type".into(), only);
        }
    }
    let null = |a: &Value| a["type"] == "null";
    let Some(Value::Array(alternatives)) = o.get("anyOf") else {
        return;
    };
    if alternatives.len() == 2 && alternatives.iter().any(null) {
        let Some(Value::Object(kept)) = alternatives.iter().find(|a| !null(a)).cloned() else {
            return;
        };
        o.remove("anyOf");
        for (k, v) in kept {
            o.entry(k).or_insert(v);
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::output::messages::SCHEMA_SCENE;
    use sha2::{Digest, Sha256};

    #[test]
    fn scene_schema_is_the_vendored_official_file() {
        let digest = Sha256::digest(FOXGLOVE_SCENE_UPDATE);
        let hex: String = digest.iter().map(|b| format!("{b:02x}")).collect();
        assert_eq!(
            hex, "bc563208a8b4bb2eaecd17713405ef2d9ba87264ac73ae375ba5ab30368c8991",
            "coordinator/schemas/foxglove/SceneUpdate.json changed"
        );
        let v: serde_json::Value = serde_json::from_slice(&scene_schema()).unwrap();
        assert_eq!(v["title"], SCHEMA_SCENE);
        assert_eq!(v["type"], "object");
        assert!(v["properties"]["entities"].is_object());
    }

    /// What a viewer's schema parser needs of a generated schema: its
    /// title, draft 2020-12, nothing it refuses, no `$ref`, no `null`.
    pub(crate) fn assert_viewer_ready(title: &str, value: &serde_json::Value) {
        assert_eq!(value["title"], title);
        assert_eq!(
            value["$schema"],
            "https://json-schema.org/draft/2020-12/schema"
        );
        assert_eq!(viewer_refusals(value), Vec::<String>::new(), "{title}");
        let text = value.to_string();
        assert!(!text.contains("\"$ref\""), "{title} has a $ref");
        assert!(!text.contains("\"null\""), "{title} has a nullable field");
    }

    #[test]
    fn the_viewers_read_the_official_scene_schema() {
        let v: serde_json::Value = serde_json::from_slice(FOXGLOVE_SCENE_UPDATE).unwrap();
        assert_eq!(viewer_refusals(&v), Vec::<String>::new());
    }

    /// Each form the viewers' parser refuses, as the apps reported them
    /// for the schemas of fixplan 0.x, is found.
    #[test]
    fn refusals_are_found_where_the_viewers_refused() {
        let v = serde_json::json!({"type": "object", "properties": {
            "units": {"oneOf": [{"const": "mm"}, {"const": "in"}]},
            "kind": {"oneOf": [{"const": 0, "title": "A"}, {"const": 1, "title": "B"}]},
            "counts": {"type": ["object", "null"], "properties": {}},
            "outline": {"type": "array", "items": {"type": "array", "items": {"type": "number"}}},
            "nested": {"type": "object"},
            "rows": {"type": "array", "items": {"type": "object", "properties": {
                "ok": {"type": "boolean"}, "bad": {"anyOf": [{"type": "number"}]}
            }}},
            "name": {"type": "string", "pattern": "^(a|b)$"}
        }});
        assert_eq!(
            viewer_refusals(&v),
            vec![
                "(root).counts: type [\"object\",\"null\"]".to_string(),
                "(root).nested: an object without properties".to_string(),
                "(root).outline: array items of type \"array\"".to_string(),
                "(root).rows.bad: type null".to_string(),
                "(root).units: oneOf alternatives without number values".to_string(),
            ]
        );
    }

    /// Optional fields lose their `null`, required ones keep it.
    #[test]
    fn optional_fields_are_not_nullable() {
        let mut v = serde_json::json!({"type": "object", "required": ["kept"], "properties": {
            "kept": {"type": ["number", "null"]},
            "number": {"type": ["number", "null"], "description": "d"},
            "object": {"description": "o", "anyOf": [
                {"type": "object", "properties": {"a": {"type": ["string", "null"]}}},
                {"type": "null"}
            ]}
        }});
        optional_not_nullable(&mut v);
        assert_eq!(
            v,
            serde_json::json!({"type": "object", "required": ["kept"], "properties": {
                "kept": {"type": ["number", "null"]},
                "number": {"type": "number", "description": "d"},
                "object": {"description": "o", "type": "object",
                    "properties": {"a": {"type": "string"}}}
            }})
        );
    }
}
