//! A seeded xorshift generator for unit tests that sample many random
//! cases: fixed seeds keep every run on the same cases, so a failure
//! reproduces.

/// xorshift64 state.
pub(crate) struct Xorshift(u64);

impl Xorshift {
    /// A generator from a nonzero seed.
    pub(crate) fn new(seed: u64) -> Xorshift {
        Xorshift(seed)
    }

    /// The next value, uniform in `[-1, 1)`.
    pub(crate) fn signed_unit(&mut self) -> f64 {
        let s = &mut self.0;
        *s ^= *s << 13;
        *s ^= *s >> 7;
        *s ^= *s << 17;
        (*s >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
}
