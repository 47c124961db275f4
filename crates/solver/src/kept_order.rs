//! An elimination order kept over global keys, to number later systems whose unknowns mostly
//! reappear.
//!
//! A planner that factors a new system at every step, over unknowns that are a moving subset of
//! one fixed set (the vertices of a background lattice under a window that follows the robot),
//! can keep the fill-reducing order computed for an earlier system — by the unknowns' global
//! keys rather than their positions in that system — and number the next systems in it:
//! the factorisation then needs no ordering of its own ([`crate::Ordering::Natural`]).
//! [`KeptOrder::order_for`] applies the kept order while it still ranks at least
//! [`KeptOrder::MIN_RANKED_PERCENT`] % of the new unknowns; an unknown new to it goes just
//! before its first-ranked neighbour (so it is eliminated with the part of the graph it joins),
//! one with no ranked neighbour last. Otherwise it answers `None` and the caller computes a
//! fresh order (e.g. [`crate::Ordering::Amd`], read back with
//! [`crate::AccurateLdlt::permutation`]) and keeps that one instead.
//!
//! ```
//! use harmonic_solver::KeptOrder;
//! // A path 0 – 1 – 2 – 3 – 4 by key, once eliminated from the ends inwards.
//! let kept = KeptOrder::new([0u32, 4, 1, 3, 2]);
//! // A new system over keys 1, 2, 3 and 5 (new, next to 4): 5 goes just before 4's rank,
//! // which no current unknown holds, so it comes first.
//! let keys = [1u32, 2, 3, 5];
//! let neighbours = |k: usize| {
//!     let key = keys[k];
//!     [key.checked_sub(1), Some(key + 1)].into_iter().flatten()
//! };
//! let perm = kept.order_for(&keys, neighbours).expect("3 of 4 ranked");
//! assert_eq!(perm, [3, 0, 2, 1]);
//! ```

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hash, Hasher};

/// An elimination order over global keys `K` (first eliminated first); see the module
/// documentation.
#[derive(Clone, Debug)]
pub struct KeptOrder<K> {
    rank: HashMap<K, u32, BuildHasherDefault<MixHasher>>,
    len: usize,
}

impl<K: Copy + Eq + Hash> KeptOrder<K> {
    /// The smallest share, in percent, of a new system's unknowns that the kept order must
    /// rank for [`order_for`](Self::order_for) to use it.
    pub const MIN_RANKED_PERCENT: usize = 70;

    /// Keeps `order` (the keys of an earlier system's unknowns, first eliminated first; a key
    /// listed twice keeps its last rank).
    pub fn new(order: impl IntoIterator<Item = K>) -> Self {
        let mut rank: HashMap<K, u32, BuildHasherDefault<MixHasher>> = HashMap::default();
        let mut len = 0;
        for (r, key) in order.into_iter().enumerate() {
            rank.insert(key, r as u32);
            len = r + 1;
        }
        KeptOrder { rank, len }
    }

    /// Number of ranks (the length of the order it was made from).
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether it ranks nothing.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The rank of `key`, if it has one.
    pub fn rank(&self, key: &K) -> Option<u32> {
        self.rank.get(key).copied()
    }

    /// The numbering `perm[new] = k` of the unknowns with keys `keys` in the kept order, if it
    /// ranks at least [`MIN_RANKED_PERCENT`](Self::MIN_RANKED_PERCENT) % of them (and at
    /// least one); `neighbours(k)` gives the keys of the neighbours of unknown `k` in the
    /// matrix graph (any key, not only those of `keys`). An unranked unknown goes just before
    /// the lowest-ranked of its neighbours, one without a ranked neighbour after everything
    /// else; ties keep the order of `keys`.
    pub fn order_for<I>(
        &self,
        keys: &[K],
        mut neighbours: impl FnMut(usize) -> I,
    ) -> Option<Vec<usize>>
    where
        I: IntoIterator<Item = K>,
    {
        // Sort key 2r + 1 for rank r, 2r just before it, `last` after every rank.
        let last = 2 * self.len;
        let mut ranked = 0usize;
        let sort_keys: Vec<usize> = (0..keys.len())
            .map(|k| match self.rank(&keys[k]) {
                Some(r) => {
                    ranked += 1;
                    2 * r as usize + 1
                }
                None => neighbours(k)
                    .into_iter()
                    .filter_map(|u| self.rank(&u))
                    .min()
                    .map_or(last, |r| 2 * r as usize),
            })
            .collect();
        if ranked == 0 || 100 * ranked < Self::MIN_RANKED_PERCENT * keys.len() {
            return None;
        }
        // A counting sort: stable, so ties keep the order of `keys`.
        let mut start = vec![0usize; last + 2];
        for &s in &sort_keys {
            start[s + 1] += 1;
        }
        for b in 0..=last {
            start[b + 1] += start[b];
        }
        let mut perm = vec![0usize; keys.len()];
        for (k, &s) in sort_keys.iter().enumerate() {
            perm[start[s]] = k;
            start[s] += 1;
        }
        Some(perm)
    }
}

/// A fast multiplicative hasher for the small integer keys of a kept order (lattice indices):
/// the default SipHash costs more than the rest of the lookup.
#[derive(Clone, Copy, Debug, Default)]
struct MixHasher(u64);

impl Hasher for MixHasher {
    fn finish(&self) -> u64 {
        self.0
    }

    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u64(u64::from(b));
        }
    }

    fn write_u64(&mut self, i: u64) {
        const K: u64 = 0xf135_7aea_2e62_a9c5;
        self.0 = (self.0.rotate_left(26) ^ i).wrapping_mul(K);
    }

    fn write_u32(&mut self, i: u32) {
        self.write_u64(u64::from(i));
    }

    fn write_i64(&mut self, i: i64) {
        self.write_u64(i as u64);
    }

    fn write_usize(&mut self, i: usize) {
        self.write_u64(i as u64);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Keys of a 5 × 5 grid's vertices and their axis neighbours.
    fn neighbours(key: (i64, i64)) -> impl Iterator<Item = (i64, i64)> {
        let (i, j) = key;
        [(i, j - 1), (i - 1, j), (i + 1, j), (i, j + 1)].into_iter()
    }

    #[test]
    fn ranked_keys_follow_the_kept_order_and_new_ones_precede_their_neighbour() {
        // Kept: the 3 × 3 block at the origin, column by column.
        let kept = KeptOrder::new((0..3).flat_map(|i| (0..3).map(move |j| (i, j))));
        assert_eq!(kept.len(), 9);
        assert_eq!(kept.rank(&(1, 0)), Some(3));
        // The block shifted one to the right: 6 ranked of 9, under 70 %: a fresh order.
        let shifted: Vec<(i64, i64)> = (1..4).flat_map(|i| (0..3).map(move |j| (i, j))).collect();
        assert_eq!(kept.order_for(&shifted, |k| neighbours(shifted[k])), None);
        // The block plus (3, 1), (3, 0) and (5, 5): 9 ranked of 12 (75 %).
        let keys: Vec<(i64, i64)> = [(5, 5), (3, 1), (3, 0)]
            .into_iter()
            .chain((0..3).flat_map(|i| (0..3).map(move |j| (i, j))))
            .collect();
        let perm = kept
            .order_for(&keys, |k| neighbours(keys[k]))
            .expect("75 % ranked");
        let ordered: Vec<(i64, i64)> = perm.iter().map(|&k| keys[k]).collect();
        // (3, 1) just before its ranked neighbour (2, 1), (3, 0) before (2, 0) (both rank
        // 6 and 7); (5, 5) has no ranked neighbour: last.
        assert_eq!(
            ordered,
            [
                (0, 0),
                (0, 1),
                (0, 2),
                (1, 0),
                (1, 1),
                (1, 2),
                (3, 0),
                (2, 0),
                (3, 1),
                (2, 1),
                (2, 2),
                (5, 5)
            ]
        );
        // Two new keys before the same rank keep the order of `keys`.
        let keys = [(3, 2), (2, 3), (2, 2), (0, 0), (1, 1), (2, 1), (1, 2)];
        let perm = kept
            .order_for(&keys, |k| neighbours(keys[k]))
            .expect("5 of 7");
        assert_eq!(perm, [3, 4, 6, 5, 0, 1, 2]);
    }

    #[test]
    fn an_empty_order_or_system_gives_no_numbering() {
        let empty = KeptOrder::<u32>::new([]);
        assert!(empty.is_empty());
        assert_eq!(empty.order_for(&[1, 2], |_| [0u32]), None);
        let kept = KeptOrder::new([1u32, 2]);
        assert_eq!(kept.order_for(&[], |_| [0u32]), None);
        assert_eq!(kept.order_for(&[2, 1], |_| [0u32]), Some(vec![1, 0]));
    }
}
