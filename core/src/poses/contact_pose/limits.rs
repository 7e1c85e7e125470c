//! The tolerances of the arc pose solver, shared by the general
//! elimination (`contact_pose`) and the closed forms beside it
//! (`two_lines`), so that both count the same things as zero, parallel or
//! a near miss.

/// `F` within this fraction of `scale_f` of zero is a continuum (exact
/// continua come out near 2e-16, random setups above 1e-3; see the unit
/// tests).
pub(super) const CONTINUUM_REL: f64 = 1e-10;
/// Bound on the rounding error of the sampled polynomials' coefficients,
/// relative to their scales (at most 2e-16 is seen at known solutions; see
/// the unit tests). Too large a bound would merge distinct close roots
/// into one zero-within-rounding stretch.
pub(super) const ROUNDING_REL: f64 = 1e-14;
/// Near misses up to this residual (lattice units, with margin over `eps`)
/// are passed on as candidates so that a tangency is found whichever way
/// rounding tips it; Newton and the `eps` test then decide.
pub(super) const NEAR_MISS: f64 = 1e-8;
/// `|D| <= DEGENERATE_REL * |b1||b2|` everywhere: the rows are parallel at
/// every angle (two parallel lines), `F = |N|^2` has only double roots and
/// the angles come from `N = 0` instead.
pub(super) const DEGENERATE_REL: f64 = 1e-12;
/// Below this, the rows are treated as nearly parallel and the two points
/// where the line of solutions of one row meets the circle are also tried.
pub(super) const NEAR_PARALLEL_REL: f64 = 1e-4;
