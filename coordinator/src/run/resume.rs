//! Where a run writes, and how an interrupted one is continued: a run
//! writes `OUT.partial` and renames it when complete; the complete chunks
//! of a killed run's file are a prefix of the catalogue, which `--resume`
//! copies into a fresh file before carrying on. Only sound parts are
//! copied (the reader checks each chunk's CRC, decompression and
//! messages; this checks the run, the catalogue digest and each part's
//! place and id): from the first part that fails, the run is redone, and
//! the log says which part and why.

use super::progress::Progress;
use crate::output::messages::{PartMsg, RunMsg};
use crate::output::reader::Contents;
use crate::output::{PartMessages, ResultsFile, ResultsFileError, ResultsWriter};
use anyhow::{bail, Context, Result};
use std::fs::File;
use std::ops::Range;
use std::path::{Path, PathBuf};

/// What a run is: its message, which of the catalogue's parts it solves
/// and the catalogue's part ids (each kept part must hold its own).
pub struct RunParts<'a> {
    /// The run message.
    pub message: &'a RunMsg,
    /// The catalogue's parts this run solves (all but for a slice).
    pub parts: Range<usize>,
    /// Every part id of the catalogue, in order.
    pub ids: Vec<&'a str>,
}

/// `OUT.partial`: where an unfinished run writes.
pub fn partial_path(output: &Path) -> PathBuf {
    let mut s = output.as_os_str().to_owned();
    s.push(".partial");
    PathBuf::from(s)
}

/// The writer of this run and the index of the first part it still has to
/// solve: a fresh `OUT.partial` (the run's `parts`: not all of them for a
/// slice), or with `resume` the one found there, its finished parts kept.
pub fn open_output(
    output: &Path,
    resume: bool,
    run: &RunParts,
    progress: &mut Progress,
) -> Result<(ResultsWriter, usize)> {
    let (run_msg, parts) = (run.message, run.parts.clone());
    let partial = partial_path(output);
    let first = parts.start;
    if resume && partial.exists() {
        if let Some(r) = resume_from(&partial, run, progress)? {
            return Ok(r);
        }
    } else if resume {
        progress.log(&format!(
            "no interrupted run at {}; starting from the beginning",
            partial.display()
        ));
    } else if partial.exists() {
        progress.log(&format!(
            "overwriting the interrupted run at {} (use --resume to continue it)",
            partial.display()
        ));
    }
    let file =
        File::create(&partial).with_context(|| format!("{}: cannot create", partial.display()))?;
    Ok((ResultsWriter::create(file, run_msg)?, first))
}

/// Finishes the writer and renames `OUT.partial` to `OUT`.
pub fn close_output(writer: ResultsWriter, output: &Path) -> Result<()> {
    let partial = partial_path(output);
    let file = writer
        .finish()
        .with_context(|| format!("finishing {}", partial.display()))?;
    file.sync_all().ok();
    drop(file);
    std::fs::rename(&partial, output).with_context(|| {
        format!(
            "cannot rename {} to {}",
            partial.display(),
            output.display()
        )
    })
}

/// What copying the finished parts of an old file ended on.
enum Copied {
    /// The parts up to `next` (excluded) copied, in order.
    Parts(usize),
    /// The file was written by another run.
    OtherRun,
}

/// Why the copy stopped before the parts the old file holds, if it did.
fn stop_reason(next: usize, contents: &Contents, mismatch: Option<String>) -> Option<String> {
    if let Some(m) = mismatch {
        return Some(m);
    }
    let damage: Vec<String> = contents.damage.iter().map(ToString::to_string).collect();
    if !damage.is_empty() {
        return Some(damage.join("; "));
    }
    contents
        .parts
        .iter()
        .any(|&p| p >= next)
        .then(|| format!("part #{next} is not where it should be"))
}

/// Copies the parts of `old` that are sound, complete and in order, of
/// the run's parts, into `w`; logs why it stopped before the end of what
/// the file holds.
fn copy_finished(
    old: &ResultsFile,
    run: &RunParts,
    w: &mut ResultsWriter,
    progress: &mut Progress,
) -> Result<Result<Copied, ResultsFileError>> {
    let mut next = run.parts.start;
    let mut other_run = false;
    let mut write_err = None;
    let mut mismatch = None;
    let read = old.for_each_part(|file_run, m: PartMessages| {
        if !file_run.same_run(run.message) {
            other_run = true;
            return false;
        }
        if m.index != next || !run.parts.contains(&next) {
            return false;
        }
        let Ok(p) = m.decode::<PartMsg>() else {
            mismatch = Some(format!("part #{next}: its part message does not decode"));
            return false;
        };
        if run.ids.get(next) != Some(&p.id.as_str()) {
            mismatch = Some(format!(
                "part #{next} holds part {:?}, not {:?}",
                p.id,
                run.ids.get(next).copied().unwrap_or("(none)")
            ));
            return false;
        }
        if let Err(e) = w.write_part(&m) {
            write_err = Some(e);
            return false;
        }
        let (status, counts) = (p.status.into(), p.counts.as_ref().map(Into::into));
        let admissible = super::outcome::admissible_found(status, counts);
        progress.resumed(status, admissible, p.fixtures);
        next += 1;
        true
    });
    if let Some(e) = write_err {
        return Err(e.into());
    }
    Ok(read.map(|contents| {
        if other_run {
            return Copied::OtherRun;
        }
        if let Some(why) = stop_reason(next, &contents, mismatch) {
            progress.log(&format!("{}: {why}; redoing from part #{next}", old.path));
        }
        Copied::Parts(next)
    }))
}

/// Copies the finished parts of an interrupted run into a new writer.
/// Returns the writer and the index of the first part still to do, or
/// `None` when the old file holds nothing usable.
fn resume_from(
    partial: &Path,
    run: &RunParts,
    progress: &mut Progress,
) -> Result<Option<(ResultsWriter, usize)>> {
    let first = run.parts.start;
    let old = match ResultsFile::open(partial) {
        Ok(f) => f,
        Err(e) => bail!("{e}"),
    };
    let mut new_path = partial.as_os_str().to_owned();
    new_path.push(".new");
    let new_path = PathBuf::from(new_path);
    let file = File::create(&new_path)
        .with_context(|| format!("{}: cannot create", new_path.display()))?;
    let mut w = ResultsWriter::create(file, run.message)?;
    let next = match copy_finished(&old, run, &mut w, progress)? {
        Err(ResultsFileError::Format { message, .. }) => {
            progress.log(&format!(
                "{}: nothing usable to resume ({message}); starting from the beginning",
                partial.display()
            ));
            let _ = std::fs::remove_file(&new_path);
            return Ok(None);
        }
        Err(e) => return Err(e.into()),
        Ok(Copied::OtherRun) => {
            let _ = std::fs::remove_file(&new_path);
            bail!(
                "{} was written by a different run (catalogue content, kit, parameters, budgets or fixplan version differ); \
                 delete it or run without --resume",
                partial.display()
            );
        }
        Ok(Copied::Parts(next)) => next,
    };
    std::fs::rename(&new_path, partial).with_context(|| {
        format!(
            "cannot rename {} to {}",
            new_path.display(),
            partial.display()
        )
    })?;
    progress.log(&format!(
        "resuming {}: {} parts already done",
        partial.display(),
        next - first
    ));
    Ok(Some((w, next)))
}
