//! `fixplan show` and `fixplan export`: a results file as terminal tables
//! or as JSON lines.

use crate::drawing::hole_contacts::hole_contact_label;
use crate::output::fields::StatusName;
use crate::output::messages::FixturesMsg;
use crate::output::reader::{for_each_decoded, for_each_record, PartRecord};
use crate::output::writer::PartMessages;
use anyhow::Result;
use fixplan_core::parts::edges_of;
use fixplan_core::{Counts, FixtureReport, SegmentKind, Status, Vertex};

use std::io::Write;
use std::path::Path;

/// A status as the results file's JSON writes it, so the tables and the
/// gallery's CSS classes use the same words.
pub fn status_word(status: Status) -> &'static str {
    StatusName::from(status).text()
}

fn warn_incomplete(path: &Path, complete: bool, truncated: &Option<String>) {
    if !complete {
        eprintln!(
            "warning: {} has no summary (an interrupted run?); showing the parts it holds{}",
            path.display(),
            truncated
                .as_ref()
                .map(|t| format!(" (stopped at: {t})"))
                .unwrap_or_default()
        );
    }
}

/// Prints the ranking of each part (or of `part` only), `top` rows each
/// (`0`: all kept fixtures).
pub fn show(path: &Path, part: Option<&str>, top: usize, out: &mut dyn Write) -> Result<()> {
    let contents = for_each_record(path, part, |_, rec| print_part(rec, top, out))?;
    warn_incomplete(path, contents.complete, &contents.truncated);
    if part.is_none() {
        writeln!(
            out,
            "{} parts; kit {}; catalogue {} ({})",
            contents.parts.len(),
            contents.run.kit_name,
            contents.run.catalog.name,
            contents.run.catalog.digest
        )?;
    }
    Ok(())
}

/// The admissible count, or what a top-k mode result says instead of it.
pub(super) fn admissible_word(counts: &Counts) -> String {
    counts
        .admissible()
        .map_or("not counted (top-k mode)".into(), |a| a.to_string())
}

pub(super) fn print_part(rec: &PartRecord, top: usize, out: &mut dyn Write) -> Result<()> {
    let p = &rec.part;
    let u = p.units.text();
    write!(out, "== {} [{}]", p.id, p.status.text())?;
    if let Some(c) = p.counts.as_ref().map(Counts::from) {
        write!(
            out,
            "  segments {}  setups {}  candidates {}  admissible {}",
            c.segments,
            c.setups,
            c.candidates,
            admissible_word(&c)
        )?;
    }
    writeln!(out)?;
    if let Some(e) = &p.error {
        writeln!(out, "   {e}")?;
    }
    for w in &p.warnings {
        writeln!(out, "   warning: {w}")?;
    }
    let result = rec.fixtures.result();
    let arcs = ArcSegments::of(&result.segment_kinds);
    if let Some(line) = arcs.summary(&p.outline(), result.segment_kinds.len()) {
        writeln!(out, "   {line}")?;
    }
    if let Some(line) = holes_summary(&p.holes()) {
        writeln!(out, "   {line}")?;
    }
    let fx = &result.fixtures;
    if fx.is_empty() {
        return Ok(());
    }
    let pose = format!("pose x, y ({u}), theta");
    writeln!(
        out,
        "  {:>4} {:>10}  {:<10} {:<24} {pose:>28}  {:<22} ext ({u})",
        "rank", "score", "segments", "locators (L1 L2 L3)", "clamp seg/rot/mount",
    )?;
    let n = if top == 0 {
        fx.len()
    } else {
        top.min(fx.len())
    };
    for f in &fx[..n] {
        let locs = f
            .locators
            .iter()
            .map(|l| format!("{},{}", l[0], l[1]))
            .collect::<Vec<_>>()
            .join(" ");
        writeln!(
            out,
            "  {:>4} {:>10.4}  {:<10} {:<24} {:>28}  {:<22} {:.3}{}",
            f.rank,
            f.score,
            arcs.mark_all(&f.segments),
            locs,
            format!("{:.3}, {:.3}, {:.2}°", f.pose.x, f.pose.y, f.pose.theta_deg),
            format!(
                "{}/{}°/{},{}",
                arcs.mark(f.clamp.segment),
                f.clamp.rotation_deg,
                f.clamp.mount[0],
                f.clamp.mount[1]
            ),
            f.clamp.extension,
            if f.borderline { "  (borderline)" } else { "" }
        )?;
        arcs.print_contacts(f, u, out)?;
        if let Some(label) = hole_contact_label(&result.segment_loops, f) {
            writeln!(out, "         {label}")?;
        }
    }
    if n < fx.len() {
        writeln!(out, "  ... {} more kept (--top 0 shows all)", fx.len() - n)?;
    }
    Ok(())
}

/// How many holes the part has (SPEC 9) and the edges of each, in the
/// order that numbers them; `None` for a part without holes, whose text
/// stays as it was.
fn holes_summary(holes: &[Vec<Vertex>]) -> Option<String> {
    if holes.is_empty() {
        return None;
    }
    let edges: Vec<String> = holes.iter().map(|h| h.len().to_string()).collect();
    Some(format!(
        "holes: {} (edges of hole 0, 1, ...: {})",
        holes.len(),
        edges.join(", ")
    ))
}

/// Which segments of a part lie on arcs (SPEC 8.6's `segment_kinds`), for
/// marking them in the table and listing the contacts on them. Empty for
/// a polygon part, whose table stays as it was.
struct ArcSegments {
    arc: Vec<bool>,
}

impl ArcSegments {
    fn of(kinds: &[SegmentKind]) -> ArcSegments {
        let arc: Vec<bool> = kinds.iter().map(|k| *k == SegmentKind::Arc).collect();
        ArcSegments {
            arc: if arc.contains(&true) { arc } else { Vec::new() },
        }
    }

    fn is_arc(&self, segment: usize) -> bool {
        self.arc.get(segment).copied().unwrap_or(false)
    }

    /// A segment index, `*` after it when it lies on an arc.
    fn mark(&self, segment: usize) -> String {
        format!("{segment}{}", if self.is_arc(segment) { "*" } else { "" })
    }

    fn mark_all(&self, segments: &[usize; 3]) -> String {
        segments.map(|s| self.mark(s)).join(",")
    }

    /// Which outline edges are arcs (from the outline as listed) and which
    /// segments (from the results, when the file lists their `kinds`
    /// segment kinds); `None` for a polygon part.
    fn summary(&self, outline: &[Vertex], kinds: usize) -> Option<String> {
        let list = |ix: &[usize]| {
            ix.iter()
                .map(usize::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        };
        let edges: Vec<usize> = edges_of(outline)
            .iter()
            .enumerate()
            .filter_map(|(i, e)| e.is_arc().then_some(i))
            .collect();
        let segments: Vec<usize> = (0..self.arc.len()).filter(|&i| self.arc[i]).collect();
        if edges.is_empty() && segments.is_empty() {
            return None;
        }
        let of_segments = if !segments.is_empty() {
            format!("; segments {} of {kinds} (marked * below)", list(&segments))
        } else if kinds > 0 {
            "; no segment lies on an arc".to_string()
        } else {
            String::new()
        };
        Some(format!(
            "arcs: outline edges {} of {}{of_segments}",
            list(&edges),
            outline.len()
        ))
    }

    /// One line per contact on an arc: which locator (or the clamp), the
    /// segment, the centre of the locator or tip and the inward normal
    /// (canonical plate frame, as the results report them).
    fn print_contacts(
        &self,
        fixture: &FixtureReport,
        unit: &str,
        out: &mut dyn Write,
    ) -> Result<()> {
        let on = [
            fixture.segments[0],
            fixture.segments[1],
            fixture.segments[2],
            fixture.clamp.segment,
        ];
        for ((name, seg), c) in ["L1", "L2", "L3", "clamp"]
            .iter()
            .zip(on)
            .zip(&fixture.contacts)
        {
            if self.is_arc(seg) {
                writeln!(
                    out,
                    "         {name} on arc segment {seg}: centre ({:.3}, {:.3}) {unit}, inward normal ({:.4}, {:.4})",
                    c.point[0], c.point[1], c.normal[0], c.normal[1]
                )?;
            }
        }
        Ok(())
    }
}

/// Prints one JSON line per part: `{"part": ID, ...SPEC Appendix A result}`,
/// converted back from the fixtures message ([`FixturesMsg::export_line`]).
/// A `part` that names no part prints nothing.
pub fn export_json(path: &Path, part: Option<&str>, out: &mut dyn Write) -> Result<()> {
    let contents = for_each_decoded(path, PartMessages::decode::<FixturesMsg>, |_, fixtures| {
        if part.is_some_and(|p| p != fixtures.part) {
            return Ok(());
        }
        let line = fixtures.export_line()?;
        out.write_all(&line)?;
        out.write_all(b"\n")?;
        Ok(())
    })?;
    warn_incomplete(path, contents.complete, &contents.truncated);
    Ok(())
}
