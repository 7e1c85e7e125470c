//! The channels of a results file, declared once: [`RUN_CHANNEL`] and the
//! list [`PART_CHANNELS`], each entry its id, topic, schema and how a
//! part's message on it is made. The writer (schemas, channel records,
//! chunk layout), the reader (which topic is which message), the shape
//! check of a worker's chunk and the comparison of two parts all iterate
//! the list, so a new channel is one entry here and one message type.

use super::messages::{
    FixturesMsg, Message, PartContent, PartMessage, PartMsg, RunMsg, SCHEMA_SCENE, TOPIC_SCENE,
};
use super::scene::{scene_json, PartScene};
use super::schemas::{generated_schema, scene_schema};

/// A channel of a results file and its schema (schema `id` belongs to
/// channel `id`).
#[derive(Debug, Clone, Copy)]
pub struct Channel {
    /// Channel and schema id: the ids the MCAP writer gave them before
    /// chunks were made by the workers, and what every chunk's message
    /// records name.
    pub id: u16,
    /// The topic viewers list.
    pub topic: &'static str,
    /// The schema's name, which viewers decode by.
    pub schema_name: &'static str,
    /// The schema's bytes, as the file embeds them.
    pub schema: fn() -> Vec<u8>,
}

/// A channel that holds one message per part, and how that message is
/// made from the solved part.
#[derive(Debug, Clone, Copy)]
pub struct PartChannel {
    /// The channel.
    pub channel: Channel,
    /// The part's message on it, as JSON bytes.
    pub encode: fn(&PartContent) -> serde_json::Result<Vec<u8>>,
}

impl Channel {
    /// The channel of JSON message `M`, its schema generated from the type.
    const fn json<M: Message>(id: u16) -> Channel {
        Channel {
            id,
            topic: M::TOPIC,
            schema_name: M::SCHEMA,
            schema: generated_schema::<M>,
        }
    }
}

impl PartChannel {
    /// The channel of the per-part JSON message `M`.
    const fn json<M: PartMessage>(id: u16) -> PartChannel {
        PartChannel {
            channel: Channel::json::<M>(id),
            encode: encode_json::<M>,
        }
    }
}

fn encode_json<M: PartMessage>(part: &PartContent) -> serde_json::Result<Vec<u8>> {
    serde_json::to_vec(&M::of(part))
}

/// `/fixplan/run`: one message, at the start of the file, in a chunk of
/// its own.
pub const RUN_CHANNEL: Channel = Channel::json::<RunMsg>(1);

/// The channels with one message per part. A part's chunk holds one
/// message on each, in this order; ids follow [`RUN_CHANNEL`]'s.
pub const PART_CHANNELS: [PartChannel; 3] = [
    PartChannel::json::<PartMsg>(2),
    PartChannel::json::<FixturesMsg>(3),
    PartChannel {
        channel: Channel {
            id: 4,
            topic: TOPIC_SCENE,
            schema_name: SCHEMA_SCENE,
            schema: scene_schema,
        },
        encode: scene_message,
    },
];

/// Every channel of a results file, in id order.
pub fn all_channels() -> impl Iterator<Item = &'static Channel> {
    std::iter::once(&RUN_CHANNEL).chain(PART_CHANNELS.iter().map(|c| &c.channel))
}

/// The place in [`PART_CHANNELS`] of the channel `topic`, if it is one.
pub fn part_slot(topic: &str) -> Option<usize> {
    PART_CHANNELS.iter().position(|c| c.channel.topic == topic)
}

/// `/fixplan/scene`: the best fixture on the plate, or the outline and
/// why there is no fixture.
fn scene_message(content: &PartContent) -> serde_json::Result<Vec<u8>> {
    let caption = match &content.result.error {
        Some(e) => e.clone(),
        None => format!("{}: no fixture", content.entry.id),
    };
    scene_json(PartScene {
        index: content.index,
        id: &content.entry.id,
        units: content.units,
        kit: content.kit,
        outline: content.outline,
        holes: content.holes,
        access: content.access,
        segment_loops: &content.result.segment_loops,
        best: content.result.fixtures.first().ok_or(caption.as_str()),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::messages::{TOPIC_FIXTURES, TOPIC_PART, TOPIC_RUN};
    use crate::output::schemas::tests::assert_viewer_ready;
    use sha2::{Digest, Sha256};

    #[test]
    fn channel_ids_are_their_place_and_topics_are_unique() {
        let all: Vec<&Channel> = all_channels().collect();
        for (i, c) in all.iter().enumerate() {
            assert_eq!(usize::from(c.id), i + 1, "{}", c.topic);
            assert_eq!(all.iter().filter(|o| o.topic == c.topic).count(), 1);
        }
        let topics: Vec<&str> = all.iter().map(|c| c.topic).collect();
        assert_eq!(topics, [TOPIC_RUN, TOPIC_PART, TOPIC_FIXTURES, TOPIC_SCENE]);
        assert_eq!(part_slot(TOPIC_FIXTURES), Some(1));
        assert_eq!(part_slot(TOPIC_RUN), None);
    }

    #[test]
    fn generated_schemas_are_titled_2020_12_and_read_by_the_viewers() {
        for c in all_channels().filter(|c| c.schema_name != SCHEMA_SCENE) {
            let v: serde_json::Value = serde_json::from_slice(&(c.schema)()).unwrap();
            assert_viewer_ready(c.schema_name, &v);
        }
    }

    /// The generated schemas are part of the file format: they change only
    /// with the message types of [`crate::output::messages`].
    #[test]
    fn generated_schemas_keep_their_bytes() {
        let digests: Vec<(&str, String)> = all_channels()
            .map(|c| {
                let digest = Sha256::digest((c.schema)());
                let hex = digest.iter().map(|b| format!("{b:02x}")).collect();
                (c.schema_name, hex)
            })
            .collect();
        let want = [
            (
                "fixplan.Run",
                "0b035ce9bf18b208ec019619dae2b2b6bad522b78e2b81ad5eb47b8d04596d18",
            ),
            (
                "fixplan.Part",
                "f7be8e80a29a5db15121620815bf80f8aa3738ff54838816e510545c34d0ceae",
            ),
            (
                "fixplan.Fixtures",
                "6e2830ec2d6c25b57b7d2c9cd0f4506ce503b6dcf5222f160581273ad47adc1e",
            ),
            (
                SCHEMA_SCENE,
                "bc563208a8b4bb2eaecd17713405ef2d9ba87264ac73ae375ba5ab30368c8991",
            ),
        ];
        let want: Vec<(&str, String)> = want.iter().map(|(n, h)| (*n, h.to_string())).collect();
        assert_eq!(digests, want);
    }
}
