//! The part poses that put three locators on three segments (SPEC 3 and
//! 8.4), and the stage's dispatcher: the solver is chosen here, once, from
//! the kinds of the three features ([`TripleContacts::of`], as parry's
//! query dispatcher chooses by shapes). Three lines take the closed form
//! of [`pose`], the polygons' path, bit for bit as before arcs; a triple
//! with a circle the trigonometric elimination of [`contact_pose`]. A new
//! kind of feature is one arm in [`contact_of`] (what a locator centre on
//! it lies on) and, if the solvers cannot take it, a solver of its own.

pub(crate) mod contact_pose;
pub(crate) mod pose;

use crate::geometry::V2;
use crate::segments::Feature;
use contact_pose::{visit_contact_poses_at_angles, Circle, Contact, Gap};
use pose::{solve_poses_at_angles, Line, Pose};

/// What a locator centre touching a segment on `feature` lies on (part
/// frame): the stage's one choice by a single feature.
pub(crate) fn contact_of(feature: &Feature) -> Contact {
    match feature {
        Feature::Line(line) => Contact::Line(Line {
            n: line.n,
            c: line.c,
        }),
        Feature::Arc(arc) => Contact::Circle(Circle {
            centre: arc.center,
            radius: arc.radius,
        }),
    }
}

/// The contacts of a segment combination, by the solver they take.
#[derive(Debug, Clone, Copy)]
pub(crate) enum TripleContacts {
    /// Three lines: SPEC 3's closed form.
    Lines([Line; 3]),
    /// At least one circle: SPEC 8.4's elimination.
    Curved([Contact; 3]),
}

impl TripleContacts {
    /// The contacts of segments on `features`, and so their solver.
    #[inline]
    pub(crate) fn of(features: [&Feature; 3]) -> TripleContacts {
        match features.map(contact_of) {
            [Contact::Line(a), Contact::Line(b), Contact::Line(c)] => {
                TripleContacts::Lines([a, b, c])
            }
            contacts => TripleContacts::Curved(contacts),
        }
    }

    /// Whether a pose solution costs far more than a few distance checks
    /// (a circle's elimination), so that a caller with such checks at hand
    /// should run them first.
    #[inline]
    pub(crate) fn is_costly(&self) -> bool {
        matches!(self, TripleContacts::Curved(_))
    }

    /// Calls `visit` with every pose putting locators `locs` on the
    /// contacts, and whether it is tangential (SPEC 8.4), working out only
    /// the poses at angles the filters let through (others may be reported
    /// too): three lines ask `keeps(theta)` of each root, the elimination
    /// asks `meets(lo, hi)` of stretches of angles. Returns the number of
    /// pose solutions computed.
    #[cfg(test)]
    pub(crate) fn solve_at_angles(
        &self,
        locs: &[V2; 3],
        keeps: impl Fn(f64) -> bool,
        meets: &dyn Fn(f64, f64) -> bool,
        visit: impl FnMut(&Pose, bool),
    ) -> usize {
        self.solve_kept_at_angles(locs, keeps, meets, &|_, _| 0.0, visit)
    }

    /// [`Self::solve_at_angles`] for a caller that keeps a pose only with
    /// its contacts where `gap` says (see [`Gap`]): poses it would reject
    /// may be skipped, the others are the same to the bit.
    #[inline]
    pub(crate) fn solve_kept_at_angles(
        &self,
        locs: &[V2; 3],
        keeps: impl Fn(f64) -> bool,
        meets: &dyn Fn(f64, f64) -> bool,
        gap: &Gap<'_>,
        mut visit: impl FnMut(&Pose, bool),
    ) -> usize {
        match self {
            TripleContacts::Lines(lines) => {
                let (poses, count) = solve_poses_at_angles(lines, locs, keeps);
                for pose in &poses[..count] {
                    visit(pose, false);
                }
                count
            }
            TripleContacts::Curved(contacts) => solve_curved(contacts, locs, meets, gap, visit),
        }
    }
}

/// [`TripleContacts::solve_at_angles`] with a circle, kept out of line so
/// the polygons' loop stays as small as it was.
#[inline(never)]
fn solve_curved(
    contacts: &[Contact; 3],
    locs: &[V2; 3],
    meets: &dyn Fn(f64, f64) -> bool,
    gap: &Gap<'_>,
    mut visit: impl FnMut(&Pose, bool),
) -> usize {
    visit_contact_poses_at_angles(contacts, locs, meets, Some(gap), |found| {
        visit(&found.pose, found.tangential);
    })
}
