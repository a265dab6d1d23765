//! The 3D scene: planar convex polygons ("faces") cut into patches (thesis §2.1.3).
//!
//! A face is a polygon as drawn (an OBJ `f` line); a patch is a piece of a face, a state of
//! the Markov chain. Every patch of a face lies in the face's plane and shares its normal, so
//! patches of one face never see each other.
//!
//! Orientation (DESIGN.md): a face is seen from the side where its vertices run
//! counter-clockwise (right-hand rule), as in OBJ. Its unit normal points to that side.

use alloc::collections::BTreeMap;
use alloc::string::String;
use alloc::vec::Vec;
use core::ops::Range;

use crate::error::{ErrorKind, Result};
use crate::geom::{self, DVec3, MAX_COORDINATE};
use crate::math::KahanSum;
use crate::scene::{Frame, Material};

/// Most patches a 3D scene may hold (a cap checked before allocating).
pub(crate) const MAX_PATCHES_3D: usize = 4_000_000;

/// Most vertices one face may have.
pub(crate) const MAX_FACE_VERTICES: usize = 256;

/// Largest `k` of [`Subdivision::Grid`] (`k² = 4,000,000` patches, the scene cap).
pub(crate) const MAX_GRID: u32 = 2_000;

/// Largest level of [`Subdivision::Triangles`] (`4¹⁰ ≈ 10⁶` triangles per triangle).
pub(crate) const MAX_TRIANGLE_LEVEL: u32 = 10;

/// Largest distance of a vertex from a face's plane, relative to the face's size (the
/// diagonal of its bounding box).
pub(crate) const PLANARITY_TOLERANCE: f64 = 1e-6;

/// Most negative sine of a turn still accepted as convex; turns smaller than it (in radians)
/// count as straight, and such vertices are skipped when a face is triangulated.
pub(crate) const CONVEXITY_TOLERANCE: f64 = 1e-6;

/// Smallest area accepted, relative to the square of a face's size; also the smallest edge
/// relative to its size.
const DEGENERACY_TOLERANCE: f64 = 1e-12;

/// How each face is cut into patches.
///
/// Every variant keeps the patches convex and planar, and their areas add up to the face's.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Subdivision {
    /// One patch per face: the face itself.
    None,
    /// `Grid(k)`: a quad is cut into `k × k` quads along the lines of its bilinear
    /// parameterisation (straight lines for a planar convex quad, so every cell is a convex
    /// quad); a triangle into `k²` triangles on a regular barycentric grid; a larger polygon
    /// is first fanned into triangles, each cut likewise. `1 ≤ k ≤` `MAX_GRID`.
    Grid(u32),
    /// `Triangles(l)`: the face is fanned into triangles (a quad into 2) and each triangle is
    /// cut `l` times at its edge midpoints, giving `4^l` triangles per triangle.
    /// `0 ≤ l ≤` `MAX_TRIANGLE_LEVEL`.
    Triangles(u32),
}

impl Subdivision {
    /// Checks the parameter's range.
    ///
    /// # Errors
    /// [`ErrorKind::BadSubdivision`] for `Grid(0)`, `Grid(k > MAX_GRID)` or
    /// `Triangles(l > MAX_TRIANGLE_LEVEL)`.
    pub fn validate(self) -> Result<()> {
        match self {
            Self::None => Ok(()),
            Self::Grid(k) if (1..=MAX_GRID).contains(&k) => Ok(()),
            Self::Grid(k) => Err(ErrorKind::BadSubdivision {
                given: u64::from(k),
                max: u64::from(MAX_GRID),
            }
            .into()),
            Self::Triangles(l) if l <= MAX_TRIANGLE_LEVEL => Ok(()),
            Self::Triangles(l) => Err(ErrorKind::BadSubdivision {
                given: u64::from(l),
                max: u64::from(MAX_TRIANGLE_LEVEL),
            }
            .into()),
        }
    }

    /// Patches of a face of `n` vertices, `corners` of them not straight (`3 ≤ corners ≤ n`).
    fn patch_count(self, n: usize, corners: usize) -> u64 {
        let fan = corners.saturating_sub(2) as u64;
        match self {
            Self::None => 1,
            Self::Grid(k) if n == 4 => u64::from(k) * u64::from(k),
            Self::Grid(k) => fan * u64::from(k) * u64::from(k),
            Self::Triangles(l) => fan << (2 * l),
        }
    }
}

/// A patch: a planar convex piece of a face, one state of the scene's Markov chain.
#[derive(Clone, Debug, PartialEq)]
pub struct Patch3 {
    /// Index of the patch's first vertex in the scene's points ([`Scene3::patch_vertices`]).
    pub first: usize,
    /// Number of vertices (3 or 4 for a subdivided face).
    pub count: usize,
    /// Index of the face it was cut from.
    pub face: usize,
    /// Index into [`Scene3::materials`].
    pub material: usize,
    /// Unit normal of the front side: the face's normal.
    pub normal: DVec3,
    /// Area `A_i > 0`.
    pub area: f64,
    /// Area centroid.
    pub centroid: DVec3,
}

/// A face: a planar convex polygon as drawn, cut into patches.
#[derive(Clone, Debug, PartialEq)]
pub struct Face3 {
    /// Index of the face's first vertex in the scene's points ([`Scene3::face_vertices`]).
    pub first: usize,
    /// Number of vertices, 3 to `MAX_FACE_VERTICES`.
    pub count: usize,
    /// Index into [`Scene3::materials`].
    pub material: usize,
    /// Unit normal of the front side (right-hand rule), by Newell's method.
    pub normal: DVec3,
    /// Area.
    pub area: f64,
    /// The indices of its patches in [`Scene3::patches`].
    pub patches: Range<usize>,
    /// Index into [`Scene3::objects`].
    pub object: usize,
}

/// A 3D scene: faces, their patches, materials and object names.
///
/// Built with [`Scene3::builder`] or the OBJ parser ([`crate::io::parse_obj`]); every
/// constructor validates, so a `Scene3` always has at least one patch, finite coordinates
/// within `MAX_COORDINATE`, planar convex faces of positive area and patches of positive
/// area. Materials and objects are listed in order of first use, each once.
///
/// Points, normals' positions, areas and bounds are **stored** ones: the given coordinates
/// moved and scaled exactly into the scene's [`Frame`] ([`Scene3::frame`]; the identity for a
/// scene of ordinary size near the origin), so no computation depends on the units or the
/// position the scene was given in. [`Frame::to_world`] gives back the given coordinates
/// bit for bit.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene3 {
    points: Vec<DVec3>,
    patches: Vec<Patch3>,
    faces: Vec<Face3>,
    materials: Vec<Material>,
    objects: Vec<String>,
    total_area: f64,
    frame: Frame,
}

impl Scene3 {
    /// A builder for a scene.
    #[must_use]
    pub fn builder() -> Scene3Builder {
        Scene3Builder::default()
    }

    /// The patches (states).
    #[must_use]
    pub fn patches(&self) -> &[Patch3] {
        &self.patches
    }

    /// The faces (polygons as drawn).
    #[must_use]
    pub fn faces(&self) -> &[Face3] {
        &self.faces
    }

    /// The materials referenced by faces and patches.
    #[must_use]
    pub fn materials(&self) -> &[Material] {
        &self.materials
    }

    /// The object names referenced by faces (OBJ `o`/`g`; `"default"` before any).
    #[must_use]
    pub fn objects(&self) -> &[String] {
        &self.objects
    }

    /// All vertices: each face's, followed by its patches' (a face of one patch shares its
    /// vertices with it).
    #[must_use]
    pub fn points(&self) -> &[DVec3] {
        &self.points
    }

    /// Number of patches `n_p`.
    #[must_use]
    pub fn n_patches(&self) -> usize {
        self.patches.len()
    }

    /// Where the stored coordinates sit in the given ones:
    /// `world = origin + 2^exponent · stored` ([`Frame`]).
    #[must_use]
    pub fn frame(&self) -> Frame {
        self.frame
    }

    /// The scene built from this one's stored coordinates (a subdivision, a mesh of
    /// leaves), placed in this one's frame.
    #[must_use]
    pub(crate) fn placed_in(mut self, outer: Frame) -> Scene3 {
        self.frame = outer.then(self.frame);
        self
    }

    /// Total area `A_T = Σ A_i` (stored units: [`Frame::area_to_world`] for the given
    /// ones).
    #[must_use]
    pub fn total_area(&self) -> f64 {
        self.total_area
    }

    /// The vertices of patch `i`, counter-clockwise about its normal; empty if `i` is out of
    /// range.
    #[must_use]
    pub fn patch_vertices(&self, i: usize) -> &[DVec3] {
        self.patches
            .get(i)
            .and_then(|p| self.points.get(p.first..p.first + p.count))
            .unwrap_or(&[])
    }

    /// The vertices of face `f`, counter-clockwise about its normal; empty if `f` is out of
    /// range.
    #[must_use]
    pub fn face_vertices(&self, f: usize) -> &[DVec3] {
        self.faces
            .get(f)
            .and_then(|p| self.points.get(p.first..p.first + p.count))
            .unwrap_or(&[])
    }

    /// The material of patch `i`, or `None` if `i` is out of range.
    #[must_use]
    pub fn patch_material(&self, i: usize) -> Option<&Material> {
        self.patches
            .get(i)
            .and_then(|p| self.materials.get(p.material))
    }

    /// The material of every patch, in patch order (the radiosity system's `ρ_i`, `E_i`,
    /// 2.6); the default material where a patch has none.
    #[must_use]
    pub fn patch_materials(&self) -> Vec<Material> {
        (0..self.n_patches())
            .map(|i| self.patch_material(i).copied().unwrap_or_default())
            .collect()
    }

    /// Axis-aligned bounds `(min, max)` of all vertices.
    #[must_use]
    pub fn bounds(&self) -> (DVec3, DVec3) {
        let mut lo = DVec3::splat(f64::INFINITY);
        let mut hi = DVec3::splat(f64::NEG_INFINITY);
        for &p in &self.points {
            lo = lo.min(p);
            hi = hi.max(p);
        }
        (lo, hi)
    }

    /// Relative areas `a_i = A_i / A_T` (the stationary distribution, thesis (2.16)), written
    /// into `out`.
    ///
    /// # Errors
    /// [`ErrorKind::BufferTooSmall`] if `out` is shorter than the number of patches.
    pub fn relative_areas_into(&self, out: &mut [f64]) -> Result<()> {
        let n = self.patches.len();
        let found = out.len();
        let out = out
            .get_mut(..n)
            .ok_or(ErrorKind::BufferTooSmall { needed: n, found })?;
        for (o, p) in out.iter_mut().zip(&self.patches) {
            *o = p.area / self.total_area;
        }
        Ok(())
    }

    /// The same faces, materials and objects, every face cut anew by `s` (the current
    /// patches are discarded, not refined).
    ///
    /// # Errors
    /// [`ErrorKind::BadSubdivision`], [`ErrorKind::TooManyPatches`], and
    /// [`ErrorKind::DegenerateFace`] if a new patch is too small to have a positive area.
    pub fn subdivided(&self, s: Subdivision) -> Result<Scene3> {
        let mut b = Scene3::builder();
        for (k, f) in self.faces.iter().enumerate() {
            b.material(self.materials[f.material]);
            b.object(&self.objects[f.object]);
            b.polygon(self.face_vertices(k), s)?;
        }
        Ok(b.build()?.placed_in(self.frame))
    }
}

/// Builds a [`Scene3`] face by face, validating each and cutting it into patches at once.
#[derive(Clone, Debug, Default)]
pub struct Scene3Builder {
    points: Vec<DVec3>,
    patches: Vec<Patch3>,
    faces: Vec<Face3>,
    materials: Vec<Material>,
    material_index: BTreeMap<[u64; 6], usize>,
    objects: Vec<String>,
    object_index: BTreeMap<String, usize>,
    current_material: Option<Material>,
    current_object: Option<String>,
    /// The subdivision each face was cut by (to cut its pieces alike in
    /// [`Scene3Builder::build_as_drawn`]).
    subdivisions: Vec<Subdivision>,
    /// Faces are kept scaled by `2^−working_exponent` from the first one on, so a scene
    /// 10⁻²⁰⁰ wide is validated and cut without underflow ([`working_exponent`]); `None`
    /// before the first face.
    working_exponent: Option<i32>,
}

impl Scene3Builder {
    /// Sets the material of the faces added after this call (default:
    /// [`Material::BLACK`]).
    pub fn material(&mut self, m: Material) -> &mut Self {
        self.current_material = Some(m);
        self
    }

    /// Sets the object (OBJ `o`/`g` name) of the faces added after this call (default:
    /// `"default"`). Faces of one name form one object, however they are interleaved.
    pub fn object(&mut self, name: &str) -> &mut Self {
        self.current_object = Some(String::from(name));
        self
    }

    /// Number of patches so far.
    #[must_use]
    pub fn patch_count(&self) -> usize {
        self.patches.len()
    }

    /// Number of faces so far.
    #[must_use]
    pub fn face_count(&self) -> usize {
        self.faces.len()
    }

    /// Adds the planar convex polygon through `vertices` (front side: counter-clockwise,
    /// right-hand rule), cut into patches by `s`.
    ///
    /// The tolerances are relative to the face's size `d` (its bounding-box diagonal): it is
    /// degenerate if its area is at most `10⁻¹² d²` or an edge at most `10⁻¹² d` long;
    /// non-planar if a vertex lies more than `PLANARITY_TOLERANCE`` · d` from its Newell
    /// plane; non-convex if the sine of a turn is below `−``CONVEXITY_TOLERANCE` or the
    /// polygon winds more than once.
    ///
    /// # Errors
    /// In this order: [`ErrorKind::FaceVertexCount`], [`ErrorKind::NonFiniteNumber`],
    /// [`ErrorKind::CoordinateRange`], [`ErrorKind::DegenerateFace`],
    /// [`ErrorKind::NonPlanarFace`], [`ErrorKind::NonConvexFace`],
    /// [`ErrorKind::BadSubdivision`], [`ErrorKind::TooManyPatches`] (checked before any
    /// patch is allocated). On error the builder is unchanged.
    pub fn polygon(&mut self, vertices: &[DVec3], s: Subdivision) -> Result<&mut Self> {
        check_face_input(vertices)?;
        let exponent = self.exponent_for(vertices);
        let scaled = scale_face(vertices, exponent)?;
        self.add_polygon(&scaled, s)?;
        self.working_exponent = Some(exponent);
        Ok(self)
    }

    /// The working exponent: the builder's, or the one the first face sets.
    fn exponent_for(&self, vertices: &[DVec3]) -> i32 {
        self.working_exponent
            .unwrap_or_else(|| working_exponent(vertices))
    }

    /// [`Self::polygon`] for vertices already in working coordinates.
    fn add_polygon(&mut self, vertices: &[DVec3], s: Subdivision) -> Result<&mut Self> {
        let n = vertices.len();
        check_face_input(vertices)?;
        // Degeneracy: area and edges against the face's size
        let size = geom::bounds_diagonal(vertices);
        let vector_area = geom::polygon_normal(vertices);
        let twice_area = vector_area.length();
        let short_edge = (0..n)
            .any(|k| (vertices[(k + 1) % n] - vertices[k]).length() <= DEGENERACY_TOLERANCE * size);
        if !(twice_area > DEGENERACY_TOLERANCE * size * size) || short_edge {
            return Err(ErrorKind::DegenerateFace.into());
        }
        let normal = vector_area / twice_area;
        // Planarity about Newell's plane, then convexity within it
        let deviation = geom::plane_deviation(vertices, normal);
        if deviation > PLANARITY_TOLERANCE * size {
            return Err(ErrorKind::NonPlanarFace { deviation }.into());
        }
        if !geom::is_convex(vertices, normal, CONVEXITY_TOLERANCE) {
            return Err(ErrorKind::NonConvexFace.into());
        }
        // Patch count, against the cap, before allocating
        s.validate()?;
        let corners: Vec<usize> = (0..n)
            .filter(|&k| n == 3 || geom::turn_angle(vertices, k, normal) > CONVEXITY_TOLERANCE)
            .collect();
        if corners.len() < 3 {
            return Err(ErrorKind::DegenerateFace.into());
        }
        let count = s.patch_count(n, corners.len());
        let total = (self.patches.len() as u64).saturating_add(count);
        if total > MAX_PATCHES_3D as u64 {
            return Err(ErrorKind::TooManyPatches {
                max: MAX_PATCHES_3D as u64,
            }
            .into());
        }
        // Cut the face, rolling back if a patch turns out degenerate
        let (points_len, patches_len) = (self.points.len(), self.patches.len());
        let face = self.faces.len();
        let first = self.points.len();
        self.points.extend_from_slice(vertices);
        let mut cutter = Cutter {
            points: &mut self.points,
            patches: &mut self.patches,
            face,
            normal,
        };
        let cut = match s {
            Subdivision::None => cutter.whole(first, n, 0.5 * twice_area, vector_area),
            Subdivision::Grid(k) if n == 4 => {
                let q = [vertices[0], vertices[1], vertices[2], vertices[3]];
                cutter.grid_quad(q, k)
            }
            Subdivision::Grid(k) => cutter.fan(vertices, &corners, k),
            Subdivision::Triangles(l) => cutter.fan(vertices, &corners, 1 << l),
        };
        if let Err(e) = cut {
            self.points.truncate(points_len);
            self.patches.truncate(patches_len);
            return Err(e);
        }
        // Material and object, registered on first use
        let material = self.current_material.unwrap_or(Material::BLACK);
        let key = material_key(&material);
        let material = *self.material_index.entry(key).or_insert_with(|| {
            self.materials.push(material);
            self.materials.len() - 1
        });
        let name = self.current_object.as_deref().unwrap_or("default");
        let object = match self.object_index.get(name) {
            Some(&k) => k,
            None => {
                self.objects.push(String::from(name));
                self.object_index
                    .insert(String::from(name), self.objects.len() - 1);
                self.objects.len() - 1
            }
        };
        for p in &mut self.patches[patches_len..] {
            p.material = material;
        }
        self.faces.push(Face3 {
            first,
            count: n,
            material,
            normal,
            area: 0.5 * twice_area,
            patches: patches_len..self.patches.len(),
            object,
        });
        self.subdivisions.push(s);
        Ok(self)
    }

    /// The finished scene.
    ///
    /// # Errors
    /// [`ErrorKind::EmptyScene`] if no face was added; [`ErrorKind::CoincidentSurfaces`]
    /// (face indices) if two faces lie in one plane, face the same way and overlap
    /// ([`super::coincident`]).
    pub fn build(&self) -> Result<Scene3> {
        let total_area = self.validate()?;
        Scene3 {
            points: self.points.clone(),
            patches: self.patches.clone(),
            faces: self.faces.clone(),
            materials: self.materials.clone(),
            objects: self.objects.clone(),
            total_area,
            frame: Frame::IDENTITY,
        }
        .stored_in_frame(self.working_exponent.unwrap_or(0))
    }

    /// [`Self::build`] without copying: the builder's vectors become the scene's (half the
    /// peak memory of a large scene).
    ///
    /// # Errors
    /// As [`Self::build`].
    pub fn finish(self) -> Result<Scene3> {
        self.validate()?;
        self.into_scene()
    }

    /// The scene of the faces as they are, checking only the total area (the coincidence
    /// check left to the caller).
    fn into_scene(self) -> Result<Scene3> {
        let total_area = self.total_area()?;
        let working = self.working_exponent.unwrap_or(0);
        Scene3 {
            points: self.points,
            patches: self.patches,
            faces: self.faces,
            materials: self.materials,
            objects: self.objects,
            total_area,
            frame: Frame::IDENTITY,
        }
        .stored_in_frame(working)
    }

    /// The checks of [`Self::build`]; the total area.
    fn validate(&self) -> Result<f64> {
        if self.faces.is_empty() {
            return Err(ErrorKind::EmptyScene.into());
        }
        super::coincident::refuse(super::coincident::coincident_faces(&self.face_list()))?;
        self.total_area()
    }

    /// `A_T`, compensated; refused unless finite and positive.
    fn total_area(&self) -> Result<f64> {
        let mut total = KahanSum::new();
        for p in &self.patches {
            total.add(p.area);
        }
        let total_area = total.total();
        if !(total_area.is_finite() && total_area > 0.0) {
            return Err(ErrorKind::CoordinateRange.into());
        }
        Ok(total_area)
    }

    /// Each face's vertices and unit normal, as [`super::coincident`] takes them.
    fn face_list(&self) -> Vec<(&[DVec3], DVec3)> {
        self.faces
            .iter()
            .map(|f| (&self.points[f.first..f.first + f.count], f.normal))
            .collect()
    }
}

/// The checks every face passes before anything else, strict or as drawn: 3 to
/// [`MAX_FACE_VERTICES`] vertices ([`ErrorKind::FaceVertexCount`]), then
/// [`check_coordinates`].
fn check_face_input(vertices: &[DVec3]) -> Result<()> {
    let n = vertices.len();
    if !(3..=MAX_FACE_VERTICES).contains(&n) {
        return Err(ErrorKind::FaceVertexCount {
            given: n as u64,
            max: MAX_FACE_VERTICES as u64,
        }
        .into());
    }
    check_coordinates(vertices)
}

impl Scene3 {
    /// The scene of working coordinates `2^working` given units, moved and scaled exactly
    /// into the [`Frame`] of its bounding box (module docs of [`crate::scene::frame`]).
    fn stored_in_frame(mut self, working: i32) -> Result<Scene3> {
        let (lo, hi) = self.bounds();
        let frame = Frame::for_bounds_in_units(lo, hi, working)?;
        if !frame.is_identity() {
            let area_exponent = -2 * frame.exponent();
            let area = |a: f64| crate::math::scale_by_power_of_two(a, area_exponent);
            for p in &mut self.points {
                *p = frame.to_stored(*p);
            }
            for p in &mut self.patches {
                p.centroid = frame.to_stored(p.centroid);
                p.area = area(p.area);
                if !(p.area > 0.0) {
                    return Err(ErrorKind::DegenerateFace.into());
                }
            }
            for f in &mut self.faces {
                f.area = area(f.area);
            }
            self.total_area = area(self.total_area);
        }
        self.frame = Frame::scaled(working).then(frame);
        Ok(self)
    }
}

/// The working exponent a first face sets: 0 while its extent (largest side of its
/// bounding box) lies within `2^±`[`SAFE_EXTENT_EXPONENT`](crate::scene::SAFE_EXTENT_EXPONENT),
/// else `⌊log₂ extent⌋`, so its working extent lies in `[1, 2)`.
fn working_exponent(vertices: &[DVec3]) -> i32 {
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for &p in vertices {
        lo = lo.min(p);
        hi = hi.max(p);
    }
    let e = crate::math::exponent_of((hi - lo).max_element());
    if e.abs() <= crate::scene::SAFE_EXTENT_EXPONENT {
        0
    } else {
        e
    }
}

/// A face's vertices in working coordinates, `v · 2^−exponent` (exact while they stay in
/// the normal range; borrowed when `exponent` is 0).
///
/// # Errors
/// [`ErrorKind::CoordinateRange`] if a coordinate overflows: the face is more than `2¹⁰²³`
/// times larger than the scene's first face.
fn scale_face(vertices: &[DVec3], exponent: i32) -> Result<alloc::borrow::Cow<'_, [DVec3]>> {
    use alloc::borrow::Cow;
    if exponent == 0 {
        return Ok(Cow::Borrowed(vertices));
    }
    let scale = |x: f64| crate::math::scale_by_power_of_two(x, -exponent);
    let scaled: Vec<DVec3> = vertices
        .iter()
        .map(|v| DVec3::new(scale(v.x), scale(v.y), scale(v.z)))
        .collect();
    if scaled.iter().any(|v| !v.is_finite()) {
        return Err(ErrorKind::CoordinateRange.into());
    }
    Ok(Cow::Owned(scaled))
}

/// Checks that every coordinate is finite and within [`MAX_COORDINATE`].
fn check_coordinates(vertices: &[DVec3]) -> Result<()> {
    for v in vertices {
        for c in v.to_array() {
            if !c.is_finite() {
                return Err(ErrorKind::NonFiniteNumber {
                    field: "coordinate",
                }
                .into());
            }
            if c.abs() > MAX_COORDINATE {
                return Err(ErrorKind::CoordinateRange.into());
            }
        }
    }
    Ok(())
}

/// The bit patterns of a material, a total-order key for de-duplication.
fn material_key(m: &Material) -> [u64; 6] {
    let [r, g, b] = m.reflectance;
    let [er, eg, eb] = m.emittance;
    [r, g, b, er, eg, eb].map(f64::to_bits)
}

/// Cuts one face into patches, appending their vertices and records.
struct Cutter<'a> {
    points: &'a mut Vec<DVec3>,
    patches: &'a mut Vec<Patch3>,
    face: usize,
    normal: DVec3,
}

impl Cutter<'_> {
    /// The face as its own single patch, sharing its vertices.
    fn whole(&mut self, first: usize, count: usize, area: f64, vector_area: DVec3) -> Result<()> {
        let centroid = geom::polygon_centroid(&self.points[first..first + count], vector_area);
        self.patches.push(Patch3 {
            first,
            count,
            face: self.face,
            material: 0,
            normal: self.normal,
            area,
            centroid,
        });
        Ok(())
    }

    /// Appends the patch through `vertices` (in the face's plane and orientation).
    fn push(&mut self, vertices: &[DVec3]) -> Result<()> {
        let vector_area = geom::polygon_normal(vertices);
        // The signed area along the face's normal: a sliver that rounding flipped is caught.
        let area = 0.5 * vector_area.dot(self.normal);
        if !(area > 0.0 && area.is_finite()) {
            return Err(ErrorKind::DegenerateFace.into());
        }
        let first = self.points.len();
        self.points.extend_from_slice(vertices);
        self.patches.push(Patch3 {
            first,
            count: vertices.len(),
            face: self.face,
            material: 0,
            normal: self.normal,
            area,
            centroid: geom::polygon_centroid(vertices, self.normal),
        });
        Ok(())
    }

    /// A quad `q0 q1 q2 q3` cut into `k × k` quads at the points
    ///
    /// ```text
    /// P(u, v) = (1 − v) ((1 − u) q0 + u q1) + v ((1 − u) q3 + u q2),   u, v ∈ {0, 1/k, …, 1}
    /// ```
    ///
    /// (weights of the form `(1 − t) a + t b` hit the corners exactly).
    fn grid_quad(&mut self, q: [DVec3; 4], k: u32) -> Result<()> {
        let k = k as usize;
        let lerp = |a: DVec3, b: DVec3, t: f64| a * (1.0 - t) + b * t;
        let t = |i: usize| i as f64 / k as f64;
        let grid: Vec<DVec3> = (0..=k)
            .flat_map(|j| {
                let v = t(j);
                (0..=k).map(move |i| {
                    let u = t(i);
                    lerp(lerp(q[0], q[1], u), lerp(q[3], q[2], u), v)
                })
            })
            .collect();
        let at = |i: usize, j: usize| grid[j * (k + 1) + i];
        for j in 0..k {
            for i in 0..k {
                self.push(&[at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)])?;
            }
        }
        Ok(())
    }

    /// The convex polygon fanned from its first corner into triangles, each cut into `k²`.
    fn fan(&mut self, vertices: &[DVec3], corners: &[usize], k: u32) -> Result<()> {
        let a = vertices[corners[0]];
        for w in corners[1..].windows(2) {
            self.grid_triangle([a, vertices[w[0]], vertices[w[1]]], k)?;
        }
        Ok(())
    }

    /// A triangle `a b c` cut into `k²` triangles on the barycentric grid
    ///
    /// ```text
    /// P(i, j) = ((k − i − j) a + i b + j c) / k,   i + j ≤ k
    /// ```
    ///
    /// (for `k = 2^l`, the triangles of `l` rounds of midpoint subdivision).
    fn grid_triangle(&mut self, [a, b, c]: [DVec3; 3], k: u32) -> Result<()> {
        let k = k as usize;
        let kf = k as f64;
        let at = |i: usize, j: usize| {
            a * ((k - i - j) as f64 / kf) + b * (i as f64 / kf) + c * (j as f64 / kf)
        };
        for j in 0..k {
            for i in 0..k - j {
                // The upward triangle at (i, j), then the downward one beside it
                self.push(&[at(i, j), at(i + 1, j), at(i, j + 1)])?;
                if i + j + 1 < k {
                    self.push(&[at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)])?;
                }
            }
        }
        Ok(())
    }
}

mod lenient;
mod overlap;

#[cfg(test)]
mod tests;
