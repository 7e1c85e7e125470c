//! The study chart: a hand-written SVG with, per kit, the share of parts
//! held (by count and by quantity) and the best score over the parts held
//! (median, with a whisker to the 90th percentile). No plotting library:
//! the file is small, stable byte for byte, and opens in any browser.

use super::messages::{StudyKitMsg, StudyReport};
use crate::view::svg::escape;

/// Where everything goes: a column of kit names, the coverage bars, the
/// score axis, a row per kit.
struct Layout {
    /// Left edge and width of the coverage bars (0 to 100 %).
    cov_x: f64,
    cov_w: f64,
    /// Left edge and width of the score axis (0 to `smax`).
    sc_x: f64,
    sc_w: f64,
    width: f64,
    height: f64,
    row_h: f64,
    /// Top and bottom of the kit rows.
    top: f64,
    bottom: f64,
    /// Right end of the score axis: a round number above every whisker.
    smax: f64,
}

impl Layout {
    fn new(rep: &StudyReport) -> Layout {
        let name_w = rep
            .kits
            .iter()
            .map(|k| k.name.chars().count())
            .max()
            .unwrap_or(10)
            .clamp(10, 60) as f64
            * 6.6
            + 40.0;
        let (cov_x, cov_w) = (name_w, 300.0);
        let (sc_x, sc_w) = (cov_x + cov_w + 60.0, 300.0);
        let row_h = 30.0;
        let top = 86.0;
        let max_score = rep
            .kits
            .iter()
            .filter_map(|k| k.p90_score.or(k.median_score))
            .fold(0.0_f64, f64::max);
        Layout {
            cov_x,
            cov_w,
            sc_x,
            sc_w,
            width: sc_x + sc_w + 30.0,
            height: top + row_h * rep.kits.len() as f64 + 60.0,
            row_h,
            top,
            bottom: top + row_h * rep.kits.len() as f64,
            smax: if max_score > 0.0 {
                (max_score * 1.15 * 2.0).ceil() / 2.0
            } else {
                1.0
            },
        }
    }

    /// The x of score `value`.
    fn sx(&self, value: f64) -> f64 {
        self.sc_x + self.sc_w * (value / self.smax)
    }

    /// The `<svg>` element, background, title and both legends.
    fn head(&self, rep: &StudyReport, out: &mut String) {
        let Layout {
            width,
            height,
            cov_x,
            sc_x,
            ..
        } = *self;
        out.push_str(&format!(
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width:.0}\" height=\"{height:.0}\" viewBox=\"0 0 {width:.0} {height:.0}\" font-family=\"DejaVu Sans, Helvetica, Arial, sans-serif\" font-size=\"12\">\n"
        ));
        out.push_str(&format!(
            "<rect width=\"{width:.0}\" height=\"{height:.0}\" fill=\"white\"/>\n"
        ));
        out.push_str(&format!(
            "<text x=\"20\" y=\"26\" font-size=\"16\" font-weight=\"bold\">fixplan study: {} ({} parts), {} kits</text>\n",
            escape(&rep.summary.catalog.name),
            rep.summary.catalog.parts,
            rep.kits.len()
        ));
        out.push_str(&format!(
            "<text x=\"{cov_x:.0}\" y=\"56\" font-weight=\"bold\">parts held (%)</text>\n\
             <rect x=\"{:.0}\" y=\"47\" width=\"12\" height=\"8\" fill=\"#2b6cb0\"/><text x=\"{:.0}\" y=\"55\" font-size=\"11\">by count</text>\n\
             <rect x=\"{:.0}\" y=\"47\" width=\"12\" height=\"8\" fill=\"#90cdf4\"/><text x=\"{:.0}\" y=\"55\" font-size=\"11\">by quantity</text>\n",
            cov_x + 110.0, cov_x + 126.0, cov_x + 190.0, cov_x + 206.0
        ));
        out.push_str(&format!(
            "<text x=\"{sc_x:.0}\" y=\"56\" font-weight=\"bold\">best score of the parts held (lower is better)</text>\n\
             <text x=\"{sc_x:.0}\" y=\"72\" font-size=\"11\" fill=\"#444\">dot: median, bar: to the 90th percentile</text>\n"
        ));
    }

    /// Grid lines and tick labels of both axes.
    fn axes(&self, svg: &mut String) {
        let Layout { top, bottom, .. } = *self;
        for i in 0..=4 {
            let x = self.cov_x + self.cov_w * i as f64 / 4.0;
            svg.push_str(&format!(
                "<line x1=\"{x:.1}\" y1=\"{top:.0}\" x2=\"{x:.1}\" y2=\"{bottom:.0}\" stroke=\"#ddd\"/>\n<text x=\"{x:.1}\" y=\"{:.0}\" text-anchor=\"middle\" font-size=\"11\">{}</text>\n",
                bottom + 16.0,
                i * 25
            ));
        }
        let ticks = 5;
        for i in 0..=ticks {
            let v = self.smax * i as f64 / ticks as f64;
            let x = self.sx(v);
            svg.push_str(&format!(
                "<line x1=\"{x:.1}\" y1=\"{top:.0}\" x2=\"{x:.1}\" y2=\"{bottom:.0}\" stroke=\"#ddd\"/>\n<text x=\"{x:.1}\" y=\"{:.0}\" text-anchor=\"middle\" font-size=\"11\">{v:.2}</text>\n",
                bottom + 16.0
            ));
        }
    }

    /// Row `row`: stripe, name, coverage bars and the score dot and whisker.
    fn kit_row(&self, row: usize, kit: &StudyKitMsg, svg: &mut String) {
        let Layout {
            cov_x,
            cov_w,
            row_h,
            ..
        } = *self;
        let y = self.top + row_h * row as f64;
        if row % 2 == 1 {
            svg.push_str(&format!(
                "<rect x=\"10\" y=\"{y:.0}\" width=\"{:.0}\" height=\"{row_h:.0}\" fill=\"#f5f7fa\"/>\n",
                self.width - 20.0
            ));
        }
        svg.push_str(&format!(
            "<text x=\"{:.0}\" y=\"{:.0}\" text-anchor=\"end\">{}</text>\n",
            cov_x - 10.0,
            y + 19.0,
            escape(&kit.name)
        ));
        let wc = cov_w * kit.held_pct / 100.0;
        let wq = cov_w * kit.held_quantity_pct / 100.0;
        svg.push_str(&format!(
            "<rect x=\"{cov_x:.0}\" y=\"{:.1}\" width=\"{wc:.1}\" height=\"10\" fill=\"#2b6cb0\"/>\n\
             <rect x=\"{cov_x:.0}\" y=\"{:.1}\" width=\"{wq:.1}\" height=\"8\" fill=\"#90cdf4\"/>\n\
             <text x=\"{:.1}\" y=\"{:.1}\" font-size=\"10\">{}/{}</text>\n",
            y + 5.0,
            y + 16.0,
            cov_x + wc.max(wq) + 4.0,
            y + 18.0,
            kit.held,
            kit.parts
        ));
        if let Some(m) = kit.median_score {
            let cy = y + row_h / 2.0;
            if let Some(p) = kit.p90_score {
                svg.push_str(&format!(
                    "<line x1=\"{:.1}\" y1=\"{cy:.1}\" x2=\"{:.1}\" y2=\"{cy:.1}\" stroke=\"#c05621\" stroke-width=\"3\"/>\n",
                    self.sx(m),
                    self.sx(p)
                ));
            }
            svg.push_str(&format!(
                "<circle cx=\"{:.1}\" cy=\"{cy:.1}\" r=\"5\" fill=\"#dd6b20\"/>\n<text x=\"{:.1}\" y=\"{:.1}\" font-size=\"10\">{m:.3}</text>\n",
                self.sx(m),
                self.sx(kit.p90_score.unwrap_or(m)) + 8.0,
                cy + 4.0
            ));
        }
    }

    /// The parts no kit holds, and the end of the `<svg>`.
    fn foot(&self, rep: &StudyReport, out: &mut String) {
        let sm = &rep.summary;
        let foot = if sm.unheld.is_empty() {
            "every part is held by at least one kit".to_string()
        } else {
            format!("parts no kit holds: {}", sm.unheld.join(", "))
        };
        out.push_str(&format!(
            "<text x=\"20\" y=\"{:.0}\" font-size=\"11\" fill=\"#444\">{}</text>\n</svg>\n",
            self.bottom + 42.0,
            escape(&foot)
        ));
    }
}

/// The chart of `--chart`: which kits hold most of the catalogue, and how
/// well.
pub fn chart_svg(rep: &StudyReport) -> String {
    let layout = Layout::new(rep);
    let mut s = String::new();
    layout.head(rep, &mut s);
    layout.axes(&mut s);
    for (n, k) in rep.kits.iter().enumerate() {
        layout.kit_row(n, k, &mut s);
    }
    layout.foot(rep, &mut s);
    s
}
