//! The exact angular sweep around a flatland point (module docs of [`crate::field`]).

use alloc::vec::Vec;
use core::f64::consts::{LN_2, PI, TAU};

use crate::error::{Error, ErrorKind, Result};
use crate::formfactor::{FormFactors, exact_2d};
use crate::geom::{DVec2, MAX_COORDINATE, cross, left_perp, proper_crossing};
use crate::math::{self, KahanSum};
use crate::scene::Scene2;

/// Most sweep events (patch end points plus surface crossings) a scene may have for
/// [`Field2`]; each point costs `events · surfaces`.
pub(crate) const MAX_FIELD_EVENTS: usize = 1 << 17;

/// Sweep events closer than this (radians) are merged.
const MERGE_ANGLE: f64 = 1e-12;

/// Relative depth within which two surfaces met by one ray count as coincident.
const COINCIDENT: f64 = 1e-12;

/// The field of a flatland scene: the scene, its channel's stationary distribution, and the
/// crossings of its surfaces (sweep events that do not depend on the point).
#[derive(Clone, Debug)]
pub struct Field2<'a> {
    scene: &'a Scene2,
    /// `w_j` of each patch, then `w_b` (0 for a closed scene).
    weights: Vec<f64>,
    /// `L_ref = L_T + L_b`, stored units.
    l_ref: f64,
    /// Proper crossings of two surfaces, stored coordinates.
    crossings: Vec<DVec2>,
}

/// Buffers reused from point to point.
#[derive(Clone, Debug, Default)]
pub struct FieldScratch {
    events: Vec<f64>,
    angles: Vec<f64>,
}

impl FieldScratch {
    /// The visible angle `Θ_j(x)` of each patch at the last point evaluated, then the
    /// background's `Θ_b(x)` (radians; they sum to `2π`). Divide by `2π` for `p(j | x)`.
    #[must_use]
    pub fn angles(&self) -> &[f64] {
        &self.angles
    }
}

/// The measures at one point (module docs of [`crate::field`] for the definitions).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointField {
    /// `H(x)`, bits.
    pub h: f64,
    /// `I(x)`, bits; `None` when `x` sees background the scene's channel lacks.
    pub i: Option<f64>,
    /// `I^c(x)`, bits; `None` as for `i`.
    pub i_c: Option<f64>,
    /// `p(b | x)`: the fraction of directions that escape or meet a back face.
    pub background: f64,
    /// How many patches `x` sees (`Θ_j > 0`).
    pub seen: usize,
}

impl PointField {
    /// The discretisation error `δ(x) = I^c(x) − I(x)` (≥ 0 up to rounding).
    #[must_use]
    pub fn discretisation_error(&self) -> Option<f64> {
        Some(self.i_c? - self.i?)
    }
}

impl<'a> Field2<'a> {
    /// The field of `scene` with its exact channel: `w` and `L_b` from
    /// [`exact_2d::form_factors`].
    ///
    /// # Errors
    /// Those of [`exact_2d::form_factors`]; [`ErrorKind::TooLarge`] above
    /// `MAX_FIELD_EVENTS` sweep events.
    pub fn new(scene: &'a Scene2) -> Result<Self> {
        let ff = exact_2d::form_factors(scene)?;
        Self::with_channel(scene, &ff)
    }

    /// The field of `scene` with the stationary distribution of form factors computed
    /// elsewhere (exact or Monte Carlo) for the same scene.
    ///
    /// # Errors
    /// [`ErrorKind::DimensionMismatch`] if `ff` has another patch count;
    /// [`ErrorKind::TooLarge`] above `MAX_FIELD_EVENTS` sweep events.
    pub fn with_channel(scene: &'a Scene2, ff: &FormFactors) -> Result<Self> {
        let n = scene.n_patches();
        if ff.n_patches() != n {
            return Err(Error::new(ErrorKind::DimensionMismatch {
                expected: n,
                found: ff.n_patches(),
            }));
        }
        let mut weights = ff.weights().to_vec();
        if !ff.has_background() {
            weights.push(0.0);
        }
        let l_ref = scene.total_length() + ff.background_size().unwrap_or(0.0);
        // The crossings, under the event cap
        let surfaces = scene.surfaces();
        let mut events = n + surfaces.len();
        let mut crossings = Vec::new();
        for (k, s) in surfaces.iter().enumerate() {
            for t in &surfaces[k + 1..] {
                let (p, q) = (s.segment, t.segment);
                if let Some((_, c)) = proper_crossing(p.a, p.b, q.a, q.b) {
                    events += 1;
                    if events > MAX_FIELD_EVENTS {
                        return Err(Error::new(ErrorKind::TooLarge {
                            what: "field sweep events (patch ends and surface crossings)",
                            max: MAX_FIELD_EVENTS as u64,
                        }));
                    }
                    crossings.push(c);
                }
            }
        }
        if events > MAX_FIELD_EVENTS {
            return Err(Error::new(ErrorKind::TooLarge {
                what: "field sweep events (patch ends and surface crossings)",
                max: MAX_FIELD_EVENTS as u64,
            }));
        }
        Ok(Self {
            scene,
            weights,
            l_ref,
            crossings,
        })
    }

    /// The scene.
    #[must_use]
    pub fn scene(&self) -> &'a Scene2 {
        self.scene
    }

    /// The reference distribution `w_j` of the patches, then `w_b` (0 for a closed scene).
    #[must_use]
    pub fn weights(&self) -> &[f64] {
        &self.weights
    }

    /// The measures at the world point `x`; the visible angles are left in
    /// [`FieldScratch::angles`].
    ///
    /// # Errors
    /// [`ErrorKind::CoordinateRange`] for a coordinate that is not finite or beyond
    /// `1e300` (the scenes' coordinate bound).
    pub fn point(&self, x: DVec2, scratch: &mut FieldScratch) -> Result<PointField> {
        if !(x.is_finite() && x.abs().max_element() <= MAX_COORDINATE) {
            return Err(Error::new(ErrorKind::CoordinateRange));
        }
        let x = self.scene.frame().to_stored_2d(x);
        let n = self.scene.n_patches();
        scratch.angles.clear();
        scratch.angles.resize(n + 1, 0.0);
        let continuous = self.sweep(x, scratch);
        Ok(self.measures(&scratch.angles, continuous))
    }

    /// The sweep: fills `scratch.angles` and returns `Σ_arcs ∫ log₂(p(y|x) · L_ref) dθ/2π`
    /// over the arcs that meet a front face.
    fn sweep(&self, x: DVec2, scratch: &mut FieldScratch) -> f64 {
        let surfaces = self.scene.surfaces();
        // The events: directions to every patch end and every crossing
        let events = &mut scratch.events;
        events.clear();
        let dir = |p: DVec2| {
            let v = p - x;
            math::atan2(v.y, v.x)
        };
        for s in surfaces {
            if cross(s.segment.a - x, s.segment.b - x) == 0.0 {
                continue; // x on its line: it subtends no angle
            }
            events.push(dir(s.segment.a));
            events.push(dir(s.segment.b));
            for &t in &s.cuts {
                events.push(dir(s.segment.point_at(t)));
            }
        }
        events.extend(self.crossings.iter().map(|&c| dir(c)));
        let background = self.weights.len() - 1;
        if events.is_empty() {
            scratch.angles[background] = TAU;
            return 0.0;
        }
        events.sort_unstable_by(f64::total_cmp);
        // Directions to one corner computed from the two surfaces meeting there differ by
        // rounding; the sliver between them would be probed exactly through the corner,
        // where a ray may slip between the two. Merged, the corner costs at most
        // `MERGE_ANGLE` of exactness.
        events.dedup_by(|b, a| *b - *a <= MERGE_ANGLE);
        while events.len() > 1 && events[0] + TAU - events[events.len() - 1] <= MERGE_ANGLE {
            events.pop();
        }

        // Each arc between consecutive events: one surface (or none), one patch
        let mut info = KahanSum::new();
        let m = events.len();
        for k in 0..m {
            let lo = events[k];
            let hi = if k + 1 < m {
                events[k + 1]
            } else {
                events[0] + TAU
            };
            let width = hi - lo;
            if !(width > 0.0) {
                continue;
            }
            let mid = 0.5 * (lo + hi);
            let u = DVec2::new(math::cos(mid), math::sin(mid));
            match self.first_hit(x, u) {
                Some((surface, s, d)) => {
                    let surf = &surfaces[surface];
                    let idx = surf.cuts.partition_point(|&c| c < s);
                    let patch = (surf.patches.start + idx).min(surf.patches.end - 1);
                    scratch.angles[patch] += width;
                    // The arc's continuous term (module docs)
                    let foot = -left_perp(surf.segment.b - surf.segment.a);
                    let phi_mid = wrap(mid - math::atan2(foot.y, foot.x));
                    let half = 0.5 * PI;
                    let phi0 = (phi_mid - 0.5 * width).clamp(-half, half);
                    let phi1 = (phi_mid + 0.5 * width).clamp(-half, half);
                    let k_over_d = self.l_ref / (TAU * d);
                    let term = width * math::log2(k_over_d)
                        + 2.0 / LN_2 * (log_cos_integral(phi1) - log_cos_integral(phi0));
                    info.add(term / TAU);
                }
                None => scratch.angles[background] += width,
            }
        }
        info.total()
    }

    /// The front face the ray `x + t u` meets first: `(surface, parameter along it,
    /// distance from x to its line)`, or `None` if it escapes or meets a back face first.
    fn first_hit(&self, x: DVec2, u: DVec2) -> Option<(usize, f64, f64)> {
        // (surface, s, t, distance to its line — positive on its front side, the rounding
        // scale of t)
        let mut best: Option<(usize, f64, f64, f64, f64)> = None;
        for (k, surf) in self.scene.surfaces().iter().enumerate() {
            let (a, b) = (surf.segment.a, surf.segment.b);
            let e = b - a;
            let denom = cross(u, e);
            if denom == 0.0 {
                continue;
            }
            let ax = a - x;
            let t = cross(ax, e) / denom;
            let s = cross(ax, u) / denom;
            if !(t > 0.0 && (0.0..=1.0).contains(&s)) {
                continue;
            }
            let d = cross(e, x - a) / math::length(e);
            // t's rounding follows the products in cross(ax, e), not t itself: a point
            // 4e-6 from a wall 0.36 long has t ~ 1e-5 with rounding ~ 1e-17 (≫ 1e-12 t)
            let scale = (ax.abs().max_element() * e.abs().max_element() / denom.abs()).max(t);
            let better = match best {
                None => true,
                // Coincident opposite surfaces (a two-sided wall) meet the ray at the same
                // depth up to rounding: the one facing x is the one seen
                Some((_, _, bt, bd, bscale))
                    if (t - bt).abs() <= COINCIDENT * scale.max(bscale) =>
                {
                    d > 0.0 && !(bd > 0.0)
                }
                Some((_, _, bt, _, _)) => t < bt,
            };
            if better {
                best = Some((k, s, t, d, scale));
            }
        }
        let (k, s, _, d, _) = best?;
        (d > 0.0).then_some((k, s, d))
    }

    fn measures(&self, angles: &[f64], continuous: f64) -> PointField {
        let mut h = KahanSum::new();
        let mut i = KahanSum::new();
        let mut seen = 0;
        let mut defined = true;
        let last = angles.len() - 1;
        for (j, (&theta, &w)) in angles.iter().zip(&self.weights).enumerate() {
            let p = theta / TAU;
            if !(p > 0.0) {
                continue;
            }
            if j < last {
                seen += 1;
            }
            h.add(math::eta(p));
            if w > 0.0 {
                i.add(p * math::log2_ratio(p, w));
            } else {
                defined = false;
            }
        }
        let p_b = angles[last] / TAU;
        let background_term = if p_b > 0.0 && self.weights[last] > 0.0 {
            p_b * math::log2_ratio(p_b, self.weights[last])
        } else {
            0.0
        };
        let h = h.total();
        PointField {
            // A single term of η(1) may round to −0
            h: if h > 0.0 { h } else { 0.0 },
            i: defined.then(|| i.total()),
            i_c: defined.then_some(continuous + background_term),
            background: p_b,
            seen,
        }
    }
}

/// `G(φ) = ∫₀^φ ln cos t dt = ½ Cl₂(π − 2φ) − φ ln 2` for `|φ| ≤ π/2`.
fn log_cos_integral(phi: f64) -> f64 {
    0.5 * math::clausen2(PI - 2.0 * phi) - phi * LN_2
}

/// An angle brought into `(−π, π]`.
fn wrap(a: f64) -> f64 {
    let mut a = a % TAU;
    if a > PI {
        a -= TAU;
    } else if a <= -PI {
        a += TAU;
    }
    a
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Scene2;

    fn point(scene: &Scene2, x: DVec2) -> (PointField, Vec<f64>) {
        let field = Field2::new(scene).unwrap();
        let mut scratch = FieldScratch::default();
        let f = field.point(x, &mut scratch).unwrap();
        (f, scratch.angles().to_vec())
    }

    #[test]
    fn centre_of_a_regular_polygon_sees_every_patch_alike() {
        for (sides, per_side) in [(3, 1), (4, 1), (6, 1), (5, 1)] {
            let scene = Scene2::regular_polygon(sides, per_side).unwrap();
            let (lo, hi) = scene.bounds();
            let c: DVec2 = scene
                .patches()
                .iter()
                .map(|p| p.segment.midpoint())
                .sum::<DVec2>()
                / scene.n_patches() as f64;
            let c = scene.frame().to_world_2d(c);
            let _ = (lo, hi);
            let (f, angles) = point(&scene, c);
            let n = scene.n_patches();
            for a in &angles[..n] {
                assert!((a - TAU / n as f64).abs() < 1e-12, "{a}");
            }
            assert!((f.h - (n as f64).log2()).abs() < 1e-12);
            // w_j = 1/n = p(j|x): no information, discretely
            assert!(f.i.unwrap().abs() < 1e-12);
            assert!(f.discretisation_error().unwrap() >= -1e-12);
            assert_eq!(f.seen, n);
        }
    }

    #[test]
    fn square_room_angles_follow_atan() {
        let scene = Scene2::rectangle(1.0, 1.0, 1).unwrap();
        let x = DVec2::new(0.25, 0.5);
        let (_, angles) = point(&scene, scene.frame().to_world_2d(x));
        // The wall x = 0 at distance 0.25 spans 2 atan(0.5/0.25); x = 1 at 0.75
        let near = 2.0 * (0.5f64 / 0.25).atan();
        let far = 2.0 * (0.5f64 / 0.75).atan();
        let mut sorted: Vec<f64> = angles[..4].to_vec();
        sorted.sort_by(f64::total_cmp);
        let side = (TAU - near - far) / 2.0;
        let mut want = [near, far, side, side];
        want.sort_by(f64::total_cmp);
        for (a, b) in sorted.iter().zip(want) {
            assert!((a - b).abs() < 1e-12, "{a} {b}");
        }
    }

    #[test]
    fn continuous_term_matches_a_quadrature() {
        let scene = Scene2::rectangle(2.0, 1.0, 3).unwrap();
        let x = scene.frame().to_world_2d(DVec2::new(0.3, 0.2));
        let field = Field2::new(&scene).unwrap();
        let mut scratch = FieldScratch::default();
        let f = field.point(x, &mut scratch).unwrap();
        // Midpoint rule over directions: log2(L_T cos θ_y / (2π r))
        let xs = scene.frame().to_stored_2d(x);
        let samples = 200_000;
        let mut sum = 0.0;
        for k in 0..samples {
            let th = (k as f64 + 0.5) / samples as f64 * TAU;
            let u = DVec2::new(th.cos(), th.sin());
            let (surf, _, d) = field.first_hit(xs, u).unwrap();
            let seg = scene.surfaces()[surf].segment;
            let cos_y = -u.dot(seg.normal().normalize());
            let r = d / cos_y;
            sum += (scene.total_length() * cos_y / (TAU * r)).log2();
        }
        let quad = sum / samples as f64;
        // The midpoint rule's error is O(h log h) at the grazing corners (log cos θ_y):
        // 7.6e-6 at this step, 2.5e-7 at a quarter of it (measured)
        assert!((quad - f.i_c.unwrap()).abs() < 2e-5, "{quad} {:?}", f.i_c);
        assert!(f.discretisation_error().unwrap() > 0.0);
    }

    #[test]
    fn centre_of_a_square_has_the_closed_form_continuous_term() {
        // Side 2, L_T = 8, each wall at d = 1 seen over φ ∈ [−π/4, π/4]:
        // I^c = (2/π) [(π/2) log₂(8/2π) + (4/ln 2) G(π/4)], G(π/4) = ½ G_cat − (π/4) ln 2
        let scene = Scene2::rectangle(2.0, 2.0, 1).unwrap();
        let (f, _) = point(&scene, DVec2::new(1.0, 1.0));
        let catalan = 0.915_965_594_177_219;
        let g = 0.5 * catalan - 0.25 * PI * LN_2;
        let want = 2.0 / PI * (0.5 * PI * (8.0 / TAU).log2() + 4.0 / LN_2 * g);
        assert!((f.i_c.unwrap() - want).abs() < 1e-14, "{:?} {want}", f.i_c);
        assert!((want - 0.031_038).abs() < 1e-6);
    }

    #[test]
    fn outside_a_closed_room_information_is_undefined() {
        let scene = Scene2::rectangle(1.0, 1.0, 2).unwrap();
        let (f, _) = point(&scene, DVec2::new(5.0, 5.0));
        assert_eq!(f.background, 1.0);
        assert_eq!((f.i, f.i_c), (None, None));
        assert_eq!(f.h, 0.0);
    }

    #[test]
    fn bad_points_are_refused() {
        let scene = Scene2::rectangle(1.0, 1.0, 2).unwrap();
        let field = Field2::new(&scene).unwrap();
        let mut scratch = FieldScratch::default();
        for x in [f64::NAN, f64::INFINITY, 1e301] {
            assert!(field.point(DVec2::new(x, 0.5), &mut scratch).is_err());
        }
    }

    /// A point 3.8e-6 from a two-sided wall inside a closed room (a case the property test
    /// `bounds_hold_at_any_interior_point` found): the two coincident faces meet each ray
    /// at depths ~1e-5 that differ by rounding of the wall's coordinates (~1e-17, above
    /// 1e-12 of the depth), and the nearer-by-rounding back face hid the wall: half the
    /// view went to the background and `I(x)` was undefined.
    #[test]
    fn a_point_beside_a_two_sided_wall_sees_its_front_face() {
        let corners = [
            (2.167_629_048_670_986_6, 0.217_431_126_369_032_33),
            (1.421_450_635_728_663_8, 0.517_558_798_571_287_1),
            (-1.437_519_421_027_632_3, 0.513_890_146_183_343_6),
            (-1.839_575_404_015_838_3, 0.394_406_181_885_606_83),
            (-2.228_417_697_130_081, -0.158_949_542_803_204_06),
            (-1.491_268_472_318_034_5, -0.501_115_409_747_426_9),
            (1.236_821_202_232_158_5, -0.555_241_588_596_624_4),
            (2.234_806_799_356_858_3, -0.151_380_760_257_320_36),
        ]
        .map(|(x, y)| DVec2::new(x, y));
        let mut b = Scene2::builder();
        for k in 0..8 {
            b.segment(corners[k], corners[(k + 1) % 8], 1).unwrap();
        }
        let a = DVec2::new(-0.493_700_044_460_098_85, 0.012_105_067_467_738_331);
        let e = DVec2::new(-0.160_701_979_644_813_17, 0.138_847_810_198_991_76);
        b.segment(a, e, 3).unwrap();
        b.segment(e, a, 3).unwrap();
        let scene = b.build().unwrap();
        let x = DVec2::new(-0.466_583_900_495_016_63, 0.022_421_668_599_702_1);
        let (f, angles) = point(&scene, x);
        assert_eq!(f.background, 0.0, "{angles:?}");
        let total: f64 = angles.iter().sum();
        assert!((total - TAU).abs() < 1e-12);
        // The wall's near face subtends π less the two angles past its ends
        let along = (e - a).normalize();
        let (ta, tb) = ((x - a).dot(along), (e - x).dot(along));
        let d = cross(along, x - a).abs();
        let want = PI - libm::atan(d / ta) - libm::atan(d / tb);
        let wall: f64 = angles[8..14].iter().sum();
        assert!((wall - want).abs() < 1e-9, "{wall} vs {want}");
        assert!(f.i.unwrap() >= -1e-12 && f.discretisation_error().unwrap() >= -1e-12);
    }
}
