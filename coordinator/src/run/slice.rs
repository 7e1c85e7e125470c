//! A catalogue over several coordinators: `fixplan coordinator --slice K/N`
//! runs the K-th of N consecutive slices of the parts, and `fixplan merge`
//! joins the slices' results files into the file one coordinator would
//! have written. One coordinator's own work per part bounds the workers it
//! keeps busy (deploy/README.md); slices multiply that.
//!
//! A slice's file holds the whole run's message and its parts under their
//! places in the whole catalogue, so merging copies messages as they are:
//! the merged file's fixtures and scenes are the whole run's, byte for
//! byte, and its chunks close at the same parts ([`ResultsWriter`]).

use super::resume::{close_output, partial_path};
use crate::output::messages::RunMsg;
use crate::output::{PartMessages, ResultsFile, ResultsWriter};
use anyhow::{bail, Context, Result};
use std::fs::File;
use std::ops::Range;
use std::path::{Path, PathBuf};

/// `--slice K/N`: the K-th (from 1) of N consecutive, nearly equal slices
/// of a catalogue's parts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Slice {
    /// Which slice, from 1.
    pub k: usize,
    /// Slices in all.
    pub n: usize,
}

/// A `--slice` value that is not `K/N` with `1 <= K <= N`.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("slice {0:?} is not K/N with 1 <= K <= N (e.g. 2/8)")]
pub struct BadSlice(String);

impl std::str::FromStr for Slice {
    type Err = BadSlice;
    fn from_str(text: &str) -> Result<Self, BadSlice> {
        let bad = || BadSlice(text.to_string());
        let (k, n) = text.split_once('/').ok_or_else(bad)?;
        let (k, n) = (
            k.trim().parse().map_err(|_| bad())?,
            n.trim().parse().map_err(|_| bad())?,
        );
        if k == 0 || k > n {
            return Err(bad());
        }
        Ok(Slice { k, n })
    }
}

impl Slice {
    /// The parts of this slice among `total`.
    pub fn parts(self, total: usize) -> Range<usize> {
        let at = |k: usize| k * total / self.n;
        at(self.k - 1)..at(self.k)
    }
}

/// What `fixplan merge` wrote.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Merged {
    /// Input files read.
    pub files: usize,
    /// Parts written (the whole catalogue).
    pub parts: usize,
}

/// One input: its run message and the place of its first part.
struct Input {
    path: PathBuf,
    file: ResultsFile,
    run: RunMsg,
    first: Option<usize>,
}

fn open_input(path: &Path) -> Result<Input> {
    let file = ResultsFile::open(path)?;
    let mut first = None;
    let contents = file.for_each_part(|_, m| {
        first = Some(m.index);
        false
    })?;
    contents.sound(&file.path)?;
    if !contents.complete {
        bail!(
            "{}: not a finished run (no summary); finish it with --resume first",
            path.display()
        );
    }
    Ok(Input {
        path: path.to_path_buf(),
        file,
        run: contents.run,
        first,
    })
}

/// Copies the parts of `input` into `w`, checking they continue at `next`;
/// returns the place after its last part.
fn copy_parts(input: &Input, writer: &mut ResultsWriter, mut next: usize) -> Result<usize> {
    let mut failed: Option<anyhow::Error> = None;
    let mut put = |m: PartMessages| -> Result<()> {
        if m.index != next {
            let what = if m.index < next {
                "again"
            } else {
                "after a gap"
            };
            bail!(
                "{}: part #{} comes {what} (expected part #{next}): the slices overlap or one is missing",
                input.path.display(),
                m.index
            );
        }
        writer.write_part(&m)?;
        next += 1;
        Ok(())
    };
    input.file.for_each_part(|_, m| match put(m) {
        Ok(()) => true,
        Err(e) => {
            failed = Some(e);
            false
        }
    })?;
    match failed {
        Some(e) => Err(e),
        None => Ok(next),
    }
}

/// `fixplan merge`: the results files of a run's slices (any order) into
/// `output`, checked to be of the same run (catalogue, kit, parameters,
/// version) and to hold every part of the catalogue exactly once.
pub fn merge_files(inputs: &[PathBuf], output: &Path) -> Result<Merged> {
    let mut files = inputs
        .iter()
        .map(|p| open_input(p))
        .collect::<Result<Vec<_>>>()?;
    let Some(run) = files.first().map(|f| f.run.clone()) else {
        bail!("nothing to merge");
    };
    if let Some(other) = files.iter().find(|f| !run.same_run(&f.run)) {
        bail!(
            "{} and {} are not of the same run (catalogue content, kit, parameters or fixplan version differ)",
            files[0].path.display(),
            other.path.display()
        );
    }
    // Slices are consecutive: in the order of their first parts.
    files.sort_by_key(|f| f.first);
    let parts = write_merged(&files, &run, output).inspect_err(|_| {
        let _ = std::fs::remove_file(partial_path(output));
    })?;
    Ok(Merged {
        files: files.len(),
        parts,
    })
}

/// Writes the parts of `files` (sorted) into `output` through
/// `OUT.partial`, as a run does; returns how many.
fn write_merged(files: &[Input], run: &RunMsg, output: &Path) -> Result<usize> {
    let partial = partial_path(output);
    let file =
        File::create(&partial).with_context(|| format!("{}: cannot create", partial.display()))?;
    let mut w = ResultsWriter::create(file, run)?;
    let mut next = 0;
    for f in files.iter().filter(|f| f.first.is_some()) {
        next = copy_parts(f, &mut w, next)?;
    }
    if next != run.catalog.parts {
        bail!(
            "parts #{next} to #{} of {} are in none of the files: a slice is missing",
            run.catalog.parts.saturating_sub(1),
            run.catalog.name
        );
    }
    close_output(w, output)?;
    Ok(next)
}

#[cfg(test)]
mod tests {
    use super::Slice;

    #[test]
    fn slices_cover_the_catalogue_once() {
        for total in [0, 1, 7, 35, 1000] {
            for n in 1..=9 {
                let ranges: Vec<_> = (1..=n).map(|k| Slice { k, n }.parts(total)).collect();
                assert_eq!(ranges[0].start, 0);
                assert_eq!(ranges[n - 1].end, total);
                assert!(ranges.windows(2).all(|w| w[0].end == w[1].start));
            }
        }
        assert_eq!("2/8".parse(), Ok(Slice { k: 2, n: 8 }));
        for bad in ["0/3", "4/3", "2", "a/b", "1/0"] {
            assert!(bad.parse::<Slice>().is_err(), "{bad}");
        }
    }
}
