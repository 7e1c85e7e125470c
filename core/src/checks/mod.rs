//! What makes a fixture admissible once its locators and clamp contact are
//! known (SPEC 4): [`form_closure`] of the four contacts, clearance of the
//! clamp in [`admissibility`], and the fit on the [`plate`].

pub(crate) mod admissibility;
pub(crate) mod form_closure;
pub(crate) mod plate;
