//! The segment-combination space that the coordinator shards: triples
//! `(a, b, c)` with `a <= b <= c`, not all equal, in lexicographic order.
//! There are `C(n,3) + 2 C(n,2)` of them.

/// Number of combinations for `n` segments.
pub fn combination_count(n: usize) -> u64 {
    let n = n as u64;
    if n < 2 {
        return 0;
    }
    n * (n - 1) * (n - 2) / 6 + n * (n - 1)
}

/// Combinations whose first index is `a` (pairs `a <= b <= c` minus `(a,a,a)`).
fn count_from(n: usize, a: usize) -> u64 {
    let m = (n - a) as u64;
    m * (m + 1) / 2 - 1
}

/// Combinations `(a, b, c)` with fixed `a` and `b` (`c` from `b`, minus the
/// all-equal one when `a == b`).
fn count_from_b(n: usize, a: usize, b: usize) -> u64 {
    let m = (n - b) as u64;
    if a == b {
        m - 1
    } else {
        m
    }
}

/// The combination at `index` (lexicographic), or `None` past the end.
pub fn combination_at(n: usize, mut index: u64) -> Option<[usize; 3]> {
    for a in 0..n {
        let k = count_from(n, a);
        if index >= k {
            index -= k;
            continue;
        }
        for b in a..n {
            let k = count_from_b(n, a, b);
            if index >= k {
                index -= k;
                continue;
            }
            let c0 = if a == b { b + 1 } else { b };
            return Some([a, b, c0 + index as usize]);
        }
    }
    None
}

/// The next combination in lexicographic order.
pub fn next_combination(n: usize, [a, b, c]: [usize; 3]) -> Option<[usize; 3]> {
    if c + 1 < n {
        return Some([a, b, c + 1]);
    }
    if b + 1 < n {
        return Some([a, b + 1, b + 1]);
    }
    if a + 2 < n {
        return Some([a + 1, a + 1, a + 2]);
    }
    None
}

/// Iterator over the combinations with indices in `range`.
pub fn combinations_in(
    n: usize,
    range: std::ops::Range<u64>,
) -> impl Iterator<Item = (u64, [usize; 3])> {
    let end = range.end.min(combination_count(n));
    let mut cur = if range.start < end {
        combination_at(n, range.start)
    } else {
        None
    };
    let mut idx = range.start;
    std::iter::from_fn(move || {
        if idx >= end {
            return None;
        }
        let c = cur?;
        let out = (idx, c);
        idx += 1;
        cur = next_combination(n, c);
        Some(out)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn all(n: usize) -> Vec<[usize; 3]> {
        let mut v = Vec::new();
        for a in 0..n {
            for b in a..n {
                for c in b..n {
                    if !(a == b && b == c) {
                        v.push([a, b, c]);
                    }
                }
            }
        }
        v
    }

    #[test]
    fn count_indexing_and_iteration_agree_with_the_definition() {
        for n in 0..9 {
            let v = all(n);
            assert_eq!(combination_count(n), v.len() as u64, "n = {n}");
            for (i, c) in v.iter().enumerate() {
                assert_eq!(combination_at(n, i as u64), Some(*c));
            }
            assert_eq!(combination_at(n, v.len() as u64), None);
            let it: Vec<_> = combinations_in(n, 0..u64::MAX).map(|x| x.1).collect();
            assert_eq!(it, v);
            if v.len() > 3 {
                let mid: Vec<_> = combinations_in(n, 2..v.len() as u64 - 1)
                    .map(|x| x.1)
                    .collect();
                assert_eq!(mid, v[2..v.len() - 1]);
            }
        }
        // C(n,3) + 2 C(n,2)
        assert_eq!(combination_count(57), 29260 + 2 * 1596);
    }
}
