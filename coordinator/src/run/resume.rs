//! Where a run writes, and how an interrupted one is continued: a run
//! writes `OUT.partial` and renames it when complete; the complete chunks
//! of a killed run's file are a prefix of the catalogue, which `--resume`
//! copies into a fresh file before carrying on.

use super::progress::Progress;
use crate::output::messages::{PartMsg, RunMsg};
use crate::output::{PartMessages, ReadError, ResultsFile, ResultsWriter};
use anyhow::{bail, Context, Result};
use std::fs::File;
use std::ops::Range;
use std::path::{Path, PathBuf};

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
    run_msg: &RunMsg,
    parts: Range<usize>,
    progress: &mut Progress,
) -> Result<(ResultsWriter, usize)> {
    let partial = partial_path(output);
    let first = parts.start;
    if resume && partial.exists() {
        if let Some(r) = resume_from(&partial, run_msg, parts, progress)? {
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

/// Copies the parts of `old` that are complete and in order, of the run's
/// `parts`, into `w`.
fn copy_finished(
    old: &ResultsFile,
    run_msg: &RunMsg,
    parts: Range<usize>,
    w: &mut ResultsWriter,
    progress: &mut Progress,
) -> Result<Result<Copied, ReadError>> {
    let mut next = parts.start;
    let mut other_run = false;
    let mut write_err = None;
    let read = old.for_each_part(|run, m: PartMessages| {
        if !run.same_run(run_msg) {
            other_run = true;
            return false;
        }
        if m.index != next || !parts.contains(&next) {
            return false;
        }
        if let Err(e) = w.write_part(&m) {
            write_err = Some(e);
            return false;
        }
        if let Ok(p) = m.decode::<PartMsg>() {
            let (status, counts) = (p.status.into(), p.counts.as_ref().map(Into::into));
            let admissible = super::outcome::admissible_found(status, counts);
            progress.resumed(status, admissible, p.fixtures);
        }
        next += 1;
        true
    });
    if let Some(e) = write_err {
        return Err(e.into());
    }
    Ok(read.map(|_| {
        if other_run {
            Copied::OtherRun
        } else {
            Copied::Parts(next)
        }
    }))
}

/// Copies the finished parts of an interrupted run into a new writer.
/// Returns the writer and the index of the first part still to do, or
/// `None` when the old file holds nothing usable.
fn resume_from(
    partial: &Path,
    run_msg: &RunMsg,
    parts: Range<usize>,
    progress: &mut Progress,
) -> Result<Option<(ResultsWriter, usize)>> {
    let first = parts.start;
    let old = match ResultsFile::open(partial) {
        Ok(f) => f,
        Err(e) => bail!("{e}"),
    };
    let mut new_path = partial.as_os_str().to_owned();
    new_path.push(".new");
    let new_path = PathBuf::from(new_path);
    let file = File::create(&new_path)
        .with_context(|| format!("{}: cannot create", new_path.display()))?;
    let mut w = ResultsWriter::create(file, run_msg)?;
    let next = match copy_finished(&old, run_msg, parts, &mut w, progress)? {
        Err(ReadError::Format { message, .. }) => {
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
                "{} was written by a different run (catalogue content, kit, parameters or fixplan version differ); \
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
