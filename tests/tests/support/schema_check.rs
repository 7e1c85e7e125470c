//! Every message of an MCAP file validated, strictly, against the JSON
//! Schema its channel embeds (and scene messages also against the vendored
//! official `foxglove.SceneUpdate` schema), after checking that the
//! viewers' schema parser refuses no field of each embedded schema.

use fixplan_coordinator::{viewer_refusals, FOXGLOVE_SCENE_UPDATE};
use jsonschema::{Draft, Validator};
use serde_json::Value;
use std::collections::BTreeMap;

/// A draft 2020-12 validator of `schema` that also checks formats.
fn strict(schema: &Value) -> Validator {
    jsonschema::options()
        .with_draft(Draft::Draft202012)
        .should_validate_formats(true)
        .build(schema)
        .expect("the schema compiles")
}

fn check(validator: &Validator, what: &str, msg: &Value) {
    let errors: Vec<String> = validator.iter_errors(msg).map(|e| e.to_string()).collect();
    assert!(errors.is_empty(), "{what}: {errors:?}\n{msg}");
}

/// Validates every message of the MCAP file `bytes`; returns how many
/// messages were validated per topic (the scene topic's count is of
/// messages checked against both its embedded and the official schema).
pub fn validate_every_message(bytes: &[u8]) -> BTreeMap<String, usize> {
    let summary = mcap::Summary::read(bytes).unwrap().expect("summary");
    let mut validators: BTreeMap<u16, (String, Validator)> = BTreeMap::new();
    for ch in summary.channels.values() {
        let s = ch.schema.as_ref().expect("schema");
        assert_eq!(s.encoding, "jsonschema", "{}", ch.topic);
        assert_eq!(ch.message_encoding, "json", "{}", ch.topic);
        let schema: Value = serde_json::from_slice(&s.data).expect("schema is JSON");
        assert_eq!(
            viewer_refusals(&schema),
            Vec::<String>::new(),
            "{}: fields the viewers' schema parser refuses",
            ch.topic
        );
        let validator = strict(&schema);
        // Not vacuous: every channel's messages are objects.
        assert!(
            !validator.is_valid(&Value::from("not a message")),
            "{}",
            ch.topic
        );
        validators.insert(ch.id, (ch.topic.clone(), validator));
    }
    let official: Value = serde_json::from_slice(FOXGLOVE_SCENE_UPDATE).unwrap();
    assert_eq!(official["title"], "foxglove.SceneUpdate");
    let official = strict(&official);
    let mut counts: BTreeMap<String, usize> = BTreeMap::new();
    for m in mcap::MessageStream::new(bytes).unwrap() {
        let m = m.unwrap();
        let (topic, validator) = &validators[&m.channel.id];
        let msg: Value = serde_json::from_slice(&m.data).expect("message is JSON");
        let what = format!("{topic} message {}", m.sequence);
        check(validator, &what, &msg);
        if m.channel.schema.as_ref().map(|s| s.name.as_str()) == Some("foxglove.SceneUpdate") {
            check(&official, &format!("{what} (official schema)"), &msg);
        }
        *counts.entry(topic.clone()).or_default() += 1;
    }
    eprintln!("messages validated per channel: {counts:?}");
    counts
}
