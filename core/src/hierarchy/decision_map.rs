//! The oracle's cached decision per (receiver, source) element pair of the Monte Carlo
//! hierarchy: a hash table with open addressing (linear probing), because a fine mesh
//! meets millions of pairs and every ray looks up one pair per level it descends.
//!
//! Only `get` and `insert` exist, so the order of the entries never shows: the solves are
//! the same, bit for bit, as with an ordered map.

use alloc::vec;
use alloc::vec::Vec;

use crate::hierarchy::oracle::Decision;
use crate::lines::mix64;

/// No entry (the key of a pair of two `u32::MAX` elements, which no hierarchy has).
const EMPTY: u64 = u64::MAX;
/// Slots of an empty map's first allocation.
const FIRST_CAPACITY: usize = 1024;
/// Elements are numbered below `2³¹`: the key's top bit of the receiver half is free
/// and holds, with the source half's, the decision (one memory access per probe).
const INDEX_BITS: u32 = 31;
/// The key without the decision bits.
const KEY_MASK: u64 = !((1 << 63) | (1 << 31));

/// Decision per element pair, keyed by `(receiver << 32) | source`.
#[derive(Clone, Debug, Default)]
pub(crate) struct DecisionMap {
    /// Per slot the key with the decision in its bits 63 and 31, or `EMPTY`.
    slots: Vec<u64>,
    len: usize,
}

fn encode(d: Decision) -> u64 {
    match d {
        Decision::Link => 0,
        Decision::RefineReceiver => 1 << 63,
        Decision::RefineSource => 1 << 31,
    }
}

fn decode(slot: u64) -> Decision {
    if slot & (1 << 63) != 0 {
        Decision::RefineReceiver
    } else if slot & (1 << 31) != 0 {
        Decision::RefineSource
    } else {
        Decision::Link
    }
}

impl DecisionMap {
    /// The key of a pair, `None` for indices of `2³¹` or more (never cached: no hierarchy
    /// has that many elements, `McOptions::max_elements`).
    fn key(r: u32, s: u32) -> Option<u64> {
        (r >> INDEX_BITS == 0 && s >> INDEX_BITS == 0).then(|| (u64::from(r) << 32) | u64::from(s))
    }

    /// The slot of `key`, or of the empty slot where it would go. The table is at most
    /// half full, so the probe ends within its capacity.
    fn slot(&self, key: u64) -> usize {
        let mask = self.slots.len() - 1;
        let mut i = (mix64(key) as usize) & mask;
        for _ in 0..self.slots.len() {
            let k = self.slots[i];
            if k == EMPTY || k & KEY_MASK == key {
                return i;
            }
            i = (i + 1) & mask;
        }
        i
    }

    /// The decision cached for receiver `r` and source `s`.
    pub(crate) fn get(&self, r: u32, s: u32) -> Option<Decision> {
        if self.len == 0 {
            return None;
        }
        let key = Self::key(r, s)?;
        let k = self.slots[self.slot(key)];
        (k != EMPTY).then(|| decode(k))
    }

    /// Caches decision `d` for receiver `r` and source `s` (replacing one cached before).
    pub(crate) fn insert(&mut self, r: u32, s: u32, d: Decision) {
        let Some(key) = Self::key(r, s) else {
            return;
        };
        if 2 * (self.len + 1) > self.slots.len() {
            self.grow();
        }
        let i = self.slot(key);
        if self.slots[i] == EMPTY {
            self.len += 1;
        }
        self.slots[i] = key | encode(d);
    }

    /// Entries.
    #[cfg(test)]
    fn len(&self) -> usize {
        self.len
    }

    fn grow(&mut self) {
        let capacity = (2 * self.slots.len()).max(FIRST_CAPACITY);
        let old = core::mem::replace(&mut self.slots, vec![EMPTY; capacity]);
        for k in old {
            if k != EMPTY {
                let i = self.slot(k & KEY_MASK);
                self.slots[i] = k;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use alloc::collections::BTreeMap;

    /// The same answers as an ordered map over many inserts, repeats and misses (the
    /// table grows several times).
    #[test]
    fn answers_as_an_ordered_map() {
        let mut map = DecisionMap::default();
        let mut reference = BTreeMap::new();
        let decisions = [
            Decision::Link,
            Decision::RefineReceiver,
            Decision::RefineSource,
        ];
        let mut z = 7u64;
        for k in 0..20_000u64 {
            z = mix64(z);
            let (r, s) = ((z >> 40) as u32 % 300, (z as u32) % 300);
            let d = decisions[(k % 3) as usize];
            assert_eq!(map.get(r, s), reference.get(&(r, s)).copied());
            map.insert(r, s, d);
            reference.insert((r, s), d);
        }
        assert_eq!(map.len(), reference.len());
        for r in 0..300 {
            for s in 0..300 {
                assert_eq!(map.get(r, s), reference.get(&(r, s)).copied());
            }
        }
        assert_eq!(DecisionMap::default().get(0, 0), None);
        // The largest indices keep their decisions apart from the key bits
        let top = (1u32 << INDEX_BITS) - 1;
        for d in decisions {
            map.insert(top, top, d);
            assert_eq!(map.get(top, top), Some(d));
            map.insert(top, 0, d);
            assert_eq!(map.get(top, 0), Some(d));
        }
        map.insert(top + 1, 0, Decision::RefineSource);
        assert_eq!(map.get(top + 1, 0), None);
    }
}
