//! Refinement oracles: given a pair of elements, link them or refine one (thesis §2.1.12,
//! §6.2, §6.4).
//!
//! Every oracle sees the pair through a [`Pair`] — receiver `i`, source `j`, their areas,
//! normals, reflectances, emittances, current radiosities and gathered irradiances — and
//! `N` point pairs of the kernel ([`KernelSamples`]). Radiosities are RGB; an oracle's
//! products of a reflectance and a radiosity (or of two radiosities) are taken per channel
//! and the largest channel counts, so a pair is linked only when every channel is accurate
//! enough.

use crate::geom::DVec3;
use crate::hierarchy::element::Polygon4;
use crate::hierarchy::kernel::{KernelSamples, Visibility, point_kernel};

/// What an oracle decides for a pair.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Decision {
    /// The interaction is accurate enough at this level: make a link.
    Link,
    /// Split the receiver `i` and look again at its children with `j`.
    RefineReceiver,
    /// Split the source `j` and look again at `i` with its children.
    RefineSource,
}

/// One element of a pair, as an oracle sees it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Side<'a> {
    /// The element's shape.
    pub polygon: &'a Polygon4,
    /// Area `A`.
    pub area: f64,
    /// Unit front normal.
    pub normal: DVec3,
    /// Depth in the hierarchy (0 for a scene patch).
    pub depth: u32,
    /// Reflectance ρ per channel.
    pub rho: [f64; 3],
    /// Current radiosity `B` per channel.
    pub radiosity: [f64; 3],
    /// Current irradiance `H = Σ_j F_ij B_j = (B − E)/ρ` per channel (the gathered light).
    pub irradiance: [f64; 3],
}

/// A candidate interaction: light gathered by the receiver `i` from the source `j`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Pair<'a> {
    /// The receiver `i`.
    pub receiver: Side<'a>,
    /// The source `j`.
    pub source: Side<'a>,
    /// Total area of the scene `A_T`.
    pub total_area: f64,
}

impl Pair<'_> {
    /// `max_c ρ_i^c B_j^c`: the receiver's reflectance times the source's radiosity.
    #[must_use]
    pub fn rho_b(&self) -> f64 {
        (0..3)
            .map(|c| self.receiver.rho[c] * self.source.radiosity[c])
            .fold(0.0, f64::max)
    }

    /// The larger element, the receiver on ties (Hanrahan and Salzman's choice).
    #[must_use]
    pub fn refine_larger(&self) -> Decision {
        if self.source.area > self.receiver.area {
            Decision::RefineSource
        } else {
            Decision::RefineReceiver
        }
    }
}

/// A refinement criterion of hierarchical radiosity.
///
/// The thresholds live in the implementations; [`Oracle::decide`] is called once per
/// candidate pair and may cast more rays through `visibility` (counted by the caller).
pub(crate) trait Oracle {
    /// A short name, e.g. `"mi"`.
    fn name(&self) -> &'static str;
    /// The decision for `pair`, given `samples` of its kernel.
    fn decide(
        &self,
        pair: &Pair<'_>,
        samples: &KernelSamples,
        visibility: &dyn Visibility,
    ) -> Decision;
}

/// Link when the value is below `epsilon`, else refine the larger element.
fn threshold(pair: &Pair<'_>, value: f64, epsilon: f64) -> Decision {
    if value < epsilon {
        Decision::Link
    } else {
        pair.refine_larger()
    }
}

/// Power-based oracle (2.48), Hanrahan, Salzman and Aupperle 1991:
///
/// ```text
/// ρ_i A_i F_ij B_j < ε,   F_ij ≈ A_j (1/N) Σ_k F(x_k, y_k)
/// ```
///
/// with the cheap form factor estimate that ignores visibility (§2.1.12).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct PowerOracle {
    /// The threshold ε (units of power).
    pub epsilon: f64,
}

impl PowerOracle {
    /// The left-hand side of (2.48).
    #[must_use]
    pub fn value(pair: &Pair<'_>, s: &KernelSamples) -> f64 {
        let f_ij = pair.source.area * s.mean_unoccluded();
        pair.rho_b() * pair.receiver.area * f_ij
    }
}

impl Oracle for PowerOracle {
    fn name(&self) -> &'static str {
        "power"
    }
    fn decide(&self, pair: &Pair<'_>, s: &KernelSamples, _: &dyn Visibility) -> Decision {
        threshold(pair, Self::value(pair, s), self.epsilon)
    }
}

/// Kernel-smoothness oracle (2.49), Teller and Hanrahan 1993:
///
/// ```text
/// ρ_i (F^max_ij − F^min_ij) A_j B_j < ε
/// ```
///
/// with `F^max`, `F^min` the largest and smallest kernel (with visibility) over the point
/// pairs.
///
/// # Where elements touch
///
/// The kernel is unbounded where two elements meet at an edge (`r → 0`), and there the
/// left-hand side does not shrink under refinement: scaling both elements by `s` scales
/// the kernel by `1/s²` and `A_j` by `s²`, so two touching elements of any size draw the
/// same values from the same canonical samples. Whenever ε lies below that value, KS
/// refines along every junction down to the smallest element allowed
/// ([`crate::hierarchy::HrOptions::min_area`]). This is the oracle as (2.49) defines it;
/// the thesis notes the effect ("unnecessary subdivisions where the kernel is unbounded",
/// §2.1.12) and bounds refinement by "a previously imposed bound on the area of the
/// patches" (§2.1.11) — the `min_area` option. The MI oracle (6.30) weights by `A_i A_j`
/// instead, which vanishes as the elements shrink.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct KernelSmoothnessOracle {
    /// The threshold ε (units of radiosity).
    pub epsilon: f64,
}

impl KernelSmoothnessOracle {
    /// The left-hand side of (2.49).
    #[must_use]
    pub fn value(pair: &Pair<'_>, s: &KernelSamples) -> f64 {
        let (lo, hi) = s.min_max();
        pair.rho_b() * (hi - lo) * pair.source.area
    }
}

impl Oracle for KernelSmoothnessOracle {
    fn name(&self) -> &'static str {
        "ks"
    }
    fn decide(&self, pair: &Pair<'_>, s: &KernelSamples, _: &dyn Visibility) -> Decision {
        threshold(pair, Self::value(pair, s), self.epsilon)
    }
}

/// Kernel-smoothness oracle about the average (2.50), Gortler et al. 1993:
///
/// ```text
/// ρ_i max(F^max_ij − F^av_ij, F^av_ij − F^min_ij) A_j B_j < ε,   F^av_ij = F_ij / A_j
/// ```
///
/// with `F^av` the mean kernel over the point pairs (2.34). This is the "KS-based" oracle
/// of the thesis' experiments (§6.4.2). Like (2.49) it does not shrink where elements
/// touch (see [`KernelSmoothnessOracle`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct KernelAverageOracle {
    /// The threshold ε (units of radiosity).
    pub epsilon: f64,
}

impl KernelAverageOracle {
    /// The left-hand side of (2.50).
    #[must_use]
    pub fn value(pair: &Pair<'_>, s: &KernelSamples) -> f64 {
        let (lo, hi) = s.min_max();
        let av = s.mean();
        let spread = (hi - av).max(av - lo).max(0.0);
        pair.rho_b() * spread * pair.source.area
    }
}

impl Oracle for KernelAverageOracle {
    fn name(&self) -> &'static str {
        "ks-av"
    }
    fn decide(&self, pair: &Pair<'_>, s: &KernelSamples, _: &dyn Visibility) -> Decision {
        threshold(pair, Self::value(pair, s), self.epsilon)
    }
}

/// MI-based oracle (6.29)–(6.30): the visibility discretisation error `δ^v_ij`, the loss of
/// information transfer between the two elements, weighted by `ρ_i B_j`:
///
/// ```text
/// ρ_i δ^v_ij B_j < ε,   estimated with N point pairs as
/// (ρ_i A_i A_j B_j / A_T) ((1/N) Σ F_k log₂ F_k − F̄ log₂ F̄) < ε,
/// F_k = F(x_k, y_k) V(x_k, y_k),   F̄ = (1/N) Σ F_k
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct MutualInformationOracle {
    /// The threshold ε (bits times units of radiosity).
    pub epsilon: f64,
}

impl MutualInformationOracle {
    /// The left-hand side of (6.30).
    #[must_use]
    pub fn value(pair: &Pair<'_>, s: &KernelSamples) -> f64 {
        pair.rho_b() * pair.receiver.area * pair.source.area / pair.total_area * s.log_spread()
    }
}

impl Oracle for MutualInformationOracle {
    fn name(&self) -> &'static str {
        "mi"
    }
    fn decide(&self, pair: &Pair<'_>, s: &KernelSamples, _: &dyn Visibility) -> Decision {
        threshold(pair, Self::value(pair, s), self.epsilon)
    }
}

/// MI-increase oracle (6.3)–(6.5), §6.2, in its three steps:
///
/// ```text
/// 1. candidate only if  B_i B_j A_i F_ij > ε₁           (the bound (6.3) on ΔI, up to 2 log m / A_T)
/// 2. split  i  if  A_i B_i H_i ≥ A_j B_j H_j, else  j   (6.4)–(6.5), H = (B − E)/ρ = Σ_j F_ij B_j
/// 3. split only if the kernel from the chosen element's four children's centres c_k to the
///    other element's centre c varies:  (max_k F_k − min_k F_k) / max_k F_k > ε₂,
///    F_k = F(c_k, c) V(c_k, c)
/// ```
///
/// `F_ij ≈ A_j (1/N) Σ F(x_k, y_k) V(x_k, y_k)`. Step 3 is the thesis' "cheap gradient
/// estimator": it casts up to four rays more. `H` is the element's gathered irradiance
/// (equal to `(B − E)/ρ` where ρ > 0, and defined where ρ = 0).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct MiIncreaseOracle {
    /// ε₁ of step 1 (units of power times radiosity).
    pub epsilon: f64,
    /// ε₂ of step 3: the relative variation of the kernel that justifies a split.
    pub gradient: f64,
}

impl MiIncreaseOracle {
    /// The default ε₂: a split must change the kernel by 10 % across the children.
    pub const DEFAULT_GRADIENT: f64 = 0.1;
}

impl Oracle for MiIncreaseOracle {
    fn name(&self) -> &'static str {
        "mi-increase"
    }
    fn decide(&self, pair: &Pair<'_>, s: &KernelSamples, vis: &dyn Visibility) -> Decision {
        let (i, j) = (&pair.receiver, &pair.source);
        // Step 1: the potential gain (6.3)
        let bb = (0..3)
            .map(|c| i.radiosity[c] * j.radiosity[c])
            .fold(0.0, f64::max);
        if !(bb * i.area * j.area * s.mean() > self.epsilon) {
            return Decision::Link;
        }
        // Step 2: the element with the larger generalised area (6.5)
        let generalised = |e: &Side<'_>| {
            (0..3)
                .map(|c| e.area * e.radiosity[c] * e.irradiance[c])
                .fold(0.0, f64::max)
        };
        let (gi, gj) = (generalised(i), generalised(j));
        let (split, other, decision) = if gi > gj || (gi == gj && i.area >= j.area) {
            (i, j, Decision::RefineReceiver)
        } else {
            (j, i, Decision::RefineSource)
        };
        // Step 3: the kernel's gradient across the split
        let centre = other.polygon.centroid();
        let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
        for child in split.polygon.split() {
            let c = child.centroid();
            let (x, nx, y, ny) = if decision == Decision::RefineReceiver {
                (c, split.normal, centre, other.normal)
            } else {
                (centre, other.normal, c, split.normal)
            };
            let mut f = point_kernel(x, nx, y, ny);
            if f > 0.0 && !vis.visible(x, y) {
                f = 0.0;
            }
            lo = lo.min(f);
            hi = hi.max(f);
        }
        if hi > 0.0 && (hi - lo) / hi > self.gradient {
            decision
        } else {
            Decision::Link
        }
    }
}

/// Regular meshing: refine, the coarser element first, until both elements are `level`
/// splits deep, so every scene patch is cut into `4^level` elements and every pair of
/// leaves gets its own link — the full-matrix solution of the regular mesh, the reference
/// the adaptive oracles are compared with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct RegularOracle {
    /// Splits per patch.
    pub level: u32,
}

impl Oracle for RegularOracle {
    fn name(&self) -> &'static str {
        "regular"
    }
    fn decide(&self, pair: &Pair<'_>, _: &KernelSamples, _: &dyn Visibility) -> Decision {
        let (di, dj) = (pair.receiver.depth, pair.source.depth);
        if di >= self.level && dj >= self.level {
            Decision::Link
        } else if di <= dj {
            Decision::RefineReceiver
        } else {
            Decision::RefineSource
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hierarchy::kernel::{NoOccluders, Surface};
    use crate::lines::chunk_rng;

    fn square(z: f64, up: bool, size: f64) -> Polygon4 {
        let v = |x: f64, y: f64| DVec3::new(x * size, y * size, z);
        let mut p = [v(0., 0.), v(1., 0.), v(1., 1.), v(0., 1.)];
        if !up {
            p.reverse();
        }
        Polygon4::new(&p).unwrap()
    }

    fn side(p: &Polygon4, up: bool, b: f64) -> Side<'_> {
        Side {
            polygon: p,
            area: p.area(),
            normal: if up { DVec3::Z } else { -DVec3::Z },
            depth: 0,
            rho: [0.5; 3],
            radiosity: [b; 3],
            irradiance: [b; 3],
        }
    }

    fn samples(r: &Side<'_>, s: &Side<'_>, n: usize) -> KernelSamples {
        KernelSamples::draw(
            Surface {
                vertices: r.polygon.vertices(),
                normal: r.normal,
            },
            Surface {
                vertices: s.polygon.vertices(),
                normal: s.normal,
            },
            n,
            &mut chunk_rng(9, 1),
            &NoOccluders,
        )
    }

    #[test]
    fn dark_sources_are_always_linked() {
        let (a, b) = (square(0.0, true, 1.0), square(0.2, false, 1.0));
        let pair = Pair {
            receiver: side(&a, true, 1.0),
            source: side(&b, false, 0.0),
            total_area: 2.0,
        };
        let s = samples(&pair.receiver, &pair.source, 10);
        let oracles: [&dyn Oracle; 5] = [
            &PowerOracle { epsilon: 1e-12 },
            &KernelSmoothnessOracle { epsilon: 1e-12 },
            &KernelAverageOracle { epsilon: 1e-12 },
            &MutualInformationOracle { epsilon: 1e-12 },
            &MiIncreaseOracle {
                epsilon: 1e-12,
                gradient: 0.0,
            },
        ];
        for o in oracles {
            assert_eq!(
                o.decide(&pair, &s, &NoOccluders),
                Decision::Link,
                "{}",
                o.name()
            );
        }
    }

    #[test]
    fn near_pairs_are_refined_and_far_ones_linked() {
        // A close pair has a steep kernel; the same squares far apart a flat one.
        let (a, near, far) = (
            square(0.0, true, 1.0),
            square(0.05, false, 1.0),
            square(50.0, false, 1.0),
        );
        let eps = 1e-3;
        let oracles: [&dyn Oracle; 4] = [
            &KernelSmoothnessOracle { epsilon: eps },
            &KernelAverageOracle { epsilon: eps },
            &MutualInformationOracle { epsilon: eps },
            &PowerOracle { epsilon: eps },
        ];
        for o in oracles {
            for (b, want_link) in [(&near, false), (&far, true)] {
                let pair = Pair {
                    receiver: side(&a, true, 1.0),
                    source: side(b, false, 1.0),
                    total_area: 2.0,
                };
                let s = samples(&pair.receiver, &pair.source, 10);
                let d = o.decide(&pair, &s, &NoOccluders);
                assert_eq!(d == Decision::Link, want_link, "{} {b:?}", o.name());
            }
        }
    }

    #[test]
    fn mi_increase_splits_the_brighter_and_needs_a_gradient() {
        // The source is shifted sideways: its children's centres see the receiver's centre
        // at different angles. (Centred squares would give four equal kernels: no gain.)
        let a = square(0.0, true, 1.0);
        let centred = square(0.3, false, 1.0);
        let v = centred.vertices();
        let shifted = [0, 1, 2, 3].map(|k| v[k] + DVec3::X * 0.5);
        let b = Polygon4::new(&shifted).unwrap();
        let mut bright = side(&b, false, 2.0);
        bright.irradiance = [3.0; 3];
        let pair = Pair {
            receiver: side(&a, true, 1.0),
            source: bright,
            total_area: 2.0,
        };
        let s = samples(&pair.receiver, &pair.source, 10);
        let o = MiIncreaseOracle {
            epsilon: 1e-6,
            gradient: 0.05,
        };
        assert_eq!(o.decide(&pair, &s, &NoOccluders), Decision::RefineSource);
        // A threshold above any relative variation never splits.
        let lazy = MiIncreaseOracle { gradient: 1.0, ..o };
        assert_eq!(lazy.decide(&pair, &s, &NoOccluders), Decision::Link);
    }

    /// A floor square and a wall square meeting at an edge, both scaled by `size`.
    fn junction(size: f64) -> (Polygon4, Polygon4) {
        let v = |x: f64, y: f64, z: f64| DVec3::new(x, y, z) * size;
        let floor = Polygon4::new(&[v(0., 0., 0.), v(1., 0., 0.), v(1., 1., 0.), v(0., 1., 0.)]);
        let wall = Polygon4::new(&[v(0., 0., 0.), v(0., 1., 0.), v(0., 1., 1.), v(0., 0., 1.)]);
        (floor.unwrap(), wall.unwrap())
    }

    #[test]
    fn kernel_smoothness_does_not_shrink_where_elements_touch() {
        // The same canonical samples at every scale: KS and KS-av give the same value at
        // 1 and at 1/1024 (only rounding differs), power and MI fall with the areas.
        let values = |size: f64| {
            let (floor, wall) = junction(size);
            let receiver = side(&floor, true, 1.0);
            let mut source = side(&wall, true, 1.0);
            source.normal = DVec3::X;
            let pair = Pair {
                receiver,
                source,
                total_area: 2.0,
            };
            let s = samples(&pair.receiver, &pair.source, 10);
            [
                KernelSmoothnessOracle::value(&pair, &s),
                KernelAverageOracle::value(&pair, &s),
                PowerOracle::value(&pair, &s),
                MutualInformationOracle::value(&pair, &s),
            ]
        };
        let (big, small) = (values(1.0), values(1.0 / 1024.0));
        for k in 0..2 {
            assert!(big[k] > 0.0);
            assert!((small[k] / big[k] - 1.0).abs() < 1e-9, "{big:?} {small:?}");
        }
        // Power scales as A_i F_ij ∝ s², and so does MI: A_i A_j ∝ s⁴ times a log spread
        // of kernels ∝ 1/s², whose log s terms cancel.
        for k in 2..4 {
            assert!((small[k] / big[k] * 1024.0 * 1024.0 - 1.0).abs() < 1e-9);
        }
    }

    #[test]
    fn regular_refines_to_its_level() {
        let (a, b) = (square(0.0, true, 1.0), square(1.0, false, 1.0));
        let mut pair = Pair {
            receiver: side(&a, true, 0.0),
            source: side(&b, false, 0.0),
            total_area: 2.0,
        };
        let s = samples(&pair.receiver, &pair.source, 1);
        let o = RegularOracle { level: 2 };
        assert_eq!(o.decide(&pair, &s, &NoOccluders), Decision::RefineReceiver);
        pair.receiver.depth = 2;
        assert_eq!(o.decide(&pair, &s, &NoOccluders), Decision::RefineSource);
        pair.source.depth = 2;
        assert_eq!(o.decide(&pair, &s, &NoOccluders), Decision::Link);
    }
}
