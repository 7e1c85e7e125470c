//! The JSON Schemas embedded in a results file, one per channel of
//! [`super::messages`]: what lets a generic MCAP viewer decode them.

use super::messages::{SCHEMA_FIXTURES, SCHEMA_PART, SCHEMA_RUN, SCHEMA_SCENE};

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

/// A JSON Schema for the subset of `foxglove.SceneUpdate` that fixplan
/// writes (entities with line, cylinder, arrow and text primitives).
pub fn scene_schema() -> Vec<u8> {
    let num = serde_json::json!({"type": "number"});
    let v3 = serde_json::json!({"type": "object", "properties": {"x": num, "y": num, "z": num},
        "required": ["x", "y", "z"]});
    let quat = serde_json::json!({"type": "object", "properties": {"x": num, "y": num, "z": num, "w": num},
        "required": ["x", "y", "z", "w"]});
    let pose = serde_json::json!({"type": "object", "properties": {"position": v3, "orientation": quat},
        "required": ["position", "orientation"]});
    let color = serde_json::json!({"type": "object", "properties": {"r": num, "g": num, "b": num, "a": num},
        "required": ["r", "g", "b", "a"]});
    let time = serde_json::json!({"type": "object", "properties": {
        "sec": {"type": "integer", "minimum": 0},
        "nsec": {"type": "integer", "minimum": 0, "maximum": 999_999_999}}});
    let line = serde_json::json!({"type": "object", "properties": {
        "type": {"type": "integer", "description": "0 LINE_STRIP, 1 LINE_LOOP, 2 LINE_LIST"},
        "pose": pose, "thickness": num, "scale_invariant": {"type": "boolean"},
        "points": {"type": "array", "items": v3}, "color": color,
        "colors": {"type": "array", "items": color},
        "indices": {"type": "array", "items": {"type": "integer", "minimum": 0}}}});
    let cylinder = serde_json::json!({"type": "object", "properties": {
        "pose": pose, "size": v3, "bottom_scale": num, "top_scale": num, "color": color}});
    let arrow = serde_json::json!({"type": "object", "properties": {
        "pose": pose, "shaft_length": num, "shaft_diameter": num,
        "head_length": num, "head_diameter": num, "color": color}});
    let text = serde_json::json!({"type": "object", "properties": {
        "pose": pose, "billboard": {"type": "boolean"}, "font_size": num,
        "scale_invariant": {"type": "boolean"}, "color": color, "text": {"type": "string"}}});
    let arr = |t: &serde_json::Value| serde_json::json!({"type": "array", "items": t});
    let any_arr = serde_json::json!({"type": "array", "items": {"type": "object"}});
    let entity = serde_json::json!({"type": "object", "properties": {
        "timestamp": time, "frame_id": {"type": "string"}, "id": {"type": "string"},
        "lifetime": time, "frame_locked": {"type": "boolean"},
        "metadata": {"type": "array", "items": {"type": "object", "properties": {
            "key": {"type": "string"}, "value": {"type": "string"}}}},
        "arrows": arr(&arrow), "cubes": any_arr, "spheres": any_arr,
        "cylinders": arr(&cylinder), "lines": arr(&line), "triangles": any_arr,
        "texts": arr(&text), "models": any_arr}});
    schema(
        SCHEMA_SCENE,
        serde_json::json!({
            "description": "An update to the entities displayed in a 3D scene (the part of Foxglove's schema that fixplan uses)",
            "type": "object",
            "properties": {
                "deletions": {"type": "array", "items": {"type": "object", "properties": {
                    "timestamp": time, "type": {"type": "integer"}, "id": {"type": "string"}}}},
                "entities": arr(&entity)
            }
        }),
    )
}
