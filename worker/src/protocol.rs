//! The messages between coordinator and workers, and their framing.
//!
//! Every message is one frame: the magic `FX`, the protocol version
//! (`u16`, little endian), a kind byte and a body. The version is checked
//! before anything else is read. Kind [`KIND_REFUSED`] carries a plain UTF-8
//! text in every protocol version, so that a peer of another version can
//! still be told, clearly, why it was refused. Every other kind carries a
//! [`Msg`] encoded with `postcard` (binary, so floats cross processes bit
//! for bit).

use bytes::Bytes;
use fixplan_core::PartialResult;
use serde::{Deserialize, Serialize};
use std::ops::Range;
use thiserror::Error;

/// The version of this protocol. A peer speaking another one is refused.
pub const PROTOCOL_VERSION: u16 = 11;
const MAGIC: [u8; 2] = *b"FX";
const HEADER: usize = 5;
const KIND_MSG: u8 = 1;
/// A refusal: plain UTF-8 text, the same in every protocol version.
pub const KIND_REFUSED: u8 = 0xFF;

/// SHA-256 of a part's wire input: the name under which workers cache it.
pub type Digest = [u8; 32];

/// Which transport carries shard requests and results.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum TransportChoice {
    /// iceoryx2 when the worker is on the coordinator's host, else zenoh.
    #[default]
    Auto,
    /// zenoh only: the worker's results take the network path even on the
    /// coordinator's host (tests, or a `/dev/shm` too small to share).
    Zenoh,
    /// iceoryx2 only: a worker that cannot share the coordinator's memory
    /// is refused rather than quietly slower.
    Iceoryx2,
}

/// A `--transport` value that is none of `auto`, `zenoh`, `iceoryx2`.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[error("unknown transport {0:?} (auto, zenoh or iceoryx2)")]
pub struct UnknownTransport(pub String);

impl std::str::FromStr for TransportChoice {
    type Err = UnknownTransport;
    fn from_str(text: &str) -> Result<Self, UnknownTransport> {
        match text {
            "auto" => Ok(TransportChoice::Auto),
            "zenoh" => Ok(TransportChoice::Zenoh),
            "iceoryx2" => Ok(TransportChoice::Iceoryx2),
            _ => Err(UnknownTransport(text.to_string())),
        }
    }
}

impl std::fmt::Display for TransportChoice {
    fn fmt(&self, formatter: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        formatter.write_str(match self {
            TransportChoice::Auto => "auto",
            TransportChoice::Zenoh => "zenoh",
            TransportChoice::Iceoryx2 => "iceoryx2",
        })
    }
}

/// A worker asks to take part in the run (zenoh, `PREFIX/join`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Join {
    /// The worker's unique name: its results, its liveliness token and the
    /// logs are matched by it.
    pub worker: String,
    /// Identifies the host and its `/dev/shm` (see [`crate::host::host_id`]).
    pub host_id: String,
    /// The worker's process id, for the operator reading the coordinator's
    /// log.
    pub pid: u32,
    /// The worker's enumeration threads: batches are sized to keep them busy.
    pub threads: u32,
    /// The transport the worker wants for its shards.
    pub transport: TransportChoice,
    /// fixplan version of the worker, for messages.
    pub software: String,
}

/// Where the worker sends its shard requests after joining.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub enum DataPath {
    /// Queries on `PREFIX/work`, as for the join.
    Zenoh,
    /// iceoryx2 request-response service `service` under the global prefix
    /// `prefix`, with the event services `service/req` and `service/resp`.
    Iceoryx2 {
        /// The run's iceoryx2 global prefix (one per run: runs never meet).
        prefix: String,
        /// The request-response service's name.
        service: String,
    },
}

/// The coordinator's answer to a [`Join`] it accepts.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Welcome {
    /// Names the run: a worker that stays does not rejoin a run it finished.
    pub run_id: String,
    /// Where to send reports from now on.
    pub data: DataPath,
    /// How long a shard may stay out before it is given to another worker.
    pub lease_ms: u64,
}

/// One task for a worker: what it is to do ([`Task`]) with which part.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Assign {
    /// Names the task in the worker's report (a shard, or the finishing
    /// of a cut part).
    pub shard_id: u64,
    /// The part the task is about: the key of the worker's cache of
    /// prepared parts.
    pub digest: Digest,
    /// The part's wire input ([`crate::part_input::PartInput::encode`]),
    /// only the first time this worker gets a task of the part. Shared
    /// bytes (serialised as `serde_bytes` would, so the wire is the same)
    /// because the coordinator sends one part's input to every worker
    /// without copying it for each.
    pub input: Option<Bytes>,
    /// What to do with the part.
    pub task: Task,
    /// What the task may spend (protocol 10): a part beyond it is
    /// answered [`TaskError::OverBudget`].
    pub budget: TaskBudget,
}

/// A task's work budget (protocol 10; fixtures since 11): `--part-setups`
/// and `--part-fixtures`, the same on every worker, and what is left of
/// the part's `--part-seconds` by the coordinator's clock when the task
/// is handed out.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct TaskBudget {
    /// Setups at most (SPEC's `setups` count): a task that sees more
    /// stops, and so does its part, since a task's setups are at most its
    /// part's.
    pub setups: Option<u64>,
    /// Fixtures kept at most, for a part whose top-k can exceed it (0 or
    /// above it): a task that keeps more stops, and so does its part,
    /// since a task's fixtures are admissible fixtures of its part.
    pub fixtures: Option<u64>,
    /// Milliseconds the task may still run.
    pub millis: Option<u64>,
}

/// Which budget stopped a task's enumeration.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Error, Serialize, Deserialize)]
pub enum BudgetStop {
    /// More setups than [`TaskBudget::setups`]: the same verdict whatever
    /// the worker or the shard.
    #[error("more than {0} setups")]
    Setups(u64),
    /// More fixtures kept than [`TaskBudget::fixtures`]: the same verdict
    /// whatever the worker or the shard.
    #[error("more than {0} fixtures kept")]
    Fixtures(u64),
    /// Past [`TaskBudget::millis`] (wall clock).
    #[error("past its time")]
    Deadline,
}

impl From<fixplan_core::BudgetHalt> for BudgetStop {
    fn from(halt: fixplan_core::BudgetHalt) -> BudgetStop {
        match halt {
            fixplan_core::BudgetHalt::Setups(n) => BudgetStop::Setups(n),
            fixplan_core::BudgetHalt::Fixtures(n) => BudgetStop::Fixtures(n),
            fixplan_core::BudgetHalt::Deadline => BudgetStop::Deadline,
        }
    }
}

impl From<BudgetStop> for fixplan_core::BudgetHalt {
    fn from(stop: BudgetStop) -> fixplan_core::BudgetHalt {
        match stop {
            BudgetStop::Setups(n) => fixplan_core::BudgetHalt::Setups(n),
            BudgetStop::Fixtures(n) => fixplan_core::BudgetHalt::Fixtures(n),
            BudgetStop::Deadline => fixplan_core::BudgetHalt::Deadline,
        }
    }
}

/// What a worker is asked to do with a part (protocol 8). The
/// coordinator's scheduler makes tasks in one place and a worker reads
/// them in one place ([`crate::task`]): each kind says what it needs and
/// nothing else.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Task {
    /// Enumerate these combinations of the part: a shard of a cut part, or
    /// a whole part the coordinator finishes itself. Answered with
    /// [`Answer::Enumerated`].
    Enumerate {
        /// The combinations (an open end: up to the part's count).
        range: Range<u64>,
        /// `--good-enough`: stop at the first combination that admits a
        /// fixture scoring this or better ([`Answer::Enumerated`]'s `hit`).
        good_enough: Option<f64>,
    },
    /// Enumerate a whole part and finish it with the worker's
    /// [`crate::finish::Finisher`]: answered with
    /// [`Answer::EnumeratedAndFinished`].
    EnumerateAndFinish {
        /// Every combination of the part (an open range).
        range: Range<u64>,
        /// What the finisher needs besides the part and its result (its
        /// place and entry in the catalogue), opaque to the worker.
        context: Bytes,
    },
    /// Finish a part cut into shards from their merged result, enumerating
    /// nothing: answered with [`Answer::Finished`]. Finishing a part costs
    /// the coordinator more than all else it does for it, so cut parts are
    /// finished by workers too, like whole ones.
    Finish {
        /// The part's shard results merged, and their time.
        merged: Box<MergedCut>,
        /// As for [`Task::EnumerateAndFinish`].
        context: Bytes,
    },
}

/// What a worker finishes a cut part from ([`Task::Finish`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MergedCut {
    /// The part's shard results merged, as the coordinator merged them.
    pub result: PartialResult,
    /// The workers' time enumerating its shards, for the part's timing.
    pub micros: u64,
}

/// A task done (by the worker named in the [`Msg::Report`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TaskDone {
    /// The task of the [`Assign`].
    pub shard_id: u64,
    /// The part the worker worked on: the coordinator checks it is the one
    /// it assigned.
    pub digest: Digest,
    /// Time spent enumerating (finishing, for [`Task::Finish`]), for the
    /// coordinator's statistics and the part's timing.
    pub micros: u64,
    /// What the task gave, of the kind the task asked for.
    pub answer: Answer,
}

/// What a task gave: one kind for each kind of [`Task`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Answer {
    /// Of [`Task::Enumerate`].
    Enumerated {
        /// The enumeration of the range, or with `good_enough` of its
        /// prefix up to and including `hit`.
        result: PartialResult,
        /// `good_enough`: the combination where the shard stopped.
        hit: Option<u64>,
    },
    /// Of [`Task::EnumerateAndFinish`].
    EnumeratedAndFinished {
        /// The enumeration of the whole part.
        result: PartialResult,
        /// The part finished by the worker's finisher (for the
        /// coordinator: its messages, compressed), or why not (the
        /// coordinator then finishes the part from `result`).
        finished: Result<Bytes, FinishError>,
    },
    /// Of [`Task::Finish`]: the part finished, or why not (the
    /// coordinator then finishes it from the merged result it holds).
    Finished(Result<Bytes, FinishError>),
}

/// A task the worker could not do (a panic, or an input it could not
/// prepare): the part becomes `invalid` with this error's text.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TaskFailed {
    /// The task of the [`Assign`].
    pub shard_id: u64,
    /// What went wrong: its text becomes the part's error message.
    pub error: TaskError,
}

/// Why a worker could not do a task. The texts are the part's error
/// message in the results file: they read as they always did.
#[derive(Debug, Clone, PartialEq, Error, Serialize, Deserialize)]
pub enum TaskError {
    /// The task is for a part this worker has not been sent.
    #[error("the coordinator sent no input for an unknown part")]
    MissingInput,
    /// The input was damaged or belongs to another part.
    #[error("part input does not match its digest")]
    DigestMismatch,
    /// The input could not be read (postcard's reason, as
    /// [`crate::part_input::InputError`] tells it).
    #[error("{0}")]
    UnreadableInput(String),
    /// The input was read but the part or kit is unusable (the prepare
    /// error's text).
    #[error("{0}")]
    Unprepared(String),
    /// A task that enumerates an empty range: nothing a coordinator of
    /// this version sends.
    #[error("a task to enumerate the empty range {0:?}")]
    EmptyRange(Range<u64>),
    /// The task panicked (a bug in the part's enumeration): the message.
    #[error("internal error in the enumeration: {0}")]
    Panicked(String),
    /// The task's budget ([`Assign::budget`]) stopped it: the part is
    /// `over_budget` (the coordinator words it as `fixplan run` does).
    #[error("over its work budget: {0}")]
    OverBudget(BudgetStop),
    /// The worker's thread panicked outside the task's own guard.
    #[error("internal error: {0}")]
    Crashed(String),
}

/// Why a part was not finished, or why a worker's finished part is not
/// what its inputs make. It crosses the wire in
/// [`Answer`]: the coordinator then finishes the part
/// itself.
#[derive(Debug, Clone, PartialEq, Eq, Error, Serialize, Deserialize)]
pub enum FinishError {
    /// The worker has no finisher (a worker loop started without one).
    #[error("this worker finishes no parts")]
    NoFinisher,
    /// The context is not one this version reads.
    #[error("malformed finish context: {0}")]
    Context(String),
    /// The part's messages could not be made or compressed.
    #[error("cannot make the part's messages: {0}")]
    Messages(String),
    /// The finished part could not be encoded.
    #[error("cannot encode the finished part: {0}")]
    Encode(String),
    /// A finished part that is not one of this version.
    #[error("malformed: {0}")]
    Malformed(String),
    /// The finished part's summary differs from what its inputs make.
    #[error("summary {theirs}, the result's {ours}")]
    Summary {
        /// The worker's summary.
        theirs: String,
        /// The summary its inputs make.
        ours: String,
    },
    /// The finished part's records differ from what its inputs make.
    #[error("{0}")]
    Records(String),
    /// Finishing panicked (a bug): the message.
    #[error("finishing panicked: {0}")]
    Panicked(String),
}

/// What became of one task of an assignment.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Outcome {
    /// Done (boxed: the result is large beside a failure).
    Done(Box<TaskDone>),
    /// Not done, and doing it again would fail the same way.
    Failed(TaskFailed),
}

impl Outcome {
    /// The shard it answers.
    pub fn shard_id(&self) -> u64 {
        match self {
            Outcome::Done(d) => d.shard_id,
            Outcome::Failed(f) => f.shard_id,
        }
    }
}

/// What a worker is to do next.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Next {
    /// Shards to enumerate: one, or several small ones together so that
    /// the round trip stays small beside the work.
    Work(Vec<Assign>),
    /// Nothing to do now; report again after this long.
    Idle {
        /// How long to wait: the coordinator paces idle workers.
        retry_ms: u64,
    },
    /// The run is over.
    Done,
    /// The coordinator does not know this worker (declared dead, or another
    /// run): join again.
    Rejoin,
}

/// Protocol 2 has one request after joining, [`Msg::Report`], and one
/// answer, [`Msg::Reply`]: a worker hands in the results of its last
/// assignment and gets the next one in the same round trip (protocol 1
/// needed two: result, then pull).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Msg {
    /// A worker asks to take part (`PREFIX/join`).
    Join(Join),
    /// The coordinator accepts a join.
    Welcome(Welcome),
    /// The outcomes of shards done since the last report (none on the
    /// first), and a request for more work.
    Report {
        /// The reporting worker's name from its [`Join`].
        worker: String,
        /// One per shard done since the last report.
        outcomes: Vec<Outcome>,
        /// Shards it still works on (protocol 7): a worker asks for more
        /// while its last shards run, so that its threads do not wait for
        /// the slowest one. Whatever else it was given and has not
        /// reported went out in a reply it never got.
        holding: Vec<u64>,
    },
    /// The answer to a report: why any outcome was not taken (a duplicate,
    /// a rejected result), and what to do next.
    Reply {
        /// Texts for the worker's log, one per outcome not taken.
        notes: Vec<String>,
        /// The next assignment, or why there is none.
        next: Next,
    },
}

/// A decoded frame.
#[derive(Debug, Clone, PartialEq)]
pub enum Frame {
    /// A message of this protocol version.
    Msg(Msg),
    /// A refusal, whatever the version of its sender: the text says why.
    Refused(String),
}

/// Why a frame cannot be read: the coordinator turns it into a refusal
/// ([`refusal_for`]), a worker stops.
#[derive(Debug, Error, PartialEq)]
pub enum DecodeError {
    /// Not a frame at all (another program on the key or service).
    #[error("not a fixplan message ({0} bytes, no FX header)")]
    NotFixplan(usize),
    /// A peer of another protocol version.
    #[error("protocol version {got}, this side speaks version {PROTOCOL_VERSION}")]
    Version {
        /// The version the peer claims.
        got: u16,
    },
    /// A kind byte this version does not define.
    #[error("unknown message kind {0}")]
    Kind(u8),
    /// The body is not a [`Msg`] (truncated or damaged).
    #[error("malformed message: {0}")]
    Body(postcard::Error),
}

/// A message postcard cannot encode (it encodes every [`Msg`] there is,
/// so this is a bug, reported rather than unwrapped).
#[derive(Debug, Error)]
#[error("cannot encode message: {0}")]
pub struct EncodeError(postcard::Error);

fn header(version: u16, kind: u8) -> Vec<u8> {
    let mut v = Vec::with_capacity(256);
    v.extend_from_slice(&MAGIC);
    v.extend_from_slice(&version.to_le_bytes());
    v.push(kind);
    v
}

/// Encodes a message in this protocol version.
pub fn encode(msg: &Msg) -> Result<Vec<u8>, EncodeError> {
    encode_as(PROTOCOL_VERSION, msg)
}

/// Encodes a message claiming another protocol version (for tests of the
/// version check).
pub fn encode_as(version: u16, msg: &Msg) -> Result<Vec<u8>, EncodeError> {
    let v = header(version, KIND_MSG);
    postcard::to_extend(msg, v).map_err(EncodeError)
}

/// A refusal, readable by a peer of any protocol version.
pub fn encode_refused(reason: &str) -> Vec<u8> {
    let mut v = header(PROTOCOL_VERSION, KIND_REFUSED);
    v.extend_from_slice(reason.as_bytes());
    v
}

/// Decodes a frame: header and version first, then the body.
pub fn decode(bytes: &[u8]) -> Result<Frame, DecodeError> {
    if bytes.len() < HEADER || bytes[..2] != MAGIC {
        return Err(DecodeError::NotFixplan(bytes.len()));
    }
    let version = u16::from_le_bytes([bytes[2], bytes[3]]);
    let kind = bytes[4];
    let body = &bytes[HEADER..];
    if kind == KIND_REFUSED {
        return Ok(Frame::Refused(String::from_utf8_lossy(body).into_owned()));
    }
    if version != PROTOCOL_VERSION {
        return Err(DecodeError::Version { got: version });
    }
    if kind != KIND_MSG {
        return Err(DecodeError::Kind(kind));
    }
    match postcard::from_bytes::<Msg>(body) {
        Ok(m) => Ok(Frame::Msg(m)),
        Err(e) => Err(DecodeError::Body(e)),
    }
}

/// The coordinator's answer to a frame it cannot read.
pub fn refusal_for(err: &DecodeError) -> String {
    match err {
        DecodeError::Version { got } => format!(
            "refused: this coordinator speaks fixplan protocol version {PROTOCOL_VERSION} (fixplan {}), \
             the worker speaks version {got}; run the same fixplan version on both",
            env!("CARGO_PKG_VERSION")
        ),
        e => format!("refused: {e}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fixplan_core::Counts;

    #[test]
    fn round_trip_and_version() {
        let m = Msg::Report {
            worker: "w1".into(),
            outcomes: vec![],
            holding: vec![3, 9],
        };
        let b = encode(&m).unwrap();
        assert_eq!(decode(&b), Ok(Frame::Msg(m.clone())));
        let b2 = encode_as(PROTOCOL_VERSION + 1, &m).unwrap();
        assert_eq!(
            decode(&b2),
            Err(DecodeError::Version {
                got: PROTOCOL_VERSION + 1
            })
        );
        assert!(matches!(
            decode(b"garbage"),
            Err(DecodeError::NotFixplan(_))
        ));
        let mut cut = b.clone();
        cut.truncate(HEADER + 1);
        assert!(matches!(decode(&cut), Err(DecodeError::Body(_))));
        let r = encode_refused("no");
        assert_eq!(decode(&r), Ok(Frame::Refused("no".into())));
    }

    #[test]
    fn floats_cross_bit_exact() {
        let xs = [
            0.1f64,
            1.0 / 3.0,
            f64::MIN_POSITIVE,
            1e-310,
            -0.0,
            123456.789e-7,
            f64::MAX,
        ];
        let pr = PartialResult {
            range: 3..9,
            counts: Counts::default(),
            fixtures: vec![],
        };
        for x in xs {
            let m = Msg::Reply {
                notes: vec![],
                next: Next::Idle {
                    retry_ms: x.to_bits(),
                },
            };
            let b = encode(&m).unwrap();
            assert_eq!(decode(&b), Ok(Frame::Msg(m)));
            let v: Vec<f64> =
                postcard::from_bytes(&postcard::to_allocvec(&vec![x]).unwrap()).unwrap();
            assert_eq!(v[0].to_bits(), x.to_bits());
        }
        let m = Msg::Report {
            worker: "w".into(),
            outcomes: vec![
                Outcome::Done(Box::new(TaskDone {
                    shard_id: 1,
                    digest: [7; 32],
                    micros: 5,
                    answer: Answer::EnumeratedAndFinished {
                        result: pr.clone(),
                        finished: Ok(Bytes::from_static(&[1, 2, 3])),
                    },
                })),
                Outcome::Done(Box::new(TaskDone {
                    shard_id: 2,
                    digest: [7; 32],
                    micros: 5,
                    answer: Answer::Enumerated {
                        result: pr,
                        hit: Some(4),
                    },
                })),
                Outcome::Failed(TaskFailed {
                    shard_id: 3,
                    error: TaskError::Panicked("boom".into()),
                }),
            ],
            holding: vec![],
        };
        assert_eq!(decode(&encode(&m).unwrap()), Ok(Frame::Msg(m)));
    }

    /// Every kind of task crosses the wire as it was made, a merged result
    /// bit for bit.
    #[test]
    fn tasks_round_trip() {
        let tasks = [
            Task::Enumerate {
                range: 0..40,
                good_enough: Some(0.25),
            },
            Task::EnumerateAndFinish {
                range: 0..u64::MAX,
                context: Bytes::from_static(b"ctx"),
            },
            Task::Finish {
                merged: Box::new(MergedCut {
                    result: PartialResult {
                        range: 0..40,
                        counts: Counts::default(),
                        fixtures: vec![],
                    },
                    micros: 1234,
                }),
                context: Bytes::from_static(b"ctx"),
            },
        ];
        let work = tasks
            .into_iter()
            .enumerate()
            .map(|(i, task)| Assign {
                shard_id: i as u64,
                digest: [5; 32],
                input: None,
                task,
                budget: TaskBudget {
                    setups: Some(i as u64 + 1),
                    fixtures: (i == 1).then_some(250_000),
                    millis: (i == 0).then_some(900),
                },
            })
            .collect();
        let m = Msg::Reply {
            notes: vec![],
            next: Next::Work(work),
        };
        assert_eq!(decode(&encode(&m).unwrap()), Ok(Frame::Msg(m)));
    }

    /// `Assign`'s shared byte fields are on the wire exactly as
    /// `serde_bytes` vectors are.
    #[test]
    fn shared_bytes_keep_the_wire_form() {
        #[derive(Serialize)]
        enum TaskAsVectors {
            #[allow(dead_code)] // only the second kind is encoded
            Enumerate,
            EnumerateAndFinish {
                range: Range<u64>,
                #[serde(with = "serde_bytes")]
                context: Vec<u8>,
            },
        }
        #[derive(Serialize)]
        struct AsVectors {
            shard_id: u64,
            digest: Digest,
            #[serde(with = "serde_bytes")]
            input: Option<Vec<u8>>,
            task: TaskAsVectors,
            budget: TaskBudget,
        }
        for (input, context) in [(Some(vec![1u8, 2, 250]), vec![]), (None, vec![9u8; 300])] {
            let a = Assign {
                shard_id: 7,
                digest: [3; 32],
                input: input.clone().map(Bytes::from),
                task: Task::EnumerateAndFinish {
                    range: 0..40,
                    context: Bytes::from(context.clone()),
                },
                budget: TaskBudget::default(),
            };
            let v = AsVectors {
                shard_id: 7,
                digest: [3; 32],
                input,
                task: TaskAsVectors::EnumerateAndFinish {
                    range: 0..40,
                    context,
                },
                budget: TaskBudget::default(),
            };
            let wire = postcard::to_allocvec(&a).unwrap();
            assert_eq!(wire, postcard::to_allocvec(&v).unwrap());
            assert_eq!(postcard::from_bytes::<Assign>(&wire).unwrap(), a);
        }
    }
}
