//! Conversions between the core's values and the results file's forms of
//! them ([`super::forms`]): every field named once on each side, so a
//! renamed core field is a compile error here, never a silent change of
//! the file. Writing converts core to form; the viewers convert what they
//! draw with core code (kit, outline, fixture) back.

use super::forms::*;
use crate::job::{StepSummary, Timing};
use fixplan_core::outline::Vertex;
use fixplan_core::report::{ClampReport, ContactReport, PlacementReport, PoseReport};
use fixplan_core::segments::SegmentKind;
use fixplan_core::{
    Clamp, Counts, FixtureReport, HoleKind, Kit, MountHole, Params, Pattern, SolveResult, Status,
    Units,
};

/// Both conversions of an enum and its form, variant for variant.
macro_rules! enum_form {
    ($core:ident <=> $form:ident { $($variant:ident),+ }) => {
        impl From<$core> for $form {
            fn from(v: $core) -> $form {
                match v {
                    $($core::$variant => $form::$variant,)+
                }
            }
        }
        impl From<$form> for $core {
            fn from(v: $form) -> $core {
                match v {
                    $($form::$variant => $core::$variant,)+
                }
            }
        }
    };
}

enum_form!(Units <=> UnitsForm { Mm, In });
enum_form!(Pattern <=> PatternForm { Square, Alternating });
enum_form!(HoleKind <=> HoleKindForm { Dowel, Tapped, Any });
enum_form!(Status <=> StatusForm { Ok, NoFixture, Invalid });
enum_form!(SegmentKind <=> SegmentKindForm { Line, Arc });

impl UnitsForm {
    /// How reports and tables write lengths in this unit.
    pub fn label(self) -> &'static str {
        Units::from(self).label()
    }
}

impl From<&Kit> for KitForm {
    fn from(k: &Kit) -> KitForm {
        let c = &k.clamp;
        KitForm {
            spacing: k.spacing,
            cols: k.cols,
            rows: k.rows,
            pattern: k.pattern.into(),
            locator_radius: k.locator_radius,
            clamp: ClampForm {
                mount_holes: c
                    .mount_holes
                    .iter()
                    .map(|h| MountHoleForm(h.offset[0], h.offset[1], h.kind.into()))
                    .collect(),
                axis_offset: c.axis_offset,
                travel: c.travel,
                body: c.body.clone(),
                plunger: c.plunger.clone(),
            },
        }
    }
}

impl From<&KitForm> for Kit {
    fn from(k: &KitForm) -> Kit {
        let c = &k.clamp;
        Kit {
            spacing: k.spacing,
            cols: k.cols,
            rows: k.rows,
            pattern: k.pattern.into(),
            locator_radius: k.locator_radius,
            clamp: Clamp {
                mount_holes: c
                    .mount_holes
                    .iter()
                    .map(|&MountHoleForm(i, j, kind)| MountHole {
                        offset: [i, j],
                        kind: kind.into(),
                    })
                    .collect(),
                axis_offset: c.axis_offset,
                travel: c.travel,
                body: c.body.clone(),
                plunger: c.plunger.clone(),
            },
        }
    }
}

impl From<&Params> for ParamsForm {
    fn from(p: &Params) -> ParamsForm {
        ParamsForm {
            max_clamp_angle_deg: p.max_clamp_angle_deg,
            edge_trim: p.edge_trim,
            min_clearance: p.min_clearance,
            grid_step: p.grid_step,
            top_k: p.top_k,
            full_counts: p.full_counts,
            wrenches: p.wrenches.clone(),
        }
    }
}

impl From<Vertex> for VertexForm {
    fn from(v: Vertex) -> VertexForm {
        VertexForm {
            x: v.x,
            y: v.y,
            bulge: v.bulge,
        }
    }
}

impl From<VertexForm> for Vertex {
    fn from(v: VertexForm) -> Vertex {
        Vertex::new(v.x, v.y, v.bulge)
    }
}

/// The outline a core function draws or measures.
pub fn outline_of(vertices: &[VertexForm]) -> Vec<Vertex> {
    vertices.iter().map(|&v| v.into()).collect()
}

impl From<Counts> for CountsForm {
    fn from(c: Counts) -> CountsForm {
        CountsForm {
            segments: c.segments,
            combinations: c.combinations,
            setups: c.setups,
            candidates: c.candidates,
            admissible: c.admissible(),
            counts_exact: c.exact,
        }
    }
}

impl From<CountsForm> for Counts {
    fn from(c: CountsForm) -> Counts {
        Counts {
            segments: c.segments,
            combinations: c.combinations,
            setups: c.setups,
            candidates: c.candidates,
            admissible: c.admissible.filter(|_| c.counts_exact).unwrap_or(0),
            exact: c.counts_exact,
        }
    }
}

impl From<&FixtureReport> for FixtureForm {
    fn from(f: &FixtureReport) -> FixtureForm {
        let (c, p) = (&f.clamp, &f.placement);
        FixtureForm {
            rank: f.rank,
            score: f.score,
            segments: f.segments,
            locators: f.locators,
            pose: PoseForm {
                x: f.pose.x,
                y: f.pose.y,
                theta_deg: f.pose.theta_deg,
            },
            clamp: ClampPlacedForm {
                segment: c.segment,
                rotation_deg: c.rotation_deg,
                mount: c.mount,
                extension: c.extension,
                contact: c.contact,
            },
            borderline: f.borderline,
            contacts: f
                .contacts
                .iter()
                .map(|c| ContactForm {
                    point: c.point,
                    normal: c.normal,
                })
                .collect(),
            placement: PlacementForm {
                rotation_deg: p.rotation_deg,
                locators: p.locators,
                clamp_holes: p.clamp_holes.clone(),
            },
        }
    }
}

impl From<&FixtureForm> for FixtureReport {
    fn from(f: &FixtureForm) -> FixtureReport {
        let (c, p) = (&f.clamp, &f.placement);
        FixtureReport {
            rank: f.rank,
            score: f.score,
            segments: f.segments,
            locators: f.locators,
            pose: PoseReport {
                x: f.pose.x,
                y: f.pose.y,
                theta_deg: f.pose.theta_deg,
            },
            clamp: ClampReport {
                segment: c.segment,
                rotation_deg: c.rotation_deg,
                mount: c.mount,
                extension: c.extension,
                contact: c.contact,
            },
            borderline: f.borderline,
            contacts: f
                .contacts
                .iter()
                .map(|c| ContactReport {
                    point: c.point,
                    normal: c.normal,
                })
                .collect(),
            placement: PlacementReport {
                rotation_deg: p.rotation_deg,
                locators: p.locators,
                clamp_holes: p.clamp_holes.clone(),
            },
        }
    }
}

impl From<&SolveResult> for ResultForm {
    fn from(r: &SolveResult) -> ResultForm {
        ResultForm {
            status: r.status.into(),
            error: r.error.clone(),
            counts: r.counts.map(CountsForm::from),
            segment_kinds: r.segment_kinds.iter().map(|&k| k.into()).collect(),
            fixtures: r.fixtures.iter().map(FixtureForm::from).collect(),
        }
    }
}

impl From<&ResultForm> for SolveResult {
    fn from(r: &ResultForm) -> SolveResult {
        SolveResult {
            status: r.status.into(),
            error: r.error.clone(),
            counts: r.counts.map(Counts::from),
            segment_kinds: r.segment_kinds.iter().map(|&k| k.into()).collect(),
            fixtures: r.fixtures.iter().map(FixtureReport::from).collect(),
        }
    }
}

impl From<Timing> for TimingForm {
    fn from(t: Timing) -> TimingForm {
        TimingForm {
            prepare_ms: t.prepare_ms,
            enumerate_ms: t.enumerate_ms,
            shards: t.shards,
        }
    }
}

impl From<&StepSummary> for StepForm {
    fn from(s: &StepSummary) -> StepForm {
        StepForm {
            grid_step: s.grid_step,
            counts: s.counts.into(),
            fixtures: s.fixtures,
            best_score: s.best_score,
            best: s.best.as_ref().map(FixtureForm::from),
            added: s.added,
            improved_by: s.improved_by,
            stopped_at: s.stopped_at,
            enumerate_ms: s.enumerate_ms,
        }
    }
}
