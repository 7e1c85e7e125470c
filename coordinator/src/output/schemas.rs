//! The JSON Schemas embedded in a results file, one per channel of
//! [`super::messages`]: what lets a generic MCAP viewer decode them.

use super::messages::{SCHEMA_FIXTURES, SCHEMA_PART, SCHEMA_RUN};

fn schema(title: &str, body: serde_json::Value) -> Vec<u8> {
    let mut v = body;
    if let Some(o) = v.as_object_mut() {
        o.insert(
            "$schema".into(),
            "https://json-schema.org/draft/2020-12/schema".into(),
        );
        o.insert("title".into(), title.into());
    }
    serde_json::to_vec_pretty(&v).unwrap_or_default()
}

fn point() -> serde_json::Value {
    serde_json::json!({"type": "array", "items": {"type": "number"}, "minItems": 2, "maxItems": 2})
}

fn polygon() -> serde_json::Value {
    serde_json::json!({"type": "array", "items": point()})
}

fn lattice() -> serde_json::Value {
    serde_json::json!({"type": "array", "items": {"type": "integer"}, "minItems": 2, "maxItems": 2})
}

fn counts() -> serde_json::Value {
    serde_json::json!({"type": "object", "properties": {
        "segments": {"type": "integer"}, "combinations": {"type": "integer"},
        "setups": {"type": "integer"}, "candidates": {"type": "integer"},
        "admissible": {"type": "integer"}}})
}

fn status() -> serde_json::Value {
    serde_json::json!({"enum": ["ok", "no_fixture", "invalid"]})
}

/// The schema of `/fixplan/run`.
pub fn run_schema() -> Vec<u8> {
    schema(
        SCHEMA_RUN,
        serde_json::json!({
            "description": "What was run: tool version, catalogue (with a digest of its content), kit and parameters.",
            "type": "object",
            "required": ["tool", "version", "catalog", "kit_name", "kit", "params"],
            "properties": {
                "tool": {"type": "string"}, "version": {"type": "string"},
                "catalog": {"type": "object", "properties": {
                    "name": {"type": "string"}, "source": {"type": "string"},
                    "units": {"enum": ["mm", "in"]}, "parts": {"type": "integer"},
                    "digest": {"type": "string"}}},
                "kit_name": {"type": "string"},
                "kit": {"type": "object", "description": "SPEC Appendix A kit, catalogue units"},
                "params": {"type": "object", "description": "SPEC Appendix A params"},
                "grid_steps": {"type": "array", "items": {"type": "integer"}},
                "good_enough": {"type": "number"}
            }
        }),
    )
}

/// The schema of `/fixplan/part`.
pub fn part_schema() -> Vec<u8> {
    schema(
        SCHEMA_PART,
        serde_json::json!({
            "description": "One catalogue part: outline and access regions (part frame, catalogue units), outcome, counts, timings.",
            "type": "object",
            "required": ["index", "id", "status", "units", "quantity", "outline", "fixtures", "timing"],
            "properties": {
                "index": {"type": "integer"}, "id": {"type": "string"},
                "file": {"type": ["string", "null"]},
                "status": status(), "error": {"type": ["string", "null"]},
                "warnings": {"type": "array", "items": {"type": "string"}},
                "units": {"enum": ["mm", "in"]}, "quantity": {"type": "number"},
                "outline": polygon(), "access": {"type": "array", "items": polygon()},
                "counts": {"oneOf": [counts(), {"type": "null"}]},
                "fixtures": {"type": "integer"}, "best_score": {"type": ["number", "null"]},
                "timing": {"type": "object", "properties": {
                    "prepare_ms": {"type": "number"}, "enumerate_ms": {"type": "number"},
                    "shards": {"type": "integer"}}},
                "refine": {"type": "array", "description": "--grid-steps: one entry per step, coarse to fine",
                    "items": {"type": "object", "properties": {
                        "grid_step": {"type": "integer"}, "counts": counts(),
                        "fixtures": {"type": "integer"},
                        "best_score": {"type": ["number", "null"]},
                        "best": {"type": ["object", "null"], "description": "the best fixture at this step (as in /fixplan/fixtures)"},
                        "added": {"type": "integer", "description": "admissible fixtures added to the previous step"},
                        "improved_by": {"type": ["number", "null"], "description": "previous best score minus this one"},
                        "stopped_at": {"type": "integer"},
                        "enumerate_ms": {"type": "number"}}}},
                "stopped": {"enum": ["good_enough"], "description": "why the enumeration ended early"},
                "stopped_at": {"type": "integer", "description": "combination index of the early stop"}
            }
        }),
    )
}

/// The schema of `/fixplan/fixtures`.
pub fn fixtures_schema() -> Vec<u8> {
    let fixture = serde_json::json!({"type": "object", "properties": {
        "rank": {"type": "integer"}, "score": {"type": "number"},
        "segments": {"type": "array", "items": {"type": "integer"}},
        "locators": {"type": "array", "items": lattice()},
        "pose": {"type": "object", "properties": {
            "x": {"type": "number"}, "y": {"type": "number"}, "theta_deg": {"type": "number"}}},
        "clamp": {"type": "object", "properties": {
            "segment": {"type": "integer"}, "rotation_deg": {"type": "integer"},
            "mount": lattice(), "extension": {"type": "number"}, "contact": point()}},
        "borderline": {"type": "boolean"},
        "contacts": {"type": "array", "items": {"type": "object", "properties": {
            "point": point(), "normal": point()}}},
        "placement": {"type": "object", "properties": {
            "rotation_deg": {"type": "integer"},
            "locators": {"type": "array", "items": lattice()},
            "clamp_holes": {"type": "array", "items": lattice()}}}
    }});
    schema(
        SCHEMA_FIXTURES,
        serde_json::json!({
            "description": "The ranked fixtures of one part: SPEC Appendix A result plus contacts and plate placement.",
            "type": "object",
            "required": ["part", "status", "fixtures"],
            "properties": {
                "part": {"type": "string"}, "status": status(),
                "error": {"type": "string"}, "counts": counts(),
                "fixtures": {"type": "array", "items": fixture}
            }
        }),
    )
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
mod tests {
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
