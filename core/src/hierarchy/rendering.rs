//! Gouraud-shaded pictures of a hierarchy's leaves from a pinhole camera, and their
//! image-space error against a reference's (issue 22: the thesis judges its meshes by such
//! pictures, Figs. 6.6–6.11).
//!
//! # The picture
//!
//! A [`Camera3`] (the crate's one pinhole camera) samples each pixel once, at its centre,
//! along [`Camera3::direction`]. The first hit on a patch's *front*
//! is found through the scene's BVH (back faces are passed through, as a renderer culls
//! them: the Cornell box is seen through its front wall); the pixel's value is the Gouraud
//! radiosity of the leaf holding the hit point — the crate's one Gouraud shading
//! ([`crate::image`]): vertex radiosities welded by its rule, interpolated linearly over the
//! triangle of the leaf's fan `(v₀, v_k, v_{k+1})` that holds the point. That is what
//! [`crate::image::Picture3`] draws for the same fan, up to its coverage of pixel centres.
//!
//! # The error
//!
//! Both pictures are tone-mapped by the *reference's* [`ToneMap::for_scene`] (white at its
//! brightest non-emitting leaf, then sRGB) to display levels `0..=255`, and
//!
//! ```text
//! RMSE = √( (1/3P) Σ_pixels Σ_channels (c_mesh − c_ref)² )
//! ```
//!
//! over the `P` pixels that show the scene in the reference. The *boundary* RMSE is the same
//! sum over the pixels where the reference picture changes most — the given fraction of
//! them with the largest `max over 4-neighbours and channels |c_p − c_q|`: shadow and
//! penumbra edges, corners, the light's rim; what the thesis points at in its figures.

use alloc::vec;
use alloc::vec::Vec;

use crate::accel::Bvh3;
use crate::error::{ErrorKind, Result};
use crate::geom::{self, DVec3};
use crate::hierarchy::element::Polygon4;
use crate::hierarchy::monte_carlo::McHierarchy;
use crate::hierarchy::tree::Hierarchy;
use crate::image::{Camera3, ShadedPolygon, ToneMap, gouraud, interpolate};
use crate::math;
use crate::scene::{Material, Scene3};

/// Largest picture side in pixels.
pub(crate) const MAX_IMAGE_SIDE: u32 = 4096;

/// Back faces a pixel's ray passes through before it gives up (shows nothing).
const MAX_BACK_FACES: usize = 16;

/// One leaf to draw: the scene patch it lies on, its shape, and what the shaded polygon it
/// becomes needs.
#[derive(Clone, Copy, Debug)]
pub struct LeafShade<'a> {
    /// The scene patch.
    pub patch: u32,
    /// Its shape.
    pub polygon: &'a Polygon4,
    /// Unit front normal.
    pub normal: DVec3,
    /// Area.
    pub area: f64,
    /// Radiosity.
    pub radiosity: [f64; 3],
    /// Material (reflectance, emittance).
    pub material: Material,
}

impl Hierarchy {
    /// The leaves as `LeafShade`s, in [`Hierarchy::leaves`] order.
    #[must_use]
    pub fn shaded_leaves(&self) -> Vec<LeafShade<'_>> {
        self.leaves()
            .map(|e| LeafShade {
                patch: e.patch,
                polygon: &e.polygon,
                normal: e.normal,
                area: e.area,
                radiosity: e.radiosity,
                material: Material {
                    reflectance: e.rho,
                    emittance: e.emission,
                },
            })
            .collect()
    }
}

impl McHierarchy {
    /// The leaves as `LeafShade`s, in element order.
    #[must_use]
    pub fn shaded_leaves(&self) -> Vec<LeafShade<'_>> {
        self.elements()
            .iter()
            .filter(|e| e.is_leaf())
            .map(|e| LeafShade {
                patch: e.patch,
                polygon: &e.polygon,
                normal: e.normal,
                area: e.area,
                radiosity: e.radiosity,
                material: Material {
                    reflectance: e.rho,
                    emittance: e.emission,
                },
            })
            .collect()
    }
}

/// The Gouraud vertex radiosities of `leaves` (`gouraud`): per leaf, per vertex.
#[must_use]
pub(crate) fn leaf_vertex_radiosities(leaves: &[LeafShade<'_>]) -> Vec<[[f64; 3]; 4]> {
    let polygons: Vec<ShadedPolygon<'_>> = leaves
        .iter()
        .map(|l| ShadedPolygon {
            vertices: l.polygon.vertices(),
            normal: l.normal,
            area: l.area,
            radiosity: l.radiosity,
            material: l.material,
        })
        .collect();
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for v in polygons.iter().flat_map(|p| p.vertices) {
        lo = lo.min(*v);
        hi = hi.max(*v);
    }
    let mesh = gouraud(&polygons, (lo, hi));
    mesh.faces
        .iter()
        .map(|face| {
            let mut out = [[0.0; 3]; 4];
            for (o, &v) in out.iter_mut().zip(face) {
                *o = mesh.vertex_radiosity[v];
            }
            out
        })
        .collect()
}

/// A picture: per pixel (row-major, top row first) the linear radiosity seen, `None` where
/// no front face is hit.
#[derive(Clone, Debug, PartialEq)]
pub struct GouraudImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// The pixels.
    pub pixels: Vec<Option<[f64; 3]>>,
}

impl GouraudImage {
    /// The picture as 8-bit sRGB through `tone` (`background` where nothing is seen).
    #[must_use]
    pub fn to_rgb8(&self, tone: &ToneMap, background: [u8; 3]) -> Vec<u8> {
        self.pixels
            .iter()
            .flat_map(|p| p.map_or(background, |b| tone.rgb(b)))
            .collect()
    }
}

/// The Gouraud-shaded picture of `leaves` (leaves of a hierarchy over `scene`'s patches)
/// seen from `view` (module docs).
///
/// # Errors
/// [`ErrorKind::TooLarge`] for a side above `MAX_IMAGE_SIDE`; those of [`Bvh3::build`].
pub fn render_gouraud(
    scene: &Scene3,
    leaves: &[LeafShade<'_>],
    view: &Camera3,
) -> Result<GouraudImage> {
    let (width, height) = view.size();
    if width > MAX_IMAGE_SIDE || height > MAX_IMAGE_SIDE {
        return Err(ErrorKind::TooLarge {
            what: "picture side (1 to the maximum)",
            max: u64::from(MAX_IMAGE_SIDE),
        }
        .into());
    }
    let polygons: Vec<(usize, usize)> =
        scene.patches().iter().map(|p| (p.first, p.count)).collect();
    let bvh = Bvh3::build(scene.points(), &polygons)?;
    let t_min = 1e-9 * geom::bounds_diagonal(scene.points());
    // The leaves of each patch
    let mut by_patch: Vec<Vec<u32>> = vec![Vec::new(); scene.n_patches()];
    for (k, l) in leaves.iter().enumerate() {
        if let Some(list) = by_patch.get_mut(l.patch as usize) {
            list.push(k as u32);
        }
    }
    let vertex = leaf_vertex_radiosities(leaves);
    let (w, h) = (width as usize, height as usize);
    let mut pixels = vec![None; w * h];
    for (k, px) in pixels.iter_mut().enumerate() {
        let dir = view.direction((k % w) as u32, (k / w) as u32, [0.5, 0.5]);
        let mut origin = view.eye();
        for _ in 0..MAX_BACK_FACES {
            let Some(hit) = bvh.first_hit(origin, dir, t_min) else {
                break;
            };
            let q = hit.prim as usize;
            let p = origin + dir * hit.t;
            if scene.patches()[q].normal.dot(dir) >= 0.0 {
                origin = p;
                continue;
            }
            *px = by_patch
                .get(q)
                .and_then(|list| leaf_holding(leaves, list, p))
                .map(|l| {
                    interpolate(
                        leaves[l].polygon.vertices(),
                        &vertex[l][..],
                        p,
                        leaves[l].normal,
                    )
                });
            break;
        }
    }
    Ok(GouraudImage {
        width,
        height,
        pixels,
    })
}

/// The leaf among `list` holding `p` (the one with the nearest centroid when rounding
/// leaves it in none).
fn leaf_holding(leaves: &[LeafShade<'_>], list: &[u32], p: DVec3) -> Option<usize> {
    list.iter()
        .map(|&k| k as usize)
        .find(|&k| leaves[k].polygon.contains(p, leaves[k].normal, 1e-6))
        .or_else(|| {
            list.iter().map(|&k| k as usize).min_by(|&a, &b| {
                let d = |k: usize| (leaves[k].polygon.centroid() - p).length_squared();
                d(a).total_cmp(&d(b))
            })
        })
}

/// A reference picture, tone-mapped, and its boundary pixels (module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct ImageReference {
    /// The view.
    pub view: Camera3,
    /// The tone map of every picture compared with it (the reference's).
    pub tone: ToneMap,
    /// Display levels of the reference, per pixel; `None` where nothing is seen.
    levels: Vec<Option<[u8; 3]>>,
    /// Whether each pixel is a boundary pixel.
    boundary: Vec<bool>,
}

/// Image-space errors of a picture against an `ImageReference`, in display levels
/// (`0..=255`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImageError {
    /// RMSE over the pixels showing the scene.
    pub rmse: f64,
    /// RMSE over the boundary pixels.
    pub boundary_rmse: f64,
}

impl ImageReference {
    /// The reference picture of `leaves` from `view`, tone-mapped by its own
    /// [`ToneMap::for_scene`], with the `boundary_fraction` of its pixels where it changes
    /// most marked as boundary pixels.
    ///
    /// # Errors
    /// Those of [`render_gouraud`]; [`ErrorKind::EmptyScene`] when the view shows nothing.
    pub fn new(
        scene: &Scene3,
        leaves: &[LeafShade<'_>],
        view: &Camera3,
        boundary_fraction: f64,
    ) -> Result<Self> {
        let image = render_gouraud(scene, leaves, view)?;
        let (radiosity, materials): (Vec<[f64; 3]>, Vec<Material>) =
            leaves.iter().map(|l| (l.radiosity, l.material)).unzip();
        let tone = ToneMap::for_scene(&radiosity, &materials);
        let levels: Vec<Option<[u8; 3]>> = image
            .pixels
            .iter()
            .map(|p| p.map(|b| tone.rgb(b)))
            .collect();
        let (w, h) = (view.size().0 as usize, view.size().1 as usize);
        let mut scored: Vec<(u32, usize)> = Vec::new();
        for (k, c) in levels.iter().enumerate() {
            let Some(c) = c else { continue };
            let (x, y) = (k % w, k / w);
            let mut s = 0u32;
            let mut visit = |q: usize| {
                if let Some(Some(d)) = levels.get(q) {
                    for ch in 0..3 {
                        s = s.max(u32::from(c[ch].abs_diff(d[ch])));
                    }
                }
            };
            if x > 0 {
                visit(k - 1);
            }
            if x + 1 < w {
                visit(k + 1);
            }
            if y > 0 {
                visit(k - w);
            }
            if y + 1 < h {
                visit(k + w);
            }
            scored.push((s, k));
        }
        if scored.is_empty() {
            return Err(ErrorKind::EmptyScene.into());
        }
        scored.sort_by(|a, b| b.cmp(a));
        let keep = ((scored.len() as f64 * boundary_fraction.clamp(0.0, 1.0)) as usize)
            .clamp(1, scored.len());
        let mut boundary = vec![false; levels.len()];
        for &(_, k) in &scored[..keep] {
            boundary[k] = true;
        }
        Ok(Self {
            view: *view,
            tone,
            levels,
            boundary,
        })
    }

    /// The same view, tone map and edge pixels with the picture of `leaves` instead: one
    /// of the independent solves a mean reference averages, so that a mesh's image errors
    /// against each solve are measured on the same pixels and levels as against the mean
    /// (`McReference::with_halves`).
    ///
    /// # Errors
    /// Those of [`render_gouraud`].
    pub(crate) fn with_picture_of(&self, scene: &Scene3, leaves: &[LeafShade<'_>]) -> Result<Self> {
        let image = render_gouraud(scene, leaves, &self.view)?;
        Ok(Self {
            view: self.view,
            tone: self.tone,
            levels: image
                .pixels
                .iter()
                .map(|p| p.map(|b| self.tone.rgb(b)))
                .collect(),
            boundary: self.boundary.clone(),
        })
    }

    /// The errors of `leaves`' picture from the same view (module docs); a pixel the mesh
    /// shows as nothing counts as black.
    ///
    /// # Errors
    /// Those of [`render_gouraud`].
    pub fn error(&self, scene: &Scene3, leaves: &[LeafShade<'_>]) -> Result<ImageError> {
        let image = render_gouraud(scene, leaves, &self.view)?;
        let (mut all, mut n_all, mut edge, mut n_edge) = (0.0, 0u64, 0.0, 0u64);
        for ((r, m), &b) in self.levels.iter().zip(&image.pixels).zip(&self.boundary) {
            let Some(r) = r else { continue };
            let c = m.map_or([0; 3], |m| self.tone.rgb(m));
            let d2: f64 = (0..3)
                .map(|ch| {
                    let d = f64::from(c[ch]) - f64::from(r[ch]);
                    d * d
                })
                .sum();
            all += d2;
            n_all += 3;
            if b {
                edge += d2;
                n_edge += 3;
            }
        }
        let rms = |s: f64, n: u64| if n > 0 { math::sqrt(s / n as f64) } else { 0.0 };
        Ok(ImageError {
            rmse: rms(all, n_all),
            boundary_rmse: rms(edge, n_edge),
        })
    }
}

#[cfg(all(test, feature = "std"))]
mod tests {
    use super::*;
    use crate::hierarchy::monte_carlo::{McOptions, McOracle};

    fn cornell() -> Scene3 {
        Scene3::cornell_box(false, 1).unwrap()
    }

    /// A picture of a mesh against itself has no error; the framing view sees the box
    /// through its front wall (most pixels show the scene); a picture too large is a typed
    /// error.
    #[test]
    fn a_mesh_against_itself_has_no_image_error() {
        let scene = cornell();
        let o = McOptions {
            rays: 3000,
            ..McOptions::default()
        };
        let mc = McHierarchy::solve(&scene, McOracle::Power(1e9), &o).unwrap();
        let leaves = mc.shaded_leaves();
        let view = Camera3::framing(scene.bounds(), 40.0, (48, 40)).unwrap();
        let r = ImageReference::new(&scene, &leaves, &view, 0.1).unwrap();
        let shown = r.levels.iter().filter(|p| p.is_some()).count();
        assert!(shown > 48 * 40 / 2, "{shown}");
        assert_eq!(r.boundary.iter().filter(|&&b| b).count(), shown / 10);
        let e = r.error(&scene, &leaves).unwrap();
        assert_eq!(e.rmse, 0.0);
        assert_eq!(e.boundary_rmse, 0.0);
        let large = Camera3::framing(scene.bounds(), 40.0, (MAX_IMAGE_SIDE + 1, 8)).unwrap();
        assert!(render_gouraud(&scene, &leaves, &large).is_err());
    }

    /// Gouraud interpolation reproduces a linear field exactly: on a quad whose vertex
    /// values are `a + g·v`, the value at any inside point is `a + g·p`.
    #[test]
    fn interpolation_is_exact_for_linear_fields() {
        let v = DVec3::new;
        let quad = [v(0., 0., 0.), v(2., 0., 0.), v(2., 1., 0.), v(0., 1., 0.)];
        let f = |p: DVec3| 1.0 + 0.5 * p.x - 0.25 * p.y;
        let b = [
            [f(quad[0]); 3],
            [f(quad[1]); 3],
            [f(quad[2]); 3],
            [f(quad[3]); 3],
        ];
        for p in [
            v(0.3, 0.2, 0.),
            v(1.7, 0.9, 0.),
            v(1.0, 0.5, 0.),
            v(2.0, 0.0, 0.),
        ] {
            let got = interpolate(&quad, &b[..], p, DVec3::Z);
            assert!((got[0] - f(p)).abs() < 1e-12, "{p} {got:?}");
        }
    }
}
