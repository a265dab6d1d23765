//! The point-to-point kernel and the point pairs every oracle evaluation draws.

use core::cell::Cell;
use core::f64::consts::PI;

use rand_core::Rng;

use crate::geom::DVec3;
use crate::lines::{canonical_2d, sample_polygon_point};
use crate::math;

/// Most point pairs one oracle evaluation may draw.
pub(crate) const MAX_PAIRS: usize = 64;

/// The point-to-point form factor kernel between `x` (normal `n_x`) and `y` (normal `n_y`),
/// without visibility:
///
/// ```text
/// F(x, y) = cos θ_x cos θ_y / (π r²),   cos θ_x = n_x·(y − x)/r,  cos θ_y = n_y·(x − y)/r
/// ```
///
/// (the kernel of (2.7), `∫_{A_j} F(x, y) dA_y = F_{x→j}`). Zero when either point is behind
/// the other's surface, when they coincide, or when the value is not finite (a pair closer
/// than about 10⁻⁸⁰ — a null set for random points).
#[must_use]
pub(crate) fn point_kernel(x: DVec3, n_x: DVec3, y: DVec3, n_y: DVec3) -> f64 {
    let d = y - x;
    let r2 = d.length_squared();
    let (cos_x, cos_y) = (n_x.dot(d), -n_y.dot(d));
    if !(cos_x > 0.0 && cos_y > 0.0 && r2 > 0.0) {
        return 0.0;
    }
    let f = cos_x * cos_y / (PI * r2 * r2);
    if f.is_finite() { f } else { 0.0 }
}

/// Whether two points see each other: the ray test behind the kernel `F(x, y) V(x, y)`.
pub(crate) trait Visibility {
    /// Whether the open segment from `x` to `y` meets no surface. `x` and `y` lie on
    /// surfaces themselves; those two surfaces do not count.
    fn visible(&self, x: DVec3, y: DVec3) -> bool;
    /// Whether [`Visibility::visible`] casts a ray (counted in the ray budget), or knows the
    /// answer without one.
    fn casts_rays(&self) -> bool;
}

/// A scene in which no surface can hide another (a convex enclosure): always visible, no
/// ray cast.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct NoOccluders;

impl Visibility for NoOccluders {
    fn visible(&self, _x: DVec3, _y: DVec3) -> bool {
        true
    }
    fn casts_rays(&self) -> bool {
        false
    }
}

/// Counts the rays a [`Visibility`] casts.
#[derive(Debug)]
pub(crate) struct RayCounter<'a, V: ?Sized> {
    inner: &'a V,
    rays: Cell<u64>,
}

impl<'a, V: Visibility + ?Sized> RayCounter<'a, V> {
    /// A counter at zero around `inner`.
    pub fn new(inner: &'a V) -> Self {
        Self {
            inner,
            rays: Cell::new(0),
        }
    }

    /// Rays cast so far.
    #[must_use]
    pub fn rays(&self) -> u64 {
        self.rays.get()
    }
}

impl<V: Visibility + ?Sized> Visibility for RayCounter<'_, V> {
    fn visible(&self, x: DVec3, y: DVec3) -> bool {
        if self.inner.casts_rays() {
            self.rays.set(self.rays.get() + 1);
        }
        self.inner.visible(x, y)
    }
    fn casts_rays(&self) -> bool {
        self.inner.casts_rays()
    }
}

/// One side of an element pair: the geometry the kernel needs.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Surface<'a> {
    /// Vertices, counter-clockwise about `normal`.
    pub vertices: &'a [DVec3],
    /// Unit front normal.
    pub normal: DVec3,
}

/// The kernel at `N` random point pairs `(x_k, y_k)`, `x_k` uniform on the receiver and
/// `y_k` on the source: `F(x_k, y_k)` without and with visibility.
#[derive(Clone, Copy, Debug)]
pub(crate) struct KernelSamples {
    unoccluded: [f64; MAX_PAIRS],
    visible: [f64; MAX_PAIRS],
    n: usize,
    n_visible: usize,
}

impl KernelSamples {
    /// Draws `n` pairs (clamped to `1..=``MAX_PAIRS`) from `rng`: per pair, a uniform point
    /// of the receiver then one of the source (`sample_polygon_point`), and, when the
    /// unoccluded kernel is positive, one visibility test. Needs no allocator.
    pub fn draw<R: Rng + ?Sized, V: Visibility + ?Sized>(
        receiver: Surface<'_>,
        source: Surface<'_>,
        n: usize,
        rng: &mut R,
        visibility: &V,
    ) -> Self {
        let n = n.clamp(1, MAX_PAIRS);
        let mut s = Self {
            unoccluded: [0.0; MAX_PAIRS],
            visible: [0.0; MAX_PAIRS],
            n,
            n_visible: 0,
        };
        for k in 0..n {
            let x = sample_polygon_point(receiver.vertices, canonical_2d(rng));
            let y = sample_polygon_point(source.vertices, canonical_2d(rng));
            let f = point_kernel(x, receiver.normal, y, source.normal);
            s.unoccluded[k] = f;
            if f > 0.0 && visibility.visible(x, y) {
                s.visible[k] = f;
                s.n_visible += 1;
            }
        }
        s
    }

    /// `F(x_k, y_k) V(x_k, y_k)`, the kernel with visibility.
    #[must_use]
    pub fn values(&self) -> &[f64] {
        &self.visible[..self.n]
    }

    /// `F(x_k, y_k)` without visibility (what a "cheap" estimate ignoring occlusion sees).
    #[must_use]
    pub fn unoccluded(&self) -> &[f64] {
        &self.unoccluded[..self.n]
    }

    /// Fraction of the pairs with a positive unoccluded kernel that see each other; 1 when
    /// no pair faces (nothing to hide).
    #[must_use]
    pub fn visible_fraction(&self) -> f64 {
        let facing = self.unoccluded().iter().filter(|&&f| f > 0.0).count();
        if facing == 0 {
            1.0
        } else {
            self.n_visible as f64 / facing as f64
        }
    }

    /// `(1/N) Σ F(x_k, y_k) V(x_k, y_k)`: `F_ij / A_j` by area sampling (2.34).
    #[must_use]
    pub fn mean(&self) -> f64 {
        math::sum(self.values().iter().copied()) / self.n as f64
    }

    /// The same without visibility.
    #[must_use]
    pub fn mean_unoccluded(&self) -> f64 {
        math::sum(self.unoccluded().iter().copied()) / self.n as f64
    }

    /// `min_k` and `max_k` of `F(x_k, y_k) V(x_k, y_k)`: the `F^min`, `F^max` of (2.49).
    #[must_use]
    pub fn min_max(&self) -> (f64, f64) {
        self.values()
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(lo, hi), &f| {
                (lo.min(f), hi.max(f))
            })
    }

    /// The bracket of (6.24) and (6.30), in bits per unit area:
    ///
    /// ```text
    /// (1/N) Σ F_k log₂ F_k − F̄ log₂ F̄,   F_k = F(x_k, y_k) V(x_k, y_k),  F̄ = (1/N) Σ F_k
    /// ```
    ///
    /// with `0 log 0 = 0`; `≥ 0` by convexity of `t log t` (clamped at 0 against rounding).
    #[must_use]
    pub fn log_spread(&self) -> f64 {
        let n = self.n as f64;
        let mean_f_log_f = -math::sum(self.values().iter().map(|&f| math::eta(f))) / n;
        let m = self.mean();
        (mean_f_log_f + math::eta(m)).max(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lines::chunk_rng;

    #[test]
    fn kernel_of_facing_points() {
        // Unit distance, both normals along the line: 1/π.
        let f = point_kernel(DVec3::ZERO, DVec3::Z, DVec3::Z, -DVec3::Z);
        assert!((f - 1.0 / PI).abs() < 1e-15);
        assert_eq!(point_kernel(DVec3::ZERO, DVec3::Z, DVec3::Z, DVec3::Z), 0.0);
        assert_eq!(
            point_kernel(DVec3::ZERO, DVec3::Z, DVec3::ZERO, -DVec3::Z),
            0.0
        );
    }

    #[test]
    fn mean_estimates_the_form_factor() {
        // Two facing unit squares at distance 1: F = 0.199825 (Howell C-11).
        let v = DVec3::new;
        let lower = [v(0., 0., 0.), v(1., 0., 0.), v(1., 1., 0.), v(0., 1., 0.)];
        let upper = [v(0., 0., 1.), v(0., 1., 1.), v(1., 1., 1.), v(1., 0., 1.)];
        let (r, s) = (
            Surface {
                vertices: &lower,
                normal: DVec3::Z,
            },
            Surface {
                vertices: &upper,
                normal: -DVec3::Z,
            },
        );
        let mut rng = chunk_rng(3, 0);
        let mut sum = 0.0;
        let mut sum2 = 0.0;
        let m = 2000;
        for _ in 0..m {
            let k = KernelSamples::draw(r, s, MAX_PAIRS, &mut rng, &NoOccluders);
            assert_eq!(k.visible_fraction(), 1.0);
            assert!(k.log_spread() >= 0.0);
            let (lo, hi) = k.min_max();
            assert!(lo <= k.mean() && k.mean() <= hi);
            sum += k.mean();
            sum2 += k.mean() * k.mean();
        }
        let mean = sum / m as f64;
        let se = ((sum2 / m as f64 - mean * mean) / m as f64).sqrt();
        // Within 5 standard errors of the exact value.
        assert!((mean - 0.199_825).abs() < 5.0 * se, "{mean} ± {se}");
    }

    #[test]
    fn constant_kernel_has_no_spread() {
        let mut s = KernelSamples {
            unoccluded: [0.0; MAX_PAIRS],
            visible: [0.0; MAX_PAIRS],
            n: 4,
            n_visible: 4,
        };
        s.visible[..4].copy_from_slice(&[0.3; 4]);
        assert!(s.log_spread().abs() < 1e-15);
        s.visible[0] = 0.0;
        assert!(s.log_spread() > 0.0);
    }
}
