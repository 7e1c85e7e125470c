//! The one place the coordinator makes a worker's [`Task`] (from the
//! part and the scheduler's [`ShardWork`]), and tells which [`Answer`] a task
//! expects: a part sent whole is enumerated and finished by its worker if
//! the caller asked for that, a shard is enumerated, a cut part whose
//! shards are merged is finished.

use super::state::{PartSlot, Settings, ShardSlot, ShardWork, WHOLE};
use fixplan_worker::protocol::{Answer, Task};

/// The kinds of task, as [`kind`] picks them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    Enumerate,
    EnumerateAndFinish,
    Finish,
}

/// Which task `sh` of `part` is.
fn kind(part: &PartSlot, sh: &ShardSlot) -> Kind {
    match &sh.work {
        ShardWork::Combinations(range) if *range == WHOLE && part.finish.is_some() => {
            Kind::EnumerateAndFinish
        }
        ShardWork::Combinations(_) => Kind::Enumerate,
        ShardWork::Finishing(_) => Kind::Finish,
    }
}

/// The task of `sh` of `part`; `None` for a finishing whose part was
/// delivered or merged again since (it is done: nothing to hand out).
pub(super) fn task(part: &PartSlot, sh: &ShardSlot, settings: &Settings) -> Option<Task> {
    let context = || part.finish.clone();
    Some(match (&sh.work, kind(part, sh)) {
        (ShardWork::Combinations(range), Kind::EnumerateAndFinish) => Task::EnumerateAndFinish {
            range: range.clone(),
            context: context()?,
        },
        (ShardWork::Combinations(range), _) => Task::Enumerate {
            range: range.clone(),
            good_enough: settings.good_enough,
        },
        (ShardWork::Finishing(merged), _) => Task::Finish {
            merged: merged.clone()?,
            context: context()?,
        },
    })
}

/// Whether `answer` is of the kind task `sh` of `part` asks for.
pub(super) fn expects(part: &PartSlot, sh: &ShardSlot, answer: &Answer) -> bool {
    matches!(
        (kind(part, sh), answer),
        (Kind::Enumerate, Answer::Enumerated { .. })
            | (
                Kind::EnumerateAndFinish,
                Answer::EnumeratedAndFinished { .. }
            )
            | (Kind::Finish, Answer::Finished(_))
    )
}
