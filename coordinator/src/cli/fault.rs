//! `fixplan worker --fault`: a worker that misbehaves on purpose, for the
//! tests of the coordinator's checks. A fault is a [`Runner`] around the
//! worker's plain one ([`fixplan_worker::task::run`]), the one seam
//! between a worker and its tasks; the honest code knows nothing of it.
//! `fixplan run --fault abort-on:ID` and `stall-on:ID` are the faults of
//! a run in this process: it dies on a part as a part that kills it
//! would, or never ends a part's solve.

use fixplan_worker::finish::{FinishInputs, Finisher};
use fixplan_worker::protocol::{Answer, Assign, FinishError, Outcome, Task};
use fixplan_worker::task::{self, CachedPart, Runner};
use std::time::Duration;
use thiserror::Error;

/// Misbehaviours for tests of the coordinator's checks.
#[derive(Debug, Clone, PartialEq)]
pub enum Fault {
    /// Halve the score of the best fixture of every enumeration (and
    /// finish parts from the halved result).
    CorruptScore,
    /// Finish parts (whole or cut) with a made-up timing: honest results,
    /// finished parts that are not what they make.
    ForgeFinished,
    /// Take this much longer over every enumeration (a slow machine: the
    /// run lasts as long whatever the size of its assignments, which tests
    /// that upset a worker mid-run rely on).
    SlowMs(u64),
    /// `fixplan run`: abort the process when this part's solve starts
    /// (not a panic, which the run catches).
    AbortOn(String),
    /// `fixplan run`: never finish this part's solve (a part too slow to
    /// wait for, which only a signal stops).
    StallOn(String),
    /// A worker: abort the process on any task of a part whose outline
    /// has this many vertices (a worker knows no part ids).
    AbortOnVertices(usize),
}

/// A `--fault` value that names no [`Fault`].
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum FaultError {
    /// None of the faults.
    #[error("unknown fault {0:?} (corrupt-score, forge-finished, slow:MS, abort-on:ID, stall-on:ID, abort-on-vertices:N)")]
    Unknown(String),
    /// `slow:` or `abort-on-vertices:` without a number.
    #[error("{text}: {source}")]
    SlowMs {
        /// The value given.
        text: String,
        /// Why it is not a number.
        source: std::num::ParseIntError,
    },
}

impl std::str::FromStr for Fault {
    type Err = FaultError;
    fn from_str(s: &str) -> Result<Self, FaultError> {
        if s == "corrupt-score" {
            return Ok(Fault::CorruptScore);
        }
        if s == "forge-finished" {
            return Ok(Fault::ForgeFinished);
        }
        let number = |text: &str| {
            text.parse::<u64>().map_err(|source| FaultError::SlowMs {
                text: s.to_string(),
                source,
            })
        };
        if let Some(ms) = s.strip_prefix("slow:") {
            return number(ms).map(Fault::SlowMs);
        }
        if let Some(n) = s.strip_prefix("abort-on-vertices:") {
            return number(n).map(|n| Fault::AbortOnVertices(n as usize));
        }
        if let Some(id) = s.strip_prefix("abort-on:") {
            return Ok(Fault::AbortOn(id.to_string()));
        }
        if let Some(id) = s.strip_prefix("stall-on:") {
            return Ok(Fault::StallOn(id.to_string()));
        }
        Err(FaultError::Unknown(s.to_string()))
    }
}

/// The forger's extra time on every finished part.
const FORGED_MICROS: u64 = 1_000_000;

/// Halves the best fixture's score of `result`.
fn corrupt(result: &mut fixplan_core::PartialResult) {
    if let Some(f) = result.fixtures.first_mut() {
        f.score *= 0.5;
    }
}

/// How a faulty worker's finishing departs from the honest one.
#[derive(Debug, Clone, Copy)]
enum Tamper {
    /// From the result with its best score halved.
    HalveBest,
    /// With the forged timing.
    ForgeTiming,
}

/// The worker's finisher as a faulty worker uses it.
struct FaultyFinisher<'a> {
    tamper: Tamper,
    honest: &'a dyn Finisher,
}

impl Finisher for FaultyFinisher<'_> {
    fn finish(&self, inputs: &FinishInputs) -> Result<Vec<u8>, FinishError> {
        match self.tamper {
            Tamper::HalveBest => {
                let mut result = inputs.result.clone();
                corrupt(&mut result);
                self.honest.finish(&FinishInputs {
                    result: &result,
                    ..*inputs
                })
            }
            Tamper::ForgeTiming => self.honest.finish(&FinishInputs {
                micros: inputs.micros + FORGED_MICROS,
                ..*inputs
            }),
        }
    }

    fn check(&self, inputs: &FinishInputs, theirs: &[u8]) -> Result<(), FinishError> {
        self.honest.check(inputs, theirs)
    }
}

impl Runner for Fault {
    fn run(&self, a: &Assign, part: &CachedPart, finisher: Option<&dyn Finisher>) -> Outcome {
        // A cut part's finishing enumerates nothing: only the forger
        // touches it.
        let enumerates = !matches!(a.task, Task::Finish { .. });
        let tamper = match *self {
            Fault::AbortOnVertices(n) => {
                let prepared = part.get();
                if matches!(prepared.as_ref(), Ok((input, _)) if input.part.outline.len() == n) {
                    crate::run::journal::fault::die();
                }
                None
            }
            Fault::AbortOn(_) | Fault::StallOn(_) => None,
            Fault::SlowMs(ms) => {
                if enumerates {
                    std::thread::sleep(Duration::from_millis(ms));
                }
                None
            }
            Fault::CorruptScore => enumerates.then_some(Tamper::HalveBest),
            Fault::ForgeFinished => Some(Tamper::ForgeTiming),
        };
        let faulty = match (tamper, finisher) {
            (Some(tamper), Some(honest)) => Some(FaultyFinisher { tamper, honest }),
            _ => None,
        };
        let finisher = match &faulty {
            Some(f) => Some(f as &dyn Finisher),
            None => finisher,
        };
        let mut out = task::run(a, part, finisher);
        if let (Some(Tamper::HalveBest), Outcome::Done(done)) = (tamper, &mut out) {
            if let Answer::Enumerated { result, .. }
            | Answer::EnumeratedAndFinished { result, .. } = &mut done.answer
            {
                corrupt(result);
            }
        }
        out
    }
}
#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn faults_read_from_the_command_line() {
        assert_eq!("corrupt-score".parse(), Ok(Fault::CorruptScore));
        assert_eq!("forge-finished".parse(), Ok(Fault::ForgeFinished));
        assert_eq!("slow:150".parse(), Ok(Fault::SlowMs(150)));
        assert_eq!("abort-on:a b".parse(), Ok(Fault::AbortOn("a b".into())));
        assert_eq!("stall-on:x".parse(), Ok(Fault::StallOn("x".into())));
        assert_eq!("abort-on-vertices:7".parse(), Ok(Fault::AbortOnVertices(7)));
        assert!(matches!(
            "slow:x".parse::<Fault>(),
            Err(FaultError::SlowMs { .. })
        ));
        assert_eq!(
            "lie".parse::<Fault>(),
            Err(FaultError::Unknown("lie".into()))
        );
    }
}
