//! `fixplan render`: the SVG of every fixture kept (or of the part alone,
//! without a fixture) written to a folder, with an `index.html` gallery of
//! all parts.

use super::picture::{fixture_svg, part_svg};
use super::svg::escape;
use crate::output::messages::RunMsg;
use crate::output::reader::{for_each_record, PartRecord};
use anyhow::{Context, Result};
use fixplan_core::Counts;
use std::fmt::Write as _;
use std::path::Path;

/// A file-name-safe stem for part `index` with id `id`.
pub fn stem(index: usize, id: &str) -> String {
    let clean: String = id
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || "-_.".contains(c) {
                c
            } else {
                '_'
            }
        })
        .collect();
    format!("{index:04}-{clean}")
}

/// Renders the file into `out_dir`; returns how many SVGs were written.
pub fn render(path: &Path, out_dir: &Path, part: Option<&str>, top: usize) -> Result<usize> {
    std::fs::create_dir_all(out_dir)
        .with_context(|| format!("{}: cannot create", out_dir.display()))?;
    let mut html = String::new();
    let mut count = 0;
    let contents = for_each_record(path, part, |run, rec| {
        count += render_part(run, rec, out_dir, top, &mut html)?;
        Ok(())
    })?;
    let run = &contents.run;
    let page = format!(
        "<!doctype html>\n<html><head><meta charset=\"utf-8\"><title>fixplan: {name}</title>\n<style>\
         body{{font-family:sans-serif;margin:2em;color:#222}} .part{{margin-bottom:2.5em}} \
         .fx img{{width:380px;border:1px solid #ccc;margin:4px}} .invalid{{color:#b0271f}} \
         .no_fixture{{color:#8a6d00}} .ok{{color:#138a36}} code{{background:#f3f3f3}}</style></head><body>\n\
         <h1>fixplan results: {name}</h1>\n<p>{parts} parts, kit <code>{kit}</code>, catalogue digest \
         <code>{digest}</code>, fixplan {ver}.{incomplete}</p>\n{html}</body></html>\n",
        name = escape(&run.catalog.name),
        parts = contents.parts.len(),
        kit = escape(&run.kit_name),
        digest = escape(&run.catalog.digest),
        ver = escape(&run.version),
        incomplete = if contents.complete { "" } else { " <b>Incomplete file (interrupted run).</b>" },
    );
    let index = out_dir.join("index.html");
    std::fs::write(&index, page).with_context(|| format!("{}: cannot write", index.display()))?;
    Ok(count)
}

fn render_part(
    run: &RunMsg,
    rec: &PartRecord,
    out_dir: &Path,
    top: usize,
    html: &mut String,
) -> Result<usize> {
    let p = &rec.part;
    let st = stem(p.index, &p.id);
    let status = p.status.text();
    let _ = writeln!(
        html,
        "<div class=\"part\"><h2>{} <span class=\"{status}\">{status}</span></h2>",
        escape(&p.id)
    );
    if let Some(c) = p.counts.as_ref().map(Counts::from) {
        let _ = writeln!(
            html,
            "<p>{} segments, {} setups, {} candidates, <b>{}</b> admissible fixtures; {} kept.</p>",
            c.segments,
            c.setups,
            c.candidates,
            super::show::admissible_word(&c),
            p.fixtures
        );
    }
    if let Some(e) = &p.error {
        let _ = writeln!(html, "<p class=\"invalid\">{}</p>", escape(e));
    }
    let _ = write!(html, "<div class=\"fx\">");
    let fx = &rec.fixtures.result().fixtures;
    let mut n = 0;
    if fx.is_empty() {
        let name = format!("{st}.svg");
        let f = out_dir.join(&name);
        std::fs::write(&f, part_svg(rec))
            .with_context(|| format!("{}: cannot write", f.display()))?;
        let _ = write!(
            html,
            "<a href=\"{name}\"><img src=\"{name}\" alt=\"{}\"></a>",
            escape(&p.id)
        );
        n += 1;
    }
    let take = if top == 0 {
        fx.len()
    } else {
        top.min(fx.len())
    };
    for f in &fx[..take] {
        let name = format!("{st}-rank{:02}.svg", f.rank);
        let path = out_dir.join(&name);
        std::fs::write(&path, fixture_svg(run, rec, f))
            .with_context(|| format!("{}: cannot write", path.display()))?;
        let _ = write!(
            html,
            "<a href=\"{name}\"><img src=\"{name}\" alt=\"{} rank {}\" title=\"rank {} score {:.4}\"></a>",
            escape(&p.id),
            f.rank,
            f.rank,
            f.score
        );
        n += 1;
    }
    html.push_str("</div></div>\n");
    Ok(n)
}
