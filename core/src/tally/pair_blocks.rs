//! The segments of a bundle of parallel lines, gathered per patch pair before they reach a
//! [`LineTally`](super::tally::LineTally).
//!
//! A global-line segment from patch `i` to patch `j` adds one to the pair's count and
//! its continuous term (4.13) `log₂ f`, `f = L_T cos θ_i cos θ_j / 2r`, to the pair's
//! information. [`PairBlocks`] keeps, per pair met in a bundle of parallel lines, the
//! number of segments and `Σ log₂ f` as a running product ([`Log2Product`]: one
//! multiplication per segment, one logarithm per pair); the tracer then adds each pair
//! once per bundle with
//! [`LineTally::add_pair_block`](super::tally::LineTally::add_pair_block), which
//! quantises its information once instead of once per segment. The lines of a bundle
//! share their direction, so a pair's segments are many (they are met by neighbouring
//! lines), and the per-pair work is shared by all of them.

use alloc::vec;
use alloc::vec::Vec;

use crate::math::Log2Product;

/// A free slot of the table.
const EMPTY: u64 = u64::MAX;

/// Initial number of slots (grown by doubling, never shrunk: no allocation once a tracer
/// has seen its largest bundle).
const INITIAL_SLOTS: usize = 256;

/// One patch pair's segments in the current bundle.
#[derive(Clone, Copy, Debug)]
struct Block {
    /// `(i << 32) | j`, or [`EMPTY`].
    key: u64,
    /// Segments from `i` to `j`.
    count: u32,
    /// `Π f_k` of their terms' arguments.
    terms: Log2Product,
}

// Two blocks a cache line: a drain's table of ~750 pairs (2048 slots on the 64-squares
// room) is 64 KiB, not the 80 KiB of a 40-byte block.
const _: () = assert!(core::mem::size_of::<Block>() == 32);

const FREE: Block = Block {
    key: EMPTY,
    count: 0,
    terms: Log2Product::new(),
};

/// Scratch space gathering one bundle's segments per ordered patch pair `(i, j)`: an
/// open-addressing table (linear probing, at most half full) and the list of slots
/// touched, in the order first met, so that draining visits only those and in an order
/// that depends on the lines alone (deterministic results).
#[derive(Clone, Debug)]
pub(crate) struct PairBlocks {
    slots: Vec<Block>,
    touched: Vec<u32>,
}

impl Default for PairBlocks {
    fn default() -> Self {
        Self {
            slots: vec![FREE; INITIAL_SLOTS],
            touched: Vec::new(),
        }
    }
}

impl PairBlocks {
    /// A segment from patch `i` to patch `j` whose term is `log₂ f`.
    #[inline]
    pub(crate) fn add(&mut self, i: u32, j: u32, f: f64) {
        let key = (u64::from(i) << 32) | u64::from(j);
        let mask = self.slots.len() - 1;
        // Fibonacci hashing: the top bits of key · 2⁶⁴/φ
        let mut s = (key.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 40) as usize & mask;
        loop {
            let Some(block) = self.slots.get_mut(s) else {
                return; // unreachable: s ≤ mask
            };
            if block.key == key {
                block.count += 1;
                block.terms.push(f);
                return;
            }
            if block.key == EMPTY {
                // A free block is an empty one (drained blocks are reset): it is filled in
                // place, field by field (a whole new block, built apart and copied in,
                // stalled on forwarding its parts' stores)
                block.key = key;
                block.count = 1;
                block.terms.push(f);
                self.touched.push(s as u32);
                if 2 * self.touched.len() > self.slots.len() {
                    self.grow();
                }
                return;
            }
            s = (s + 1) & mask;
        }
    }

    /// Doubles the table, keeping the touched slots in their order.
    #[cold]
    fn grow(&mut self) {
        let doubled = vec![FREE; 2 * self.slots.len()];
        let old = core::mem::replace(&mut self.slots, doubled);
        let mask = self.slots.len() - 1;
        for t in &mut self.touched {
            let block = old[*t as usize];
            let mut s = (block.key.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 40) as usize & mask;
            while self.slots[s].key != EMPTY {
                s = (s + 1) & mask;
            }
            self.slots[s] = block;
            *t = s as u32;
        }
    }

    /// Calls `visit(i, j, count, Σ log₂ f)` for every pair met since the last drain, in
    /// the order first met (`Σ log₂ f` is `None` if some `f` was not a positive finite
    /// number), and empties the table.
    pub(crate) fn drain(&mut self, mut visit: impl FnMut(usize, usize, u32, Option<f64>)) {
        for &t in &self.touched {
            if let Some(block) = self.slots.get_mut(t as usize) {
                let (i, j) = (
                    (block.key >> 32) as usize,
                    (block.key & 0xffff_ffff) as usize,
                );
                visit(i, j, block.count, block.terms.log2());
                *block = FREE;
            }
        }
        self.touched.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use alloc::collections::BTreeMap;

    #[test]
    fn gathers_like_a_map_and_empties() {
        let mut blocks = PairBlocks::default();
        let mut want: BTreeMap<(usize, usize), (u32, f64)> = BTreeMap::new();
        let mut rng = crate::lines::chunk_rng(4, 0);
        // Enough pairs to grow the table twice.
        for _ in 0..20_000 {
            let i = (crate::lines::canonical(&mut rng) * 700.0) as u32;
            let j = (crate::lines::canonical(&mut rng) * 3.0) as u32 + i;
            let r = 0.01 + crate::lines::canonical(&mut rng);
            blocks.add(i, j, r);
            let e = want.entry((i as usize, j as usize)).or_insert((0, 0.0));
            e.0 += 1;
            e.1 += libm::log2(r);
        }
        let mut got = BTreeMap::new();
        let mut order = Vec::new();
        blocks.drain(|i, j, c, l| {
            order.push((i, j));
            got.insert((i, j), (c, l.unwrap()));
        });
        assert_eq!(got.len(), want.len());
        assert_eq!(order.len(), want.len());
        for (k, (c, l)) in &want {
            let (gc, gl) = got[k];
            assert_eq!(gc, *c);
            assert!((gl - l).abs() < 1e-12 * f64::from(*c), "{k:?}: {gl} vs {l}");
        }
        let mut again = 0;
        blocks.drain(|_, _, _, _| again += 1);
        assert_eq!(again, 0);
        blocks.add(3, 4, 2.0);
        blocks.drain(|i, j, c, l| assert_eq!((i, j, c, l), (3, 4, 1, Some(1.0))));
    }
}
