//! The one place a worker reads what it is asked ([`Task`]) and does it:
//! [`run`] checks the task, enumerates, finishes, and answers with the
//! [`Answer`] of the task's kind. The `fixplan` binary may put a
//! [`Runner`] of its own around it (its fault injector for tests, its
//! replay for benchmarks): the one seam between a worker and its tasks.

use crate::finish::{FinishInputs, Finisher};
use crate::part_input::{PartInput, WireInputError};
use crate::protocol::{
    Answer, Assign, Digest, FinishError, Outcome, Task, TaskBudget, TaskDone, TaskError, TaskFailed,
};
use bytes::Bytes;
use fixplan_core::{EnumerateOptions, PartialResult, PreparedPart, WorkBudget};
use std::ops::Range;
use std::sync::{Arc, OnceLock};
use std::time::{Duration, Instant};
use tracing::warn;

/// A part's input and the part prepared, or why there is none.
pub type Prepared = Result<(PartInput, PreparedPart), WireInputError>;

/// A part as its tasks find it on a worker: the input its first task
/// brought, prepared once, by whichever of its tasks runs first, on the
/// pool (on the agent's thread, preparing would be a serial stage before
/// every task, a limit for many threads on small parts), and only when a task needs it (a replayed one does not).
pub struct CachedPart {
    digest: Digest,
    input: Option<Bytes>,
    prepared: OnceLock<Arc<Prepared>>,
}

impl CachedPart {
    /// The part of `digest`, from its wire `input` if it came with one.
    pub fn new(digest: Digest, input: Option<Bytes>) -> CachedPart {
        CachedPart {
            digest,
            input,
            prepared: OnceLock::new(),
        }
    }

    /// The part prepared (the first call prepares it; concurrent ones
    /// wait for it).
    pub fn get(&self) -> Arc<Prepared> {
        self.prepared
            .get_or_init(|| {
                Arc::new(PartInput::prepare_wire_kept(
                    &self.digest,
                    self.input.as_deref(),
                ))
            })
            .clone()
    }
}

/// How a worker runs its tasks: [`Plain`] ([`run`]) unless the binary
/// gives another.
pub trait Runner: Send + Sync {
    /// The outcome of `assign` on `part`, finishing with `finisher`
    /// (without one, parts come back unfinished and the coordinator
    /// finishes them).
    fn run(&self, assign: &Assign, part: &CachedPart, finisher: Option<&dyn Finisher>) -> Outcome;
}

/// Runs every task as it is asked ([`run`]).
#[derive(Debug, Default, Clone, Copy)]
pub struct Plain;

impl Runner for Plain {
    fn run(&self, assign: &Assign, part: &CachedPart, finisher: Option<&dyn Finisher>) -> Outcome {
        run(assign, part, finisher)
    }
}

impl std::fmt::Debug for dyn Runner {
    fn fmt(&self, formatter: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        formatter.write_str("Runner")
    }
}

/// A task's checks before it runs: what no coordinator of this version
/// sends.
fn check(task: &Task) -> Result<(), TaskError> {
    match task {
        Task::Enumerate { range, .. } | Task::EnumerateAndFinish { range, .. }
            if range.is_empty() =>
        {
            Err(TaskError::EmptyRange(range.clone()))
        }
        _ => Ok(()),
    }
}

/// Does one task on the calling rayon pool: the worker's one reading of
/// a [`Task`].
pub fn run(assign: &Assign, part: &CachedPart, finisher: Option<&dyn Finisher>) -> Outcome {
    let failed = |error| {
        Outcome::Failed(TaskFailed {
            shard_id: assign.shard_id,
            error,
        })
    };
    if let Err(e) = check(&assign.task) {
        return failed(e);
    }
    let prepared = part.get();
    let (input, prep) = match prepared.as_ref() {
        Ok((input, prep)) => (input, prep),
        Err(e) => return failed(TaskError::from(e)),
    };
    let done = |micros, answer| {
        Outcome::Done(Box::new(TaskDone {
            shard_id: assign.shard_id,
            digest: assign.digest,
            micros,
            answer,
        }))
    };
    let finish = |result: &PartialResult, micros, context: &Bytes| {
        finished(
            finisher,
            &FinishInputs {
                input,
                prep,
                result,
                micros,
                context,
            },
        )
    };
    match &assign.task {
        Task::Enumerate { range, good_enough } => {
            match enumerate(prep, range, *good_enough, assign.budget) {
                Ok((result, hit, micros)) => done(micros, Answer::Enumerated { result, hit }),
                Err(e) => failed(e),
            }
        }
        Task::EnumerateAndFinish { range, context } => {
            match enumerate(prep, range, None, assign.budget) {
                Ok((result, _, micros)) => {
                    let finished = finish(&result, micros, context);
                    done(micros, Answer::EnumeratedAndFinished { result, finished })
                }
                Err(e) => failed(e),
            }
        }
        Task::Finish { merged, context } => {
            let t0 = Instant::now();
            let finished = finish(&merged.result, merged.micros, context);
            done(micros_since(t0), Answer::Finished(finished))
        }
    }
}

/// Microseconds since `t`.
fn micros_since(start: Instant) -> u64 {
    u64::try_from(start.elapsed().as_micros()).unwrap_or(u64::MAX)
}

/// The enumeration of `range`, or with `good_enough` of its shortest
/// prefix that admits a fixture scoring that or better (with the hit
/// index), and its time; a panic, or going beyond `budget`, is the
/// task's failure.
fn enumerate(
    prep: &PreparedPart,
    range: &Range<u64>,
    good_enough: Option<f64>,
    budget: TaskBudget,
) -> Result<(PartialResult, Option<u64>, u64), TaskError> {
    let t0 = Instant::now();
    let deadline = budget.millis.map(|ms| t0 + Duration::from_millis(ms));
    let work =
        WorkBudget::new(budget.setups, deadline).with_fixtures(budget.fixtures, prep.top_k());
    let out = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        let options = EnumerateOptions {
            good_enough,
            budget: work.is_limited().then_some(&work),
            ..EnumerateOptions::default()
        };
        prep.enumerate(range.clone(), options)
    }));
    match out {
        Ok(done) => match work.verdict(
            done.halted,
            done.result.counts.setups,
            done.result.fixtures.len(),
        ) {
            Some(halt) => Err(TaskError::OverBudget(halt.into())),
            None => Ok((done.result, done.stopped_at, micros_since(t0))),
        },
        Err(p) => Err(TaskError::Panicked(crate::panic_text(p))),
    }
}

/// A part finished by `finisher`, or why not (logged: the coordinator
/// then finishes it from its result).
pub fn finished(
    finisher: Option<&dyn Finisher>,
    inputs: &FinishInputs,
) -> Result<Bytes, FinishError> {
    let finisher = finisher.ok_or(FinishError::NoFinisher)?;
    let out = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| finisher.finish(inputs)))
        .unwrap_or_else(|p| Err(FinishError::Panicked(crate::panic_text(p))));
    if let Err(e) = &out {
        warn!("could not finish a part here ({e}): the coordinator will");
    }
    out.map(Bytes::from)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::part_input::{digest, sample_input};
    use crate::protocol::MergedCut;

    fn assign(part: &[u8], task: Task) -> Assign {
        Assign {
            shard_id: 4,
            digest: digest(part),
            input: None,
            task,
            budget: TaskBudget::default(),
        }
    }

    #[test]
    fn tasks_running_at_once_prepare_their_part_once() {
        let bytes = sample_input().encode().unwrap();
        let part = CachedPart::new(digest(&bytes), Some(bytes.into()));
        let got: Vec<_> = std::thread::scope(|s| {
            let handles: Vec<_> = (0..4).map(|_| s.spawn(|| part.get())).collect();
            handles.into_iter().map(|h| h.join().unwrap()).collect()
        });
        assert!(got[0].is_ok());
        assert!(got.iter().all(|p| Arc::ptr_eq(p, &got[0])));
        // A part whose input never came fails its tasks by name.
        let missing = CachedPart::new([0; 32], None);
        let out = run(
            &assign(
                &[],
                Task::Enumerate {
                    range: 0..10,
                    good_enough: None,
                },
            ),
            &missing,
            None,
        );
        assert_eq!(
            out,
            Outcome::Failed(TaskFailed {
                shard_id: 4,
                error: TaskError::MissingInput
            })
        );
    }

    /// Each kind of task answers with its own kind of answer.
    #[test]
    fn each_task_gets_its_own_kind_of_answer() {
        let bytes = sample_input().encode().unwrap();
        let part = CachedPart::new(digest(&bytes), Some(bytes.clone().into()));
        let answer = |task| match run(&assign(&bytes, task), &part, None) {
            Outcome::Done(d) => d.answer,
            Outcome::Failed(f) => panic!("{}", f.error),
        };
        let Answer::Enumerated { result, hit: None } = answer(Task::Enumerate {
            range: 0..u64::MAX,
            good_enough: None,
        }) else {
            panic!("not an enumeration")
        };
        assert!(result.counts.combinations > 0);
        let context = Bytes::from_static(b"ctx");
        assert_eq!(
            answer(Task::EnumerateAndFinish {
                range: 0..u64::MAX,
                context: context.clone(),
            }),
            Answer::EnumeratedAndFinished {
                result: result.clone(),
                finished: Err(FinishError::NoFinisher),
            }
        );
        let merged = Box::new(MergedCut { result, micros: 9 });
        assert_eq!(
            answer(Task::Finish { merged, context }),
            Answer::Finished(Err(FinishError::NoFinisher))
        );
        // An empty range is refused before anything runs.
        let empty = run(
            &assign(
                &bytes,
                Task::Enumerate {
                    range: 3..3,
                    good_enough: None,
                },
            ),
            &part,
            None,
        );
        assert!(matches!(
            empty,
            Outcome::Failed(TaskFailed {
                error: TaskError::EmptyRange(_),
                ..
            })
        ));
    }
}
