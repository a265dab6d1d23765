//! The radiosity channel (thesis §5.1–5.2): a lit scene read as a Markov chain.
//!
//! For one colour channel with radiosity `B`, emittance `E` and reflectance `ρ`, the
//! null-variance transition matrix (2.46, 5.1) and its stationary distribution (5.2) are
//!
//! ```text
//! P_ij = ρ_i F_ij B_j / (B_i − E_i),      𝐀_i = A_i B_i (B_i − E_i) / ρ_i = A_i B_i^in B_i
//! ```
//!
//! with the extended reciprocity `𝐀_i P_ij = A_i B_i F_ij B_j = 𝐀_j P_ji` (5.4). Here the
//! incoming radiosity is computed from its definition, `B_i^in = Σ_j F_ij B_j`, which equals
//! `(B_i − E_i)/ρ_i` for the solution of (2.6) and is its limit where `ρ_i = 0`; then
//! `P_ij = F_ij B_j / B_i^in` and every row with incoming light sums to one exactly, whatever
//! the solver's tolerance.
//!
//! A state that receives no light (`B_i^in = 0`) or sends none (`B_i = 0`) has weight 0 and an
//! empty row: it carries no light through the chain. A state that sends light but receives
//! none cannot be a state of the chain (its transitions would be infinite): that is the error
//! [`ErrorKind::TransitionToNullState`].

use super::measures::{
    RadiosityMeasures, RadiosityTransitions, generalised_areas_in_place, incoming_radiosity_into,
};
use crate::channel::Transitions;
use crate::error::{ErrorKind, Result};

impl RadiosityMeasures {
    /// Writes the radiosity channel of one colour channel: the stationary distribution
    /// `𝐚_i = 𝐀_i / Σ 𝐀` into `weights` (length `n`) and the row-major `n × n` transitions
    /// `P_ij` (5.1) into `matrix`. `sizes` are the patch areas (lengths), `b` the radiosities.
    ///
    /// Feed the result to [`crate::channel::Channel::new`] with a
    /// [`crate::channel::DenseMatrix`] to get the radiosity entropies and mutual information
    /// (5.5–5.7).
    ///
    /// # Errors
    /// [`ErrorKind::DimensionMismatch`] / [`ErrorKind::BufferTooSmall`] for bad lengths;
    /// [`ErrorKind::NonFiniteEntry`] / [`ErrorKind::NegativeEntry`] for bad sizes or
    /// radiosities; [`ErrorKind::TransitionToNullState`] when a patch that emits light receives
    /// none; [`ErrorKind::NotNormalized`] when no light flows at all.
    pub fn channel_into<M: Transitions>(
        f: &M,
        sizes: &[f64],
        b: &[f64],
        weights: &mut [f64],
        matrix: &mut [f64],
    ) -> Result<()> {
        let n = f.n_states();
        for (len, what) in [(sizes.len(), n), (b.len(), n)] {
            if len != what {
                return Err(ErrorKind::DimensionMismatch {
                    expected: n,
                    found: len,
                }
                .into());
            }
        }
        if weights.len() < n || matrix.len() < n * n {
            let (needed, found) = if weights.len() < n {
                (n, weights.len())
            } else {
                (n * n, matrix.len())
            };
            return Err(ErrorKind::BufferTooSmall { needed, found }.into());
        }
        let weights = &mut weights[..n];
        // Incoming radiosity B_i^in = Σ_j F_ij B_j (into `weights`), the rows (5.1) ...
        incoming_radiosity_into(f, b, weights)?;
        let p = RadiosityTransitions::new(f, b, weights)?;
        for i in 0..n {
            let row = &mut matrix[i * n..(i + 1) * n];
            row.fill(0.0);
            p.for_each_in_row(i, |j, v| row[j] = v);
        }
        // ... and the generalised areas (5.2), in place.
        let total = generalised_areas_in_place(sizes, b, weights)?;
        if !(total > 0.0) {
            return Err(ErrorKind::NotNormalized { sum: total }.into());
        }
        // A transition into a state of weight 0 that still sends light (it receives none).
        for i in 0..n {
            for j in 0..n {
                if matrix[i * n + j] > 0.0 && weights[j] == 0.0 {
                    return Err(ErrorKind::TransitionToNullState { row: i, col: j }.into());
                }
            }
        }
        Ok(())
    }
}
