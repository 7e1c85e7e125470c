//! `fixplan worker --fault`: a worker that misbehaves on purpose, for the
//! tests of the coordinator's checks. A fault is a [`Runner`] around the
//! worker's plain one ([`fixplan_worker::task::run`]), the one seam
//! between a worker and its tasks; the honest code knows nothing of it.

use fixplan_worker::finish::{FinishInputs, Finisher};
use fixplan_worker::protocol::{Answer, Assign, FinishError, Outcome, Task};
use fixplan_worker::task::{self, CachedPart, Runner};
use std::time::Duration;
use thiserror::Error;

/// Misbehaviours for tests of the coordinator's checks.
#[derive(Debug, Clone, Copy, PartialEq)]
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
}

/// A `--fault` value that names no [`Fault`].
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum FaultError {
    /// None of `corrupt-score`, `forge-finished`, `slow:MS`.
    #[error("unknown fault {0:?} (corrupt-score, forge-finished, slow:MS)")]
    Unknown(String),
    /// `slow:` without a number of milliseconds.
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
        if let Some(ms) = s.strip_prefix("slow:") {
            return ms
                .parse()
                .map(Fault::SlowMs)
                .map_err(|source| FaultError::SlowMs {
                    text: s.to_string(),
                    source,
                });
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
