//! A run that died stays dead once: `OUT.journal`, beside `OUT.partial`,
//! is an append-only record of which parts were being solved, so that a
//! part in flight when the process was killed hard (SIGKILL, the kernel's
//! OOM killer, an abort) is known to the next `--resume`, and a part that
//! killed the process twice is answered `failed` instead of killing it a
//! third time.
//!
//! Lines (text, one `write` each, never buffered, so they survive the
//! process's death though not the machine's):
//! `session <run message as JSON>` when a run or resume starts,
//! `start <index> <id as JSON>` before a part's solve starts,
//! `done <index>` when its solve and messages are made,
//! `end` when the process stops in order (an error it reports),
//! `end interrupted` when SIGINT or SIGTERM stops it ([`crate::interrupt`]).
//! A session that does not end with `end` died; the parts started and not
//! done in it were in flight at that death.
//!
//! Who is blamed: every part in flight at a death counts it once, so a
//! part solved beside the killer is suspected too. A suspect (one death)
//! is solved **alone**: no other part is in flight while it runs, so a
//! second death during it is its own. A part becomes `failed` only after
//! two deaths, and since its second can only come while it runs alone, a
//! kill never fails a part that was merely beside the killer. A kill from
//! outside (an operator's `kill -9`, an OOM caused by another process) is
//! read as the part's doing: a part that is unlucky twice, the second
//! time alone, is failed; the log says so and a fresh run solves it.
//!
//! The journal is input like any other: a line that does not read, names
//! a part the catalogue does not have at that place, or belongs to a
//! session of another run is ignored and counted in the log. Damage can
//! only add or remove suspicion of a part (a suspect is solved alone: the
//! same bytes), never change a result it did not fail.

use crate::job::{SolveTiming, Solved};
use crate::output::messages::RunMsg;
use anyhow::{bail, Context, Result};
use fixplan_core::{SolveResult, Status};
use std::collections::{BTreeMap, BTreeSet};
use std::fs::{File, OpenOptions};
use std::io::{BufRead, BufReader, Read, Write};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

/// The longest line read: a session line holds the run message (kit,
/// parameters), a few kilobytes; anything longer is damage.
const LINE_MAX: u64 = 1 << 20;

/// `OUT.journal`: where a run records the parts in flight.
pub fn journal_path(output: &Path) -> PathBuf {
    let mut s = output.as_os_str().to_owned();
    s.push(".journal");
    PathBuf::from(s)
}

/// How often a part was in flight when the run died.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct RunDeaths {
    /// RunDeaths it was in flight at.
    pub times: u32,
    /// Of those, deaths at which it was the only part in flight.
    pub alone: u32,
}

/// What the earlier sessions of a journal say.
#[derive(Debug, Default, PartialEq, Eq)]
pub struct History {
    /// Per catalogue index, the deaths its part was in flight at.
    pub deaths: BTreeMap<usize, RunDeaths>,
    /// Sessions that died (did not end in order).
    pub died: usize,
    /// Lines ignored: damaged, or of another run, or naming another part.
    pub ignored: usize,
}

/// A session being read.
#[derive(Default)]
struct Session {
    /// Whether it belongs to this run (else its lines are ignored).
    ours: bool,
    in_flight: BTreeSet<usize>,
    ended: bool,
}

impl History {
    /// Closes a session read to its end: if it died, its parts in flight
    /// count that death.
    fn close(&mut self, session: Option<Session>) {
        let Some(s) = session.filter(|s| s.ours && !s.ended) else {
            return;
        };
        self.died += 1;
        let alone = s.in_flight.len() == 1;
        for i in s.in_flight {
            let d = self.deaths.entry(i).or_default();
            d.times += 1;
            d.alone += u32::from(alone);
        }
    }

    /// Reads the lines of a journal of the run `run` over a catalogue of
    /// `ids`.
    pub fn read(reader: impl Read, run: &RunMsg, ids: &[&str]) -> History {
        let mut h = History::default();
        let mut session: Option<Session> = None;
        let mut reader = BufReader::new(reader);
        let mut line = Vec::new();
        loop {
            line.clear();
            match read_line(&mut reader, &mut line) {
                Ok(None) => break,
                Ok(Some(true)) => {}
                Ok(Some(false)) | Err(_) => {
                    h.ignored += 1;
                    continue;
                }
            }
            let Ok(text) = std::str::from_utf8(&line) else {
                h.ignored += 1;
                continue;
            };
            if let Some(json) = text.strip_prefix("session ") {
                h.close(session.take());
                let ours = serde_json::from_str::<RunMsg>(json).is_ok_and(|m| m.same_run(run));
                h.ignored += usize::from(!ours);
                session = Some(Session {
                    ours,
                    ..Session::default()
                });
                continue;
            }
            let Some(s) = session.as_mut().filter(|s| s.ours && !s.ended) else {
                h.ignored += 1;
                continue;
            };
            if !apply(s, text, ids) {
                h.ignored += 1;
            }
        }
        h.close(session);
        h
    }
}

/// Reads one line (without its newline) into `line`: `None` at the end,
/// `Some(false)` for a line longer than [`LINE_MAX`] (skipped) or one cut
/// off by the end of the file (a write the death interrupted).
fn read_line(reader: &mut impl BufRead, line: &mut Vec<u8>) -> std::io::Result<Option<bool>> {
    let n = reader.take(LINE_MAX).read_until(b'\n', line)?;
    if n == 0 {
        return Ok(None);
    }
    if line.last() == Some(&b'\n') {
        line.pop();
        return Ok(Some(true));
    }
    // Too long, or the last line without its newline: skip to the next.
    let mut rest = Vec::new();
    while reader.take(LINE_MAX).read_until(b'\n', &mut rest)? > 0 {
        if rest.last() == Some(&b'\n') {
            break;
        }
        rest.clear();
    }
    Ok(Some(false))
}

/// Applies a `start`, `done` or `end` line to a session of this run;
/// false if it does not read or names a part not at its place.
fn apply(s: &mut Session, text: &str, ids: &[&str]) -> bool {
    if text == "end" || text == "end interrupted" {
        s.ended = true;
        return true;
    }
    let mut words = text.splitn(3, ' ');
    let (Some(kind), Some(index)) = (words.next(), words.next()) else {
        return false;
    };
    let Ok(i) = index.parse::<usize>() else {
        return false;
    };
    match (kind, words.next()) {
        ("start", Some(id)) => {
            let named = serde_json::from_str::<String>(id).ok();
            if ids.get(i).copied() != named.as_deref() {
                return false;
            }
            s.in_flight.insert(i);
            true
        }
        ("done", None) => s.in_flight.remove(&i),
        _ => false,
    }
}

/// A part's [`Status::Failed`] result after it killed the run twice.
fn condemned(id: &str, d: RunDeaths) -> SolveResult {
    SolveResult::gave_up(
        Status::Failed,
        format!(
            "{id}: killed the process twice while being solved (in flight when the run died {} times, {} of them alone); not solved again",
            d.times, d.alone
        ),
    )
}

/// The journal of a run: what earlier sessions say, and the file this
/// session appends to.
pub struct Journal {
    path: PathBuf,
    /// Shared with the words said on a signal ([`Journal::interrupted_words`]).
    file: Arc<Mutex<File>>,
    history: History,
    /// Catalogue index of job 0.
    first: usize,
    /// The catalogue's part ids.
    ids: Vec<String>,
    /// Whether the file is gone (the run completed).
    closed: bool,
}

/// A journal's path that is there but not a regular file (a FIFO would
/// block the run on opening it): refused, never opened.
fn check_regular(path: &Path) -> Result<()> {
    match std::fs::metadata(path) {
        Ok(m) if !m.is_file() => bail!(
            "{}: not a regular file; remove it (the run keeps its journal there)",
            path.display()
        ),
        _ => Ok(()),
    }
}

impl Journal {
    /// Opens the journal of a run writing to `output`: with `resume` the
    /// earlier sessions are read (a journal of another run reads as
    /// nothing), else it starts empty. Appends this session's line.
    pub fn open(output: &Path, run: &RunMsg, ids: &[&str], resume: bool) -> Result<Journal> {
        let path = journal_path(output);
        check_regular(&path)?;
        let history = match (resume, File::open(&path)) {
            (true, Ok(f)) => History::read(f, run, ids),
            _ => History::default(),
        };
        let file = OpenOptions::new()
            .create(true)
            .append(true)
            .truncate(false)
            .open(&path)
            .with_context(|| format!("{}: cannot open", path.display()))?;
        if !resume {
            file.set_len(0)
                .with_context(|| format!("{}: cannot empty", path.display()))?;
        }
        let journal = Journal {
            path,
            file: Arc::new(Mutex::new(file)),
            history,
            first: 0,
            ids: ids.iter().map(|s| (*s).to_string()).collect(),
            closed: false,
        };
        journal.tell();
        let line = format!("session {}\n", serde_json::to_string(run)?);
        journal.append(&line)?;
        Ok(journal)
    }

    /// Warns of what the earlier sessions say (even with `--quiet`: the
    /// run died before).
    fn tell(&self) {
        let h = &self.history;
        if h.ignored > 0 {
            tracing::warn!(
                role = "coordinator",
                "{}: {} lines ignored (damaged, cut off, or of another run)",
                self.path.display(),
                h.ignored
            );
        }
        for (&i, &d) in &h.deaths {
            let id = self.ids.get(i).map_or("?", String::as_str);
            let what = if d.times >= 2 {
                "answered failed, not solved again"
            } else {
                "solved alone this time"
            };
            tracing::warn!(
                role = "coordinator",
                "part #{i} {id} was being solved when the run died ({} of {} deaths, {} alone): {what}",
                d.times,
                h.died,
                d.alone
            );
        }
    }

    /// Sets the catalogue index of the run's job 0.
    pub fn set_first(&mut self, first: usize) {
        self.first = first;
    }

    fn append(&self, line: &str) -> Result<()> {
        let mut f = self.file.lock().unwrap_or_else(|e| e.into_inner());
        f.write_all(line.as_bytes())
            .with_context(|| format!("{}: cannot write", self.path.display()))
    }

    /// Appends a line the run can go on without: a journal that cannot be
    /// written only loses the protection, which the log says.
    fn note(&self, line: &str) {
        if let Err(e) = self.append(line) {
            tracing::warn!(role = "coordinator", "{e:#}");
        }
    }

    fn deaths(&self, job: usize) -> RunDeaths {
        self.history
            .deaths
            .get(&(self.first + job))
            .copied()
            .unwrap_or_default()
    }

    /// What the journal says when a signal stops the run: `end
    /// interrupted`, so the parts in flight are not suspects; nothing is
    /// written after it (the file stays locked until the process ends).
    pub fn interrupted_words(&self) -> impl Fn() + Send + 'static {
        let file = Arc::clone(&self.file);
        move || {
            let mut f = file.lock().unwrap_or_else(|e| e.into_inner());
            let _ = f.write_all(b"end interrupted\n");
            std::mem::forget(f);
        }
    }

    /// Removes the file: the run completed.
    pub fn remove(mut self) {
        self.closed = true;
        let _ = std::fs::remove_file(&self.path);
    }
}

impl Drop for Journal {
    /// An orderly stop (an error the run reports, a panic unwinding): the
    /// parts in flight did not kill the process.
    fn drop(&mut self) {
        if !self.closed {
            self.note("end\n");
        }
    }
}

/// What the embedded drivers tell of each job and ask before solving it
/// ([`super::solve_in_order`]).
pub trait Watch: Sync {
    /// Job `job`'s result without solving it, if it must not be solved.
    fn verdict(&self, job: usize) -> Option<Solved>;
    /// Whether job `job` must be the only job in flight.
    fn alone(&self, job: usize) -> bool;
    /// Job `job`'s solve starts (after [`Watch::alone`]'s wait).
    fn started(&self, job: usize);
    /// Job `job`'s solve and messages are made.
    fn finished(&self, job: usize);
}

impl Watch for Journal {
    fn verdict(&self, job: usize) -> Option<Solved> {
        let d = self.deaths(job);
        (d.times >= 2).then(|| Solved {
            result: condemned(
                self.ids.get(self.first + job).map_or("?", String::as_str),
                d,
            ),
            timing: SolveTiming::default(),
            search: crate::job::SearchInfo::default(),
        })
    }

    fn alone(&self, job: usize) -> bool {
        self.deaths(job).times == 1
    }

    fn started(&self, job: usize) {
        let i = self.first + job;
        let id = self.ids.get(i).map_or("?", String::as_str);
        let id = serde_json::to_string(id).unwrap_or_default();
        self.note(&format!("start {i} {id}\n"));
        fault::maybe_fail(&self.ids[i]);
    }

    fn finished(&self, job: usize) {
        self.note(&format!("done {}\n", self.first + job));
    }
}

/// `fixplan run --fault abort-on:ID` (tests): the process aborts when
/// part ID's solve starts, as a part that overflows its stack or is
/// killed by the OOM killer ends it; not a panic, which
/// [`crate::job::solve_guarded`] would catch. `--fault stall-on:ID`: part
/// ID's solve never ends, as a part too slow to wait for (the tests of
/// [`crate::interrupt`]).
pub(crate) mod fault {
    use std::sync::OnceLock;

    static ABORT_ON: OnceLock<String> = OnceLock::new();
    static STALL_ON: OnceLock<String> = OnceLock::new();

    /// Makes the process abort when part `id` starts being solved.
    pub fn abort_on(id: &str) {
        let _ = ABORT_ON.set(id.to_string());
    }

    /// Makes part `id`'s solve never end.
    pub fn stall_on(id: &str) {
        let _ = STALL_ON.set(id.to_string());
    }

    pub(super) fn maybe_fail(id: &str) {
        if ABORT_ON.get().is_some_and(|a| a == id) {
            die();
        }
        if STALL_ON.get().is_some_and(|a| a == id) {
            loop {
                std::thread::sleep(std::time::Duration::from_secs(3600));
            }
        }
    }

    /// Aborts the process, without leaving a core file behind in the
    /// tests' directories.
    pub fn die() -> ! {
        let none = libc::rlimit {
            rlim_cur: 0,
            rlim_max: 0,
        };
        // SAFETY: setrlimit reads the struct it is given; nothing else.
        unsafe {
            libc::setrlimit(libc::RLIMIT_CORE, &none);
        }
        std::process::abort()
    }
}

#[cfg(test)]
mod tests;
