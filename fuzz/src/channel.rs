//! The check behind the `fuzz_channel` target: arbitrary distributions and matrices into
//! the channel constructors (`Channel::new` over `DenseMatrix` and `CsrMatrix`,
//! `CsrMatrixBuf::from_dense`) and every measure, asserting the invariant stated in
//! `fuzz/fuzz_targets/fuzz_channel.rs`.
//!
//! Input layout: byte 0 chooses `n = 1 + (b₀ mod 8)` states and a mode (`b₀ / 8 mod 4`):
//!
//! - 0, raw: `n` weights then `n²` entries, each 8 little-endian bytes of an `f64`
//!   (NaN, infinities, negatives and all): the constructors must refuse or accept
//!   cleanly;
//! - 1, reversible: a symmetric `n × n` matrix `S` from byte pairs (mantissa, exponent:
//!   `m · 2^−(x mod 96)`; a zero row gets `S_ii = 1`), `w_i = Σ_j S_ij / Σ S`,
//!   `P_ij = S_ij / Σ_j S_ij`: a closed, reversible, stationary channel whose identities
//!   must hold;
//! - 2, sub-stochastic: `w` and the rows of `P` from single bytes, each row scaled to sum
//!   to at most one;
//! - 3, reversible as in 1, plus the Markov helpers (stationary distribution, entropy rate,
//!   block and excess entropies).
//!
//! Missing bytes read as zero. Compiled by the fuzz crate and, through `#[path]`, by
//! `tests/fuzz_replay.rs`.

use core::fmt;

use sceneinfo::channel::{Channel, CsrMatrixBuf};

use super::invariants::{self, MAX_INPUT_BYTES, Outcome};

/// Agreement asked of the dense and the sparse forms of one channel (relative to
/// `1 + |value|`): they add the same terms, up to the zeros the sparse form skips.
pub const FORMS_AGREE: f64 = 1e-12;

/// A decoded channel: the distribution and the row-major matrix.
pub struct ChannelCase {
    /// The mode (0 to 3, see the module docs).
    pub mode: u8,
    /// The distribution `w`.
    pub w: Vec<f64>,
    /// The `n × n` matrix `P`, row-major.
    pub p: Vec<f64>,
}

impl fmt::Debug for ChannelCase {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "reproducer (mode {}):", self.mode)?;
        writeln!(f, "    let w: Vec<f64> = vec!{:?};", self.w)?;
        writeln!(f, "    let p: Vec<f64> = vec!{:?};", self.p)?;
        write!(f, "    let channel = Channel::from_dense(&w, &p);")
    }
}

/// Reads bytes, yielding zeros past the end.
struct Bytes<'a>(core::slice::Iter<'a, u8>);

impl Bytes<'_> {
    fn byte(&mut self) -> u8 {
        self.0.next().copied().unwrap_or(0)
    }

    fn raw_f64(&mut self) -> f64 {
        let mut b = [0u8; 8];
        for x in &mut b {
            *x = self.byte();
        }
        f64::from_le_bytes(b)
    }

    /// `m · 2^−(x mod 96)`, a non-negative number spanning 29 decades.
    fn scaled(&mut self) -> f64 {
        let (m, x) = (self.byte(), self.byte());
        f64::from(m) * 2f64.powi(-i32::from(x % 96))
    }
}

/// Decodes an input (see the module docs).
#[must_use]
pub fn decode(data: &[u8]) -> ChannelCase {
    let mut bytes = Bytes(data.iter());
    let head = bytes.byte();
    let n = 1 + usize::from(head % 8);
    let mode = (head / 8) % 4;
    let (w, p) = match mode {
        0 => {
            let w = (0..n).map(|_| bytes.raw_f64()).collect();
            let p = (0..n * n).map(|_| bytes.raw_f64()).collect();
            (w, p)
        }
        2 => {
            let raw: Vec<f64> = (0..n).map(|_| f64::from(bytes.byte())).collect();
            let total: f64 = raw.iter().sum();
            let w = raw
                .iter()
                .map(|&x| if total > 0.0 { x / total } else { 0.0 })
                .collect();
            let mut p = vec![0.0; n * n];
            for row in p.chunks_mut(n) {
                let scale = f64::from(bytes.byte().max(1));
                for x in row.iter_mut() {
                    *x = f64::from(bytes.byte());
                }
                let sum: f64 = row.iter().sum::<f64>().max(scale);
                for x in row.iter_mut() {
                    *x /= sum;
                }
            }
            (w, p)
        }
        _ => {
            let mut s = vec![0.0; n * n];
            for i in 0..n {
                for j in i..n {
                    let v = bytes.scaled();
                    s[i * n + j] = v;
                    s[j * n + i] = v;
                }
            }
            // A state that sees nothing keeps to itself (S_ii = 1): every row then sums
            // to one and w = row sums stays stationary
            for i in 0..n {
                if s[i * n..(i + 1) * n].iter().all(|&v| v == 0.0) {
                    s[i * n + i] = 1.0;
                }
            }
            let row_sums: Vec<f64> = s.chunks(n).map(|r| r.iter().sum()).collect();
            let total: f64 = row_sums.iter().sum();
            let w = row_sums
                .iter()
                .map(|&r| if total > 0.0 { r / total } else { 0.0 })
                .collect();
            let mut p = s;
            for (row, &r) in p.chunks_mut(n).zip(&row_sums) {
                for x in row.iter_mut() {
                    *x = if r > 0.0 { *x / r } else { 0.0 };
                }
            }
            (w, p)
        }
    };
    ChannelCase { mode, w, p }
}

/// Runs one input through the constructors and measures.
///
/// # Panics
///
/// When the core panics or an invariant breaks (the message holds a reproducer).
pub fn check(data: &[u8]) -> Outcome {
    if data.len() > MAX_INPUT_BYTES {
        return Outcome::Rejected;
    }
    let case = decode(data);
    let fail = |problem: String| -> ! { panic!("{problem}\n{case:?}") };
    let n = case.w.len();

    // The dense channel: refused cleanly or measured with every invariant
    let dense = match Channel::from_dense(&case.w, &case.p) {
        Ok(channel) => channel,
        Err(err) => return invariants::refused(&err, &case),
    };
    let measures = match invariants::check_channel(&dense) {
        Ok(m) => m,
        Err(problem) => fail(format!("dense: {problem}")),
    };
    if case.mode % 2 == 1 {
        let checks = dense.checks();
        let tol = 1e-12;
        if !(checks.is_row_stochastic(tol) && checks.is_reversible(1e-9)) {
            fail(format!(
                "a reversible construction fails its checks: {checks:?}"
            ));
        }
    }

    // The same channel in CSR form agrees
    let csr = match CsrMatrixBuf::from_dense(n, &case.p) {
        Ok(csr) => csr,
        Err(err) => fail(format!("CsrMatrixBuf refused what DenseMatrix took: {err}")),
    };
    let sparse = match Channel::new(&case.w, csr.as_matrix()) {
        Ok(channel) => channel,
        Err(err) => fail(format!(
            "the CSR channel refused what the dense took: {err}"
        )),
    };
    let sparse_measures = match invariants::check_channel(&sparse) {
        Ok(m) => m,
        Err(problem) => fail(format!("sparse: {problem}")),
    };
    let pairs = [
        ("h_p", measures.h_p, sparse_measures.h_p),
        ("h_s", measures.h_s, sparse_measures.h_s),
        ("h_j", measures.h_j, sparse_measures.h_j),
        ("i_s", measures.i_s, sparse_measures.i_s),
        ("e_mse", measures.e_mse, sparse_measures.e_mse),
    ];
    for (name, a, b) in pairs {
        if (a - b).abs() > FORMS_AGREE * (1.0 + a.abs()) {
            fail(format!("{name}: dense {a} vs sparse {b}"));
        }
    }

    // Per-patch splits: finite, and they add up to the scene measures
    let mut out = vec![0.0; n];
    let mut matrix = vec![0.0; n * n];
    let checked = dense
        .patch_mutual_information(&mut out)
        .map_err(|e| e.to_string())
        .and_then(|()| invariants::all_finite("I_i", &out))
        .and_then(|()| {
            let sum: f64 = out.iter().sum();
            if (sum - measures.i_s).abs() > 1e-12 * (1.0 + out.iter().map(|x| x.abs()).sum::<f64>())
            {
                return Err(format!("I_i sum to {sum}, I_S = {}", measures.i_s));
            }
            Ok(())
        })
        .and_then(|()| dense.patch_entropies(&mut out).map_err(|e| e.to_string()))
        .and_then(|()| invariants::all_finite("H_i", &out))
        .and_then(|()| {
            dense
                .mutual_information_matrix(&mut matrix)
                .map_err(|e| e.to_string())
        })
        .and_then(|()| invariants::all_finite("I_ij", &matrix));
    if let Err(problem) = checked {
        fail(problem);
    }

    // The Markov helpers
    if case.mode == 3 {
        // Documented to equal H_S bit for bit for a valid channel
        let rate = Channel::entropy_rate(&case.w, dense.transitions());
        if rate.to_bits() != dense.h_s().to_bits() {
            fail(format!("entropy rate {rate} vs H_S {}", dense.h_s()));
        }
        let (mut stat, mut scratch) = (vec![0.0; n], vec![0.0; n]);
        let found = Channel::stationary_distribution(
            dense.transitions(),
            &mut stat,
            &mut scratch,
            1e-12,
            10_000,
        );
        if found.is_ok()
            && let Err(problem) = invariants::all_finite("stationary", &stat)
        {
            fail(problem);
        }
        for len in 1..=3 {
            let values = [dense.block_entropy(len), dense.excess_entropy(len)];
            if let Some(v) = values.into_iter().flatten().find(|v| !v.is_finite()) {
                fail(format!("block/excess entropy of length {len} = {v}"));
            }
        }
    }
    Outcome::Checked
}
