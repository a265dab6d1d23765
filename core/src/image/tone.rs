//! The tone map: exposure, then the sRGB curve to 8 bits — the last steps of the colour
//! pipeline (see [`super`]).

use crate::math;
use crate::scene::Material;

/// Linear exposure with white at `white`, then the sRGB curve to 8 bits:
///
/// ```text
/// c  = clamp(B / white, 0, 1)                                  (exposure)
/// c' = 12.92 c                  for c ≤ 0.0031308              (sRGB, IEC 61966-2-1)
///      1.055 c^(1/2.4) − 0.055  otherwise
/// byte = ⌊255 c' + ½⌋
/// ```
///
/// [`ToneMap::for_scene`] picks `white` as the largest radiosity (over the three channels)
/// of the patches that do not emit, so reflected light uses the whole range and light
/// sources clip to white.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ToneMap {
    /// The radiosity shown as full white (`> 0`; a non-positive or non-finite value maps
    /// everything to black).
    pub white: f64,
}

impl ToneMap {
    /// White at the largest finite radiosity of a non-emitting patch (or of any patch when
    /// no non-emitting patch is lit: every patch emits, or the reflectors are black);
    /// `materials` per patch, `radiosity` per state (extra states ignored). `0` when nothing
    /// is lit: then every value maps to black.
    #[must_use]
    pub fn for_scene(radiosity: &[[f64; 3]], materials: &[Material]) -> Self {
        let max_of = |emitters: bool| {
            radiosity
                .iter()
                .zip(materials)
                .filter(|(_, m)| emitters || !m.is_emitter())
                .flat_map(|(b, _)| b.iter().copied())
                .filter(|x| x.is_finite())
                .fold(0.0_f64, f64::max)
        };
        let white = match max_of(false) {
            w if w > 0.0 => w,
            _ => max_of(true),
        };
        Self { white }
    }

    /// The exposure of one channel, `clamp(B / white, 0, 1)`: the linear display value
    /// (`0` for a non-positive or NaN `B`, or a `white` that is not positive and finite).
    /// Pictures that average samples (the supersampling renderer) average these.
    #[must_use]
    pub fn exposure(&self, b: f64) -> f64 {
        if self.white > 0.0 && self.white.is_finite() && b > 0.0 {
            (b / self.white).min(1.0)
        } else {
            0.0
        }
    }

    /// One channel: `B ↦ 0..=255`, [`ToneMap::encode`] of [`ToneMap::exposure`].
    #[must_use]
    pub fn channel(&self, b: f64) -> u8 {
        Self::encode(self.exposure(b))
    }

    /// A linear value (`1` = white; clamped to `[0, 1]`, NaN black) through the sRGB
    /// transfer function to `0..=255`: `12.92 c` below `0.0031308`, else
    /// `1.055 c^{1/2.4} − 0.055` (IEC 61966-2-1). The one colour encoding of every picture
    /// and mesh the front ends write.
    #[must_use]
    pub fn encode(c: f64) -> u8 {
        let c = if c > 0.0 { c.min(1.0) } else { 0.0 };
        let encoded = if c <= 0.003_130_8 {
            12.92 * c
        } else {
            1.055 * math::pow(c, 1.0 / 2.4) - 0.055
        };
        // In [0, 1] by construction; the cast saturates anyway.
        (255.0 * encoded + 0.5) as u8
    }

    /// An RGB triple.
    #[must_use]
    pub fn rgb(&self, b: [f64; 3]) -> [u8; 3] {
        [self.channel(b[0]), self.channel(b[1]), self.channel(b[2])]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn encode_is_the_srgb_curve_clamped() {
        // sRGB(0.5) = 1.055 · 0.5^(1/2.4) − 0.055 = 0.7354 → 187.5 → 188
        assert_eq!(ToneMap::encode(0.5), 188);
        assert_eq!(ToneMap::encode(0.0), 0);
        assert_eq!(ToneMap::encode(1.0), 255);
        assert_eq!(ToneMap::encode(2.0), 255);
        assert_eq!(ToneMap::encode(-1.0), 0);
        assert_eq!(ToneMap::encode(f64::NAN), 0);
        // the linear toe: 12.92 · 0.001 = 0.01292 → 3.29 → 3
        assert_eq!(ToneMap::encode(0.001), 3);
        let tone = ToneMap { white: 4.0 };
        assert_eq!(tone.channel(2.0), ToneMap::encode(0.5));
        assert_eq!(tone.exposure(2.0), 0.5);
        assert_eq!(tone.exposure(8.0), 1.0);
        assert_eq!(tone.exposure(-1.0), 0.0);
        assert_eq!(ToneMap { white: f64::NAN }.exposure(1.0), 0.0);
    }
    #[test]
    fn tone_map_is_srgb_of_a_linear_exposure() {
        let t = ToneMap { white: 2.0 };
        assert_eq!(t.channel(0.0), 0);
        assert_eq!(t.channel(2.0), 255);
        assert_eq!(t.channel(50.0), 255);
        assert_eq!(t.channel(f64::NAN), 0);
        // 18 % grey encodes to 118 in sRGB.
        assert_eq!(t.channel(0.36), 118);
        // The linear toe.
        assert_eq!(t.channel(2.0 * 0.002), (255.0 * 12.92 * 0.002 + 0.5) as u8);
        assert_eq!(ToneMap { white: 0.0 }.channel(1.0), 0);
    }

    #[test]
    fn white_is_the_brightest_reflector() {
        let lamp = Material::new([0.0; 3], [5.0; 3]).unwrap();
        let wall = Material::new([0.5; 3], [0.0; 3]).unwrap();
        let b = [[5.0; 3], [0.2, 0.7, 0.1], [0.3, 0.3, 0.3]];
        let t = ToneMap::for_scene(&b, &[lamp, wall, wall]);
        assert_eq!(t.white, 0.7);
        assert_eq!(ToneMap::for_scene(&b[..1], &[lamp]).white, 5.0);
    }
}
