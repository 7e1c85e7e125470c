//! Results back in job order: parts finish in any order (threads, workers,
//! a slow part among fast ones), but a results file holds them in
//! catalogue order, so its bytes do not depend on timing.

use std::collections::BTreeMap;

/// Holds items that arrived early until the ones before them are in.
pub struct Reorder<T> {
    next: usize,
    early: BTreeMap<usize, T>,
}

impl<T> Reorder<T> {
    /// Expects item `first` first.
    pub fn new(first: usize) -> Self {
        Reorder {
            next: first,
            early: BTreeMap::new(),
        }
    }

    /// Takes item `i`; returns the items now ready, in order (none if `i`
    /// is still waiting for an earlier one).
    pub fn push(&mut self, index: usize, item: T) -> Vec<(usize, T)> {
        self.early.insert(index, item);
        let mut ready = Vec::new();
        while let Some(item) = self.early.remove(&self.next) {
            ready.push((self.next, item));
            self.next += 1;
        }
        ready
    }

    /// Items received but not yet handed out (the tests' view).
    #[cfg(test)]
    pub fn waiting(&self) -> usize {
        self.early.len()
    }
}

#[cfg(test)]
mod tests {
    use super::Reorder;

    #[test]
    fn hands_out_in_order_whatever_the_arrival() {
        let mut r = Reorder::new(3);
        assert!(r.push(5, 'c').is_empty());
        assert!(r.push(4, 'b').is_empty());
        assert_eq!(r.waiting(), 2);
        assert_eq!(r.push(3, 'a'), vec![(3, 'a'), (4, 'b'), (5, 'c')]);
        assert_eq!(r.push(6, 'd'), vec![(6, 'd')]);
        assert_eq!(r.waiting(), 0);
    }
}
