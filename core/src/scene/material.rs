//! Surface materials.

use crate::error::{ErrorKind, Result};

/// A diffuse material: reflectance ρ ∈ [0, 1) and emittance E ≥ 0, per RGB channel
/// (thesis §2.1.4, the radiosity equation B = E + ρ F B).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    /// Reflectance ρ per channel, each in `[0, 1)`.
    pub reflectance: [f64; 3],
    /// Emittance E per channel, each `≥ 0`.
    pub emittance: [f64; 3],
}

impl Default for Material {
    /// Black and non-emitting: ρ = 0, E = 0.
    fn default() -> Self {
        Self::BLACK
    }
}

impl Material {
    /// ρ = 0, E = 0.
    pub const BLACK: Self = Self {
        reflectance: [0.0; 3],
        emittance: [0.0; 3],
    };

    /// Largest emittance accepted: `E ≤ 10¹⁰⁰` per channel.
    ///
    /// Every computation on a scene must stay finite, and the largest quantities it forms
    /// from `E` are bounded by:
    ///
    /// ```text
    /// radiosity      B ≤ E_max / (1 − ρ_max) = 100 E_max        (2.6, ρ ≤ 0.99)
    /// patch power    Φ_i = B_i A_i ≤ 100 E_max · 1.3·10³⁶        (stored extent ≤ 2⁶⁰, Frame)
    /// total power    Σ_i Φ_i ≤ 4·10⁶ · 1.3·10³⁸ E_max ≈ 5·10⁴⁴ E_max (≤ 4·10⁶ patches)
    /// second moments (Σ Φ)², Σ A_i B_i^in B_i (5.2), B_i B_j A_i F_ij, Σ s² ≤ 2.7·10⁸⁹ E_max²
    /// ```
    ///
    /// Areas are the stored ones ([`crate::scene::Frame`]: a scene's extent is kept within
    /// `2⁻⁶⁰ … 2⁶⁰` whatever its units, so `A ≤ 2¹²⁰ ≈ 1.3·10³⁶`). The last line must stay
    /// below `f64::MAX ≈ 1.8·10³⁰⁸`, so `E_max < 2.6·10¹⁰⁹`; `10¹⁰⁰` keeps a margin of `10¹⁸`
    /// in the squares for the kernels and weights multiplied in on the way.
    /// An emittance of `10³⁰⁸` (accepted before) made `B` infinite, every oracle value NaN
    /// or infinite, and hierarchical refinement split every pair down to its smallest
    /// element.
    pub const MAX_EMITTANCE: f64 = 1e100;

    /// A validated material.
    ///
    /// # Errors
    /// [`ErrorKind::NonFiniteNumber`] for NaN or infinite values, [`ErrorKind::Reflectance`]
    /// when some ρ is outside `[0, 1)` (ρ = 1 would make the radiosity system singular in a
    /// closed scene), [`ErrorKind::Emittance`] when some E is negative,
    /// [`ErrorKind::EmittanceTooLarge`] when some E exceeds [`Self::MAX_EMITTANCE`].
    pub fn new(reflectance: [f64; 3], emittance: [f64; 3]) -> Result<Self> {
        for &r in &reflectance {
            if !r.is_finite() {
                return Err(ErrorKind::NonFiniteNumber { field: "rho" }.into());
            }
            if !(0.0..1.0).contains(&r) {
                return Err(ErrorKind::Reflectance { value: r }.into());
            }
        }
        for &e in &emittance {
            if !e.is_finite() {
                return Err(ErrorKind::NonFiniteNumber { field: "emit" }.into());
            }
            if e < 0.0 {
                return Err(ErrorKind::Emittance { value: e }.into());
            }
            if e > Self::MAX_EMITTANCE {
                return Err(ErrorKind::EmittanceTooLarge {
                    value: e,
                    max: Self::MAX_EMITTANCE,
                }
                .into());
            }
        }
        Ok(Self {
            reflectance,
            emittance,
        })
    }

    /// Largest reflectance a loader keeps from a file: `ρ ≥ 1` (white, `Kd 1`, a glTF base
    /// colour of 1, common in real files) is clamped to it. The radiosity iteration contracts
    /// by the largest ρ per sweep (B = E + ρFB, thesis (2.6), with a row-stochastic F), so at
    /// 0.99 a closed scene white everywhere needs about 2,300 Jacobi sweeps to reach the
    /// solvers' default residual of 1e-10, well inside their iteration cap.
    pub const MAX_REFLECTANCE: f64 = 0.99;

    /// A material as a file gives it: reflectances above [`Self::MAX_REFLECTANCE`] are
    /// clamped to it; the second value says whether any was.
    ///
    /// # Errors
    /// As [`Self::new`] for what clamping cannot repair: NaN or infinite values, a negative
    /// reflectance or emittance.
    pub fn clamped(reflectance: [f64; 3], emittance: [f64; 3]) -> Result<(Self, bool)> {
        let mut clamped = false;
        let rho = reflectance.map(|r| {
            if r > Self::MAX_REFLECTANCE && r.is_finite() {
                clamped = true;
                Self::MAX_REFLECTANCE
            } else {
                r
            }
        });
        Ok((Self::new(rho, emittance)?, clamped))
    }

    /// Whether any channel emits.
    #[must_use]
    pub fn is_emitter(&self) -> bool {
        self.emittance.iter().any(|&e| e > 0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn validates_ranges() {
        assert!(Material::new([0.5; 3], [0.0; 3]).is_ok());
        assert!(matches!(
            Material::new([1.0, 0.0, 0.0], [0.0; 3]).unwrap_err().kind(),
            ErrorKind::Reflectance { .. }
        ));
        assert!(matches!(
            Material::new([0.1; 3], [0.0, -1.0, 0.0])
                .unwrap_err()
                .kind(),
            ErrorKind::Emittance { .. }
        ));
        assert!(matches!(
            Material::new([f64::NAN; 3], [0.0; 3]).unwrap_err().kind(),
            ErrorKind::NonFiniteNumber { .. }
        ));
        assert!(Material::new([0.99; 3], [Material::MAX_EMITTANCE; 3]).is_ok());
        let e = Material::new([0.5; 3], [1.0, 1e308, 1.0]).unwrap_err();
        assert!(matches!(e.kind(), ErrorKind::EmittanceTooLarge { .. }));
        assert!(alloc::format!("{e}").starts_with("emittance 1e308 is too large"));
    }
}
