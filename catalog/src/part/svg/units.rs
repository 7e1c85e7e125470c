//! The size of an SVG user unit, by SVG's length rules for the root
//! `<svg>`'s `width`, `height` and `viewBox`, and the warning given when
//! the file carries no physical unit, so the user sees the scale that was
//! assumed.

use super::error::SvgError;
use super::lexer::Lexer;
use crate::part::outline::fmt;
use crate::part::raw::ReadOptions;
use crate::units::LengthUnit;

/// Millimetres per CSS pixel: CSS fixes 96 px to the inch.
const MM_PER_PX: f64 = 25.4 / 96.0;
/// Inkscape before 0.92 wrote its unitless sizes at 90 px to the inch.
const MM_PER_OLD_INKSCAPE_PX: f64 = 25.4 / 90.0;
/// Scales closer than this (relative) are one scale.
const SAME_SCALE_REL: f64 = 1e-6;

/// A `width` or `height` of the root element.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Length {
    /// An absolute unit (mm, cm, Q, in, pt, pc): the number and the
    /// millimetres per unit.
    Physical(f64, f64),
    /// A bare number or `px`: CSS pixels, a unit of screens more than of
    /// drawings.
    Px(f64),
    /// Missing, a percentage, `em`/`ex`, or unreadable: no size.
    None,
}

impl Length {
    /// In millimetres, px at `mm_per_px`.
    fn mm(self, mm_per_px: f64) -> Option<f64> {
        match self {
            Length::Physical(v, mm) => Some(v * mm),
            Length::Px(v) => Some(v * mm_per_px),
            Length::None => None,
        }
    }
}

fn length(text: Option<&str>) -> Length {
    let Some(text) = text.map(str::trim) else {
        return Length::None;
    };
    let end = text
        .find(|c: char| c.is_ascii_alphabetic() || c == '%')
        .unwrap_or(text.len());
    let Ok(v) = text[..end].trim().parse::<f64>() else {
        return Length::None;
    };
    if !(v.is_finite() && v > 0.0) {
        return Length::None;
    }
    let mm = match text[end..].trim().to_ascii_lowercase().as_str() {
        "" | "px" => return Length::Px(v),
        "mm" => LengthUnit::Mm.mm(),
        "cm" => LengthUnit::Cm.mm(),
        "q" => 0.25,
        "in" => LengthUnit::In.mm(),
        "pt" => LengthUnit::In.mm() / 72.0,
        "pc" => LengthUnit::In.mm() / 6.0,
        _ => return Length::None,
    };
    Length::Physical(v, mm)
}

/// The viewBox's width and height, if it is four numbers with a positive
/// size; `Err` if it is there but not that.
fn view_box(root: roxmltree::Node) -> Result<Option<[f64; 2]>, ()> {
    let Some(s) = root.attribute("viewBox") else {
        return Ok(None);
    };
    let mut lx = Lexer::new(s);
    let v: Vec<f64> = std::iter::from_fn(|| lx.number()).collect();
    match v.as_slice() {
        [_, _, w, h] if w.is_finite() && h.is_finite() && *w > 0.0 && *h > 0.0 => {
            Ok(Some([*w, *h]))
        }
        _ => Err(()),
    }
}

/// Millimetres per px of the file: CSS's, or old Inkscape's (its
/// `inkscape:version` before 0.92).
fn mm_per_px(root: roxmltree::Node) -> (f64, &'static str) {
    let old = root
        .attributes()
        .find(|a| a.name() == "version" && a.namespace().is_some_and(|n| n.contains("inkscape")))
        .and_then(|a| {
            let mut it = a.value().split(|c: char| !c.is_ascii_digit());
            let major: u32 = it.next()?.parse().ok()?;
            let minor: u32 = it.next()?.parse().ok()?;
            Some(major == 0 && minor < 92)
        })
        .unwrap_or(false);
    if old {
        (
            MM_PER_OLD_INKSCAPE_PX,
            "px of Inkscape before 0.92, 90 per inch",
        )
    } else {
        (MM_PER_PX, "CSS px, 96 per inch")
    }
}

/// Catalogue units per user unit and, when the file carries no physical
/// unit, the warning that says which scale was taken. The arithmetic of
/// files with a physical width is what it always was (`width / viewBox
/// width * unit factor`), so their parts do not move by a rounding.
pub(super) fn user_unit(
    root: roxmltree::Node,
    opts: &ReadOptions,
) -> Result<(f64, Option<String>), SvgError> {
    let (w, h) = (
        length(root.attribute("width")),
        length(root.attribute("height")),
    );
    // The width decides, as it always has here; the height only when the
    // width gives no size.
    let (size, along) = match (w, h) {
        (Length::None, h) => (h, 1),
        (w, _) => (w, 0),
    };
    let vb = match (size, view_box(root)) {
        (Length::None, _) => None,
        (_, Ok(vb)) => vb,
        (_, Err(())) => return Err(SvgError::BadViewBox),
    };
    let (px_mm, px_name) = mm_per_px(root);
    if let (Some(vb), Some(wm), Some(hm)) = (vb, w.mm(px_mm), h.mm(px_mm)) {
        let (sx, sy) = (wm / vb[0], hm / vb[1]);
        let stretched = root
            .attribute("preserveAspectRatio")
            .is_some_and(|p| p.trim().starts_with("none"));
        if stretched && (sx - sy).abs() > SAME_SCALE_REL * sx.max(sy) {
            return Err(SvgError::Stretched { sx, sy });
        }
    }
    let to_cat = 1.0 / opts.units.mm_per_unit();
    let mm_of = |k: f64| fmt(k * opts.units.mm_per_unit());
    let chosen = chosen_unit(opts);
    Ok(match size {
        Length::Physical(v, mm) => match vb {
            Some(vb) => (v / vb[along] * (mm / opts.units.mm_per_unit()), None),
            // A physical size without a viewBox: user units are CSS px.
            None => (LengthUnit::In.factor_to(opts.units) / 96.0, None),
        },
        // No physical unit: px by SVG's rules (no size at all leaves user
        // units at one px, as browsers and Inkscape take them), unless the
        // manifest chose a unit for the file.
        Length::Px(_) | Length::None => {
            let per_px = match (size, vb) {
                (Length::Px(px), Some(vb)) => px / vb[along],
                _ => 1.0,
            };
            let (k, what) = match chosen {
                Some(u) => (
                    per_px * u.factor_to(opts.units),
                    format!(
                        "the part's units = \"{}\" taking the place of px",
                        u.label()
                    ),
                ),
                None => (per_px * px_mm * to_cat, px_name.to_string()),
            };
            let note = format!(
                "no physical unit in the file: 1 user unit read as {} mm ({what}); if the drawing is meant in mm or in, give the root <svg> a width in that unit (width=\"100mm\" with viewBox=\"0 0 100 ...\"), or set units = \"mm\" or \"in\" on its manifest entry",
                mm_of(k)
            );
            (k, Some(note))
        }
    })
}

/// The unit a manifest entry's `units` chose for files that do not say.
/// [`ReadOptions`] does not record whether `fallback` was given or is the
/// catalogue's default, so a choice is seen only when it differs from the
/// catalogue's units.
fn chosen_unit(opts: &ReadOptions) -> Option<LengthUnit> {
    (opts.fallback != LengthUnit::from(opts.units)).then_some(opts.fallback)
}
