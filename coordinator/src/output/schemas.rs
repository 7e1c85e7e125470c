//! The JSON Schemas embedded in a results file, one per channel of
//! [`super::channels`]: what lets a generic MCAP viewer decode them.

use super::messages::Message;
use schemars::{generate::SchemaSettings, JsonSchema};

/// The JSON Schema of `T`, generated from the type (serde attributes and
/// doc comments included): draft 2020-12, every subschema inline (no
/// `$ref`, which simple viewers do not follow), titled `title`.
pub fn schema_of<T: JsonSchema>(title: &str) -> serde_json::Value {
    let generator = SchemaSettings::draft2020_12()
        .with(|s| s.inline_subschemas = true)
        .into_generator();
    let mut v: serde_json::Value = generator.into_root_schema_for::<T>().into();
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

/// The paths (JSON Pointer style, `#/...`) of every object schema in
/// `schema` without `properties`: a schema whose `type` is or includes
/// `"object"`, or that uses an object keyword (`required`,
/// `additionalProperties`, `patternProperties`, `propertyNames`,
/// `minProperties`, `maxProperties`). The JSON-schema parser of the Foxglove
/// and Lichtblick viewers walks `properties` of every object schema and
/// throws on these.
pub fn objects_without_properties(schema: &serde_json::Value) -> Vec<String> {
    let mut found = Vec::new();
    walk_objects(schema, "#", &mut found);
    found
}

const OBJECT_KEYWORDS: [&str; 6] = [
    "required",
    "additionalProperties",
    "patternProperties",
    "propertyNames",
    "minProperties",
    "maxProperties",
];

fn walk_objects(v: &serde_json::Value, path: &str, found: &mut Vec<String>) {
    match v {
        serde_json::Value::Object(o) => {
            let typed_object = match o.get("type") {
                Some(serde_json::Value::String(t)) => t == "object",
                Some(serde_json::Value::Array(ts)) => ts.iter().any(|t| t == "object"),
                _ => false,
            };
            // `properties` itself is a map of names, not a schema: its keys
            // may be named like keywords.
            let object_keywords = OBJECT_KEYWORDS.iter().any(|k| o.contains_key(*k));
            if (typed_object || object_keywords) && !o.contains_key("properties") {
                found.push(path.to_string());
            }
            for (k, child) in o {
                if k == "properties" || k == "$defs" || k == "definitions" {
                    if let Some(m) = child.as_object() {
                        for (name, sub) in m {
                            walk_objects(sub, &format!("{path}/{k}/{name}"), found);
                        }
                    }
                } else if k != "enum" && k != "const" && k != "default" && k != "examples" {
                    walk_objects(child, &format!("{path}/{k}"), found);
                }
            }
        }
        serde_json::Value::Array(a) => {
            for (i, child) in a.iter().enumerate() {
                walk_objects(child, &format!("{path}/{i}"), found);
            }
        }
        _ => {}
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
    /// title, draft 2020-12, `properties` on every object, no `$ref`.
    pub(crate) fn assert_viewer_ready(title: &str, v: &serde_json::Value) {
        assert_eq!(v["title"], title);
        assert_eq!(v["$schema"], "https://json-schema.org/draft/2020-12/schema");
        assert_eq!(
            objects_without_properties(v),
            Vec::<String>::new(),
            "{title}"
        );
        assert!(!v.to_string().contains("\"$ref\""), "{title} has a $ref");
    }

    #[test]
    fn official_scene_schema_objects_all_have_properties() {
        let v: serde_json::Value = serde_json::from_slice(FOXGLOVE_SCENE_UPDATE).unwrap();
        assert_eq!(objects_without_properties(&v), Vec::<String>::new());
    }

    #[test]
    fn walker_finds_objects_without_properties() {
        let v = serde_json::json!({"type": "object", "properties": {
            "a": {"type": "object"},
            "required": {"type": ["object", "null"], "properties": {}},
            "b": {"type": "array", "items": {"required": ["x"]}},
            "c": {"enum": [{"type": "object"}]}
        }});
        assert_eq!(
            objects_without_properties(&v),
            vec![
                "#/properties/a".to_string(),
                "#/properties/b/items".to_string()
            ]
        );
    }
}
