//! The nodes' box tests of [`super::Bvh3::for_each_hit`] in `f32`: four children's slab
//! intervals in one `[f32; 4]` lane each, conservative with respect to the `f64` test of
//! every polygon below, so the tree still never culls a polygon the naive loop reports.
//!
//! # The test
//!
//! Per axis, as [`super::prim::Slab::interval4`] but in `f32` with the origins moved
//! outwards by a second margin `δ`:
//!
//! ```text
//! t_near = (b_near − õ_near) · 1/d,   t_far = (b_far − õ_far) · (−1/d)   (f32)
//! enter = max t_near,   −exit = max t_far,   culled ⇔ enter > exit
//! δ = 2⁻¹⁹ R,   R = max |o_near|, |o_far| + scale
//! ```
//!
//! `õ` is the `f64` origin of the polygon test (`o' ± m`, [`super::prim::Slab`]) moved by
//! `δ` towards the side that lowers `t`, then rounded to the nearest `f32` (which moves it
//! back by at most `2⁻²⁴·1.01 R = δ/32·1.01`); `1/d` is the `f64` inverse rounded to
//! nearest; `b` is a node bound, already rounded outwards (below a polygon's low bound,
//! above its high one), so on the side that lowers `t` too.
//!
//! # Why it is conservative
//!
//! Take a plane term, say `d > 0` and the low plane (the others are mirror images), a
//! node bound `b ≤ p` (`p` the polygon's `f64` bound) and `õ ≥ o + δ(1 − 1.01/32)`
//! (`o` the `f64` origin; `δ = 32·2⁻²⁴R`). All magnitudes are below `R(1 + 2⁻¹⁸)`, so the
//! `f32` difference `D₃₂ = fl(b − õ)` errs by at most `2R·2⁻²⁴·1.01` and the `f64` one
//! `D₆₄ = fl(p − o)` by `2R·2⁻⁵³`: `D₃₂ ≤ D₆₄ − (32 − 1.01 − 2.03)·2⁻²⁴R
//! < D₆₄ − 28·2⁻²⁴R`. The products `fl(D₃₂ · fl₃₂(1/d))` and `fl(D₆₄ · 1/d)` carry
//! relative errors of at most `2·2⁻²⁴` and `2⁻⁵³` on values below `2.01R/|d|`, that is
//! `4.03·2⁻²⁴R/|d|` in all, below the gap `28·2⁻²⁴R/|d|`: the node's `t_near` is at most
//! the polygon's. Likewise its
//! `−t_far`, so the node's interval contains the polygon's `f64` interval, and a polygon
//! whose interval is not empty (step 2 of the polygon test passed: a possible hit) is
//! never culled. With `d = ±0` both inverses are the same infinity and `D₃₂ < D₆₄`, so
//! the `f32` term is `−∞` wherever the `f64` one is `−∞` or NaN (ignored by the folds).
//!
//! The bounds hold when `2⁻⁶⁰ ≤ R ≤ 2⁶⁰` and every `d_i` is `±0` or of magnitude in
//! `[2⁻⁴⁰, 2²⁰]` (no overflow, no product below `f32`'s normal range); otherwise
//! [`Slab32::new`] declines and the walk uses the `f64` test. Sampled global lines (unit
//! directions through the bounding sphere) decline only when a component of the
//! direction is below `2⁻⁴⁰` without being zero.

use crate::geom::DVec3;

/// `2⁻¹⁹`: the second margin `δ` relative to `R` (module docs).
const DELTA: f64 = 1.0 / (1u64 << 19) as f64;

/// Smallest and largest `R` for which the error bounds hold (`2⁻⁶⁰`, `2⁶⁰`).
const MIN_REACH: f64 = 1.0 / (1u64 << 60) as f64;
const MAX_REACH: f64 = (1u64 << 60) as f64;

/// Smallest and largest magnitude of a non-zero direction component (`2⁻⁴⁰`, `2²⁰`).
const MIN_DIR: f64 = 1.0 / (1u64 << 40) as f64;
const MAX_DIR: f64 = (1u64 << 20) as f64;

/// The per-query constants of the `f32` box tests (module docs).
#[derive(Clone, Copy, Debug)]
pub(super) struct Slab32 {
    o_near: [f32; 3],
    o_far: [f32; 3],
    inv: [f32; 3],
    neg_inv: [f32; 3],
}

impl Slab32 {
    /// The `f32` tests of a query whose `f64` tests use the origins `o_near`, `o_far`
    /// (margin applied) and the inverse direction `inv = 1/d` (whose signs choose the
    /// near bounds), in a frame of scale `scale`; `None` where the error bounds of the
    /// module docs do not hold. Branch-free but for that check: it runs once a line.
    #[inline]
    pub(super) fn new(
        o_near: DVec3,
        o_far: DVec3,
        d: DVec3,
        inv: DVec3,
        scale: f64,
    ) -> Option<Self> {
        // `2 max(scale, |o|) ≥ scale + max |o|`, the R of the module docs.
        let reach = 2.0 * o_near.abs().max(o_far.abs()).max_element().max(scale);
        let a = d.abs();
        let dir_ok = (a.cmpeq(DVec3::ZERO)
            | (a.cmpge(DVec3::splat(MIN_DIR)) & a.cmple(DVec3::splat(MAX_DIR))))
        .all();
        if !(dir_ok && (MIN_REACH..=MAX_REACH).contains(&reach)) {
            return None;
        }
        // Towards the side that lowers the terms: where 1/d ≥ +0 a larger near origin and
        // a smaller far one (`copysign` reads the sign of `±∞` and `±0` too).
        let delta = DVec3::splat(DELTA * reach).copysign(inv);
        let to_f32 = |v: DVec3| v.to_array().map(|x| x as f32);
        let inv = to_f32(inv);
        Some(Self {
            o_near: to_f32(o_near + delta),
            o_far: to_f32(o_far - delta),
            inv,
            neg_inv: inv.map(|x| -x),
        })
    }

    /// The slab intervals of four boxes, given per axis their near and far bounds
    /// (`near[i][c]`, `far[i][c]` for box `c`), as `(enter, exit)` per box, lane by lane
    /// (vectorised: one packed operation per step for the four boxes). The folds are
    /// `f32::max` from `−∞`, which skip NaN terms.
    #[inline(always)]
    pub(super) fn interval4(
        &self,
        near: [&[f32; 4]; 3],
        far: [&[f32; 4]; 3],
    ) -> ([f32; 4], [f32; 4]) {
        let mut enter = [f32::NEG_INFINITY; 4];
        let mut neg_exit = [f32::NEG_INFINITY; 4];
        for i in 0..3 {
            let (o_near, o_far) = (self.o_near[i], self.o_far[i]);
            let (inv, neg_inv) = (self.inv[i], self.neg_inv[i]);
            for c in 0..4 {
                let tn = (near[i][c] - o_near) * inv;
                let tf = (far[i][c] - o_far) * neg_inv;
                enter[c] = tn.max(enter[c]);
                neg_exit[c] = tf.max(neg_exit[c]);
            }
        }
        (enter, neg_exit.map(|x| -x))
    }
}

/// `x` rounded down to an `f32` (`−∞` below its range).
#[inline]
pub(super) fn f32_down(x: f64) -> f32 {
    let y = x as f32;
    if f64::from(y) > x { y.next_down() } else { y }
}

/// `x` rounded up to an `f32` (`+∞` above its range).
#[inline]
pub(super) fn f32_up(x: f64) -> f32 {
    let y = x as f32;
    if f64::from(y) < x { y.next_up() } else { y }
}
