//! Discrete radiosity entropies and mutual information (thesis §5.2, 5.5–5.7) without
//! building the radiosity matrix: `RadiosityTransitions` computes each entry
//! `𝐅_ij = F_ij B_j / B_i^in` (5.1) on the fly from `F` and `B`, dense or sparse, so a
//! scene of any size needs only two extra vectors (`B^in` and the weights `𝐚`).
//!
//! ```text
//! H_P = −Σ_i 𝐚_i log 𝐚_i                              (5.6)
//! H_S = −Σ_i 𝐚_i Σ_j 𝐅_ij log 𝐅_ij                    (5.5)
//! I_S =  Σ_i Σ_j 𝐚_i 𝐅_ij log(𝐅_ij / 𝐚_j)              (5.7)
//! ```
//!
//! The limits are those of [`RadiosityMeasures::channel_into`]: the incoming radiosity is
//! `B_i^in = Σ_j F_ij B_j` (equal to `(B_i − E_i)/ρ_i` for the solution of (2.6), and its
//! limit where `ρ_i = 0`); a state with `B_i^in = 0` or `B_i = 0` has weight 0 and an empty
//! row. When no light flows between states at all (every weight 0: nothing emits, or the
//! emitters only see black surfaces) the channel is empty and every measure is 0 — no
//! information is transferred, which is how the thesis reads the blue column of its
//! Table 5.3 ([`RadiosityMeasures::light_flows`] is then `false`).

use core::ops::Range;

use crate::channel::{Channel, Transitions};
use crate::error::{ErrorKind, Result};
use crate::math::KahanSum;

/// The radiosity transition matrix (5.1) as a view over `F` and `B`:
/// `𝐅_ij = F_ij B_j / B_i^in`, rows with `B_i^in = 0` or `B_i = 0` empty.
///
/// Build it with [`RadiosityTransitions::new`]; pass it to [`Channel::new`] with the weights
/// of [`radiosity_weights_into`].
#[derive(Clone, Copy, Debug)]
pub(crate) struct RadiosityTransitions<'a, M> {
    f: &'a M,
    b: &'a [f64],
    b_in: &'a [f64],
}

impl<'a, M: Transitions> RadiosityTransitions<'a, M> {
    /// The view over form factors `f`, radiosities `b` and incoming radiosities `b_in`
    /// (from [`incoming_radiosity_into`]).
    ///
    /// # Errors
    /// [`ErrorKind::DimensionMismatch`] unless `b` and `b_in` have `n_states` entries.
    pub fn new(f: &'a M, b: &'a [f64], b_in: &'a [f64]) -> Result<Self> {
        let n = f.n_states();
        for len in [b.len(), b_in.len()] {
            if len != n {
                return Err(ErrorKind::DimensionMismatch {
                    expected: n,
                    found: len,
                }
                .into());
            }
        }
        Ok(Self { f, b, b_in })
    }

    /// Whether row `i` carries light (`B_i^in > 0` and `B_i > 0`).
    #[inline]
    fn active(&self, i: usize) -> bool {
        self.b_in.get(i).is_some_and(|&x| x > 0.0) && self.b.get(i).is_some_and(|&x| x > 0.0)
    }
}

impl<M: Transitions> Transitions for RadiosityTransitions<'_, M> {
    #[inline]
    fn n_states(&self) -> usize {
        self.f.n_states()
    }

    fn for_each_in_row<F: FnMut(usize, f64)>(&self, i: usize, mut f: F) {
        if !self.active(i) {
            return;
        }
        let b_in = self.b_in[i];
        self.f.for_each_in_row(i, |j, v| {
            let p = v * self.b.get(j).copied().unwrap_or(0.0) / b_in;
            if p > 0.0 {
                f(j, p);
            }
        });
    }

    fn get(&self, i: usize, j: usize) -> f64 {
        if !self.active(i) {
            return 0.0;
        }
        self.f.get(i, j) * self.b.get(j).copied().unwrap_or(0.0) / self.b_in[i]
    }

    fn for_each_in_row_range<F: FnMut(usize, f64)>(&self, i: usize, cols: Range<usize>, mut f: F) {
        if !self.active(i) {
            return;
        }
        let b_in = self.b_in[i];
        self.f.for_each_in_row_range(i, cols, |j, v| {
            let p = v * self.b.get(j).copied().unwrap_or(0.0) / b_in;
            if p > 0.0 {
                f(j, p);
            }
        });
    }
}

/// Writes the incoming radiosity `B_i^in = Σ_j F_ij B_j` of every state into `out`.
///
/// # Errors
/// [`ErrorKind::DimensionMismatch`] unless `b` and `out` have `n_states` entries;
/// [`ErrorKind::NonFiniteEntry`] / [`ErrorKind::NegativeEntry`] for a bad `B_i`.
pub(crate) fn incoming_radiosity_into<M: Transitions>(
    f: &M,
    b: &[f64],
    out: &mut [f64],
) -> Result<()> {
    let n = f.n_states();
    for len in [b.len(), out.len()] {
        if len != n {
            return Err(ErrorKind::DimensionMismatch {
                expected: n,
                found: len,
            }
            .into());
        }
    }
    for (k, &x) in b.iter().enumerate() {
        if !x.is_finite() {
            return Err(ErrorKind::NonFiniteEntry { row: k, col: 0 }.into());
        }
        if x < 0.0 {
            return Err(ErrorKind::NegativeEntry { row: k, col: 0 }.into());
        }
    }
    for (i, o) in out.iter_mut().enumerate() {
        let mut s = KahanSum::new();
        f.for_each_in_row(i, |j, v| s.add(v * b.get(j).copied().unwrap_or(0.0)));
        *o = s.total();
    }
    Ok(())
}

/// Writes the stationary distribution of the radiosity channel (5.2),
/// `𝐚_i = A_i B_i^in B_i / Σ_k A_k B_k^in B_k`, into `out` and returns the unnormalised total
/// `𝐀_T = Σ_k A_k B_k^in B_k`. A total of 0 (no light flows) leaves `out` all zero.
///
/// # Errors
/// [`ErrorKind::DimensionMismatch`] unless all slices have the same length;
/// [`ErrorKind::NonFiniteEntry`] / [`ErrorKind::NegativeEntry`] for a size that is not
/// positive and finite or a negative or non-finite `B_i`, `B_i^in`;
/// [`ErrorKind::NotFinite`] when the total overflows.
pub(crate) fn radiosity_weights_into(
    sizes: &[f64],
    b: &[f64],
    b_in: &[f64],
    out: &mut [f64],
) -> Result<f64> {
    let n = sizes.len();
    for len in [b.len(), b_in.len(), out.len()] {
        if len != n {
            return Err(ErrorKind::DimensionMismatch {
                expected: n,
                found: len,
            }
            .into());
        }
    }
    out.copy_from_slice(b_in);
    generalised_areas_in_place(sizes, b, out)
}

/// [`radiosity_weights_into`] with the incoming radiosities `B^in` given in `weights` and
/// replaced by the weights `𝐚`: the one implementation of (5.2). Lengths are the caller's
/// to check (extra entries of `b` or `weights` are ignored).
pub(super) fn generalised_areas_in_place(
    sizes: &[f64],
    b: &[f64],
    weights: &mut [f64],
) -> Result<f64> {
    let mut total = KahanSum::new();
    for (k, ((&a, &x), o)) in sizes.iter().zip(b).zip(weights.iter_mut()).enumerate() {
        let y = *o;
        if !(a.is_finite() && x.is_finite() && y.is_finite()) {
            return Err(ErrorKind::NonFiniteEntry { row: k, col: 0 }.into());
        }
        if !(a > 0.0) || x < 0.0 || y < 0.0 {
            return Err(ErrorKind::NegativeEntry { row: k, col: 0 }.into());
        }
        *o = a * y * x;
        total.add(*o);
    }
    let total = total.total();
    if !total.is_finite() {
        return Err(ErrorKind::NotFinite {
            what: "radiosity channel weights Σ A_i B_i^in B_i (5.2)",
        }
        .into());
    }
    if total > 0.0 {
        for o in weights.iter_mut() {
            *o /= total;
        }
    }
    Ok(total)
}

/// The discrete radiosity measures of one colour channel (5.5–5.7).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RadiosityMeasures {
    /// Positional entropy `H_P` of the weights `𝐚` (5.6).
    pub h_p: f64,
    /// Scene radiosity entropy `H_S` (5.5).
    pub h_s: f64,
    /// Joint entropy `H_J = H_P + H_S`.
    pub h_j: f64,
    /// Scene radiosity mutual information `I_S` (5.7): the complexity of the lit scene.
    pub i_s: f64,
    /// The unnormalised total `𝐀_T = Σ_i A_i B_i^in B_i` (5.13); 0 when no light flows.
    pub total_weight: f64,
    /// Whether any light flows between states; `false` means the empty channel, all
    /// measures 0.
    pub light_flows: bool,
}

impl RadiosityMeasures {
    /// The empty channel: no light flows, no information.
    pub const EMPTY: Self = Self {
        h_p: 0.0,
        h_s: 0.0,
        h_j: 0.0,
        i_s: 0.0,
        total_weight: 0.0,
        light_flows: false,
    };
}

impl RadiosityMeasures {
    /// Computes `H_P`, `H_S`, `H_J` and `I_S` of the radiosity channel of one colour channel
    /// from form factors `f`, patch sizes `sizes` (areas or lengths, any scale) and radiosities
    /// `b` (a solution of (2.6)), using the caller's buffers `b_in` and `weights` (`n` entries
    /// each; they receive `B^in` and `𝐚`).
    ///
    /// # Errors
    /// The errors of `incoming_radiosity_into` and `radiosity_weights_into`, and of
    /// [`Channel::new`]: [`ErrorKind::TransitionToNullState`] when a state that sends light
    /// receives none while another state sends light to it (impossible for a reciprocal `F`).
    pub fn of<M: Transitions>(
        f: &M,
        sizes: &[f64],
        b: &[f64],
        b_in: &mut [f64],
        weights: &mut [f64],
    ) -> Result<RadiosityMeasures> {
        incoming_radiosity_into(f, b, b_in)?;
        let total = radiosity_weights_into(sizes, b, b_in, weights)?;
        if total == 0.0 {
            return Ok(RadiosityMeasures::EMPTY);
        }
        let p = RadiosityTransitions::new(f, b, b_in)?;
        let channel = Channel::new(weights, p)?;
        let (h_p, h_s) = (channel.h_p(), channel.h_s());
        Ok(RadiosityMeasures {
            h_p,
            h_s,
            h_j: h_p + h_s,
            i_s: channel.i_s(),
            total_weight: total,
            light_flows: true,
        })
    }
}
