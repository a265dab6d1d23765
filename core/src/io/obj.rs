//! A Wavefront OBJ/MTL subset for 3D scenes.
//!
//! OBJ (UTF-8, one statement per line, `#` starts a comment that runs to the end of the line):
//!
//! ```text
//! v x y z [w]            # a vertex (w, or three r g b colour values, accepted and ignored)
//! f v1 v2 v3 …           # a planar convex face, counter-clockwise seen from its front;
//!                        # each vertex as v, v/vt, v//vn or v/vt/vn; 1-based, or negative
//!                        # to count back from the last vertex defined (−1 = the last)
//! o name | g name …      # the object of the faces that follow (the rest of the line)
//! mtllib a.mtl [b.mtl …] # material libraries, fetched through the caller's callback
//! usemtl name            # the material of the faces that follow
//! vt …, vn …, vp …, s …  # accepted and ignored (only the indices' syntax is checked)
//! l …, p …               # polylines and points: no area, so accepted and ignored
//! ```
//!
//! MTL (same lexical rules):
//!
//! ```text
//! newmtl name            # starts a material: ρ = 0, E = 0 until set
//! Kd r [g b]             # reflectance ρ, each in [0, 1)  (one value: grey)
//! Ke r [g b]             # emittance E, each ≥ 0
//! Ka, Ks, Ns, d, illum … # any other statement is ignored
//! ```
//!
//! Faces before any `usemtl` are [`Material::BLACK`] (ρ = 0, E = 0), as are materials without
//! `Kd`/`Ke` lines (the flatland default; MTL readers that default `Kd` to 0.8 differ). An
//! unknown `usemtl` name, a library the callback cannot provide, or a name defined twice
//! is an error. Line continuations (`\` at the end of a line) are not supported.
//!
//! Every face is validated by [`SceneBuilder::polygon`](crate::scene::SceneBuilder::polygon)
//! (planar, convex, non-degenerate, at most [`MAX_FACE_VERTICES`] vertices) and cut by the
//! [`Subdivision`] given; the patch cap [`crate::scene::MAX_PATCHES_3D`] is checked before
//! each face's patches are allocated.

use alloc::collections::BTreeMap;
use alloc::string::String;
use alloc::vec::Vec;
use core::fmt::Write;

use super::LoadReport;
use crate::error::{Error, ErrorKind, MaterialProblem, Result, token};
use crate::geom::DVec3;
use crate::scene::{MAX_FACE_VERTICES, Material, Scene, Subdivision};

/// 1-based line numbers, saturating.
fn line_number(k: usize) -> u32 {
    u32::try_from(k + 1).unwrap_or(u32::MAX)
}

/// The statement part of a line: everything before `#`.
fn content(raw: &str) -> &str {
    raw.split('#').next().unwrap_or("")
}

fn parse_number(s: &str, field: &'static str) -> Result<f64> {
    let v: f64 = s.parse().map_err(|_| ErrorKind::BadNumber {
        field,
        found: token(s),
    })?;
    if !v.is_finite() {
        return Err(ErrorKind::NonFiniteNumber { field }.into());
    }
    Ok(v)
}

/// Parses an OBJ scene (module docs give the subset), cutting every face by `subdivision`.
/// `mtl(name)` returns the text of the material library `name` named by an `mtllib` line, or
/// `None` if it cannot.
///
/// # Errors
/// The first problem found, with its 1-based OBJ line: [`ErrorKind::UnknownKeyword`],
/// [`ErrorKind::BadNumber`], [`ErrorKind::NonFiniteNumber`], [`ErrorKind::MissingField`],
/// [`ErrorKind::TrailingField`], [`ErrorKind::FaceIndex`], [`ErrorKind::MissingMaterial`],
/// [`ErrorKind::MissingMaterialLibrary`], [`ErrorKind::InMaterialLibrary`] (at the `mtllib`
/// line, naming the library's own line), and the face errors of
/// [`SceneBuilder::polygon`](crate::scene::SceneBuilder::polygon);
/// [`ErrorKind::BadSubdivision`] (no line) for a bad `subdivision`;
/// [`ErrorKind::EmptyScene`] (line of the end of input) if there is no face.
///
/// # Examples
/// ```
/// use sceneinfo::io::parse_obj;
/// use sceneinfo::scene::Subdivision;
///
/// let obj = "mtllib box.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nusemtl lamp\nf 1 2 3 4\n";
/// let mtl = |name: &str| (name == "box.mtl").then(|| "newmtl lamp\nKe 10 10 10\n".into());
/// let scene = parse_obj(obj, Subdivision::Grid(4), mtl).unwrap();
/// assert_eq!(scene.n_patches(), 16);
/// assert_eq!(scene.patch_material(0).unwrap().emittance, [10.0; 3]);
///
/// let err = parse_obj("v 0 0 0\nv 1 0 0\nf 1 2 3\n", Subdivision::None, |_| None);
/// assert_eq!(
///     err.unwrap_err().to_string(),
///     "line 3: vertex index 3 out of range (2 vertices defined so far; 0 is never valid)"
/// );
/// ```
pub fn parse_obj(
    obj: &str,
    subdivision: Subdivision,
    mtl: impl Fn(&str) -> Option<String>,
) -> Result<Scene> {
    parse_obj_report(obj, subdivision, mtl).map(|(scene, _)| scene)
}

/// [`parse_obj`], with what was repaired on the way: faces are added by
/// [`SceneBuilder::face_as_drawn`](crate::scene::SceneBuilder::face_as_drawn) (repeated
/// vertices removed, nearly planar faces flattened, concave or bent ones triangulated,
/// zero-area ones dropped) and the scene finished by
/// [`SceneBuilder::build_as_drawn`](crate::scene::SceneBuilder::build_as_drawn) (duplicate
/// faces dropped, overlapping coincident ones cut), all recorded in the [`LoadReport`].
///
/// # Errors
/// As [`parse_obj`], less the face errors those repair.
pub fn parse_obj_report(
    obj: &str,
    subdivision: Subdivision,
    mtl: impl Fn(&str) -> Option<String>,
) -> Result<(Scene, LoadReport)> {
    subdivision.validate()?;
    let mut state = ObjState {
        builder: Scene::builder(),
        vertices: Vec::new(),
        face: Vec::new(),
        materials: BTreeMap::new(),
        libraries: Vec::new(),
        subdivision,
        report: LoadReport::default(),
        line: None,
    };
    let mut last_line = 1;
    // The line of each face, to locate coincident faces found at the end
    let mut face_lines: Vec<u32> = Vec::new();
    for (k, raw) in obj.lines().enumerate() {
        let line_no = line_number(k);
        last_line = line_no;
        state.line = Some(line_no);
        state
            .statement(content(raw), &mtl)
            .map_err(|e| e.with_line(line_no))?;
        face_lines.resize(state.builder.face_count(), line_no);
    }
    let mut report = state.report;
    let scene = state
        .builder
        .build_as_drawn(&mut report, &face_lines)
        .map_err(|e| match *e.kind() {
            ErrorKind::EmptyScene => e.with_line(last_line),
            ErrorKind::CoincidentSurfaces { first, second } => {
                super::flat::locate_coincident(&face_lines, first, second)
            }
            _ => e,
        })?;
    Ok((scene, report))
}

/// What the OBJ parser keeps between lines.
struct ObjState {
    builder: crate::scene::SceneBuilder,
    vertices: Vec<DVec3>,
    face: Vec<DVec3>,
    materials: BTreeMap<String, Material>,
    libraries: Vec<String>,
    subdivision: Subdivision,
    /// What the lenient face entry repaired.
    report: LoadReport,
    /// The line being read, for the report's warnings.
    line: Option<u32>,
}

impl ObjState {
    fn statement(&mut self, line: &str, mtl: &impl Fn(&str) -> Option<String>) -> Result<()> {
        let mut fields = line.split_whitespace();
        let Some(keyword) = fields.next() else {
            return Ok(());
        };
        let rest = line.trim_start()[keyword.len()..].trim();
        match keyword {
            "v" => {
                let x = self.number(fields.next(), "x")?;
                let y = self.number(fields.next(), "y")?;
                let z = self.number(fields.next(), "z")?;
                // w, or a vertex colour r g b: checked, then ignored
                for (k, s) in fields.enumerate() {
                    if k >= 3 {
                        return Err(ErrorKind::TrailingField(token(s)).into());
                    }
                    parse_number(s, "w")?;
                }
                self.vertices.push(DVec3::new(x, y, z));
            }
            "vt" | "vn" | "vp" => {
                let field = match keyword {
                    "vt" => "vt",
                    "vn" => "vn",
                    _ => "vp",
                };
                for s in fields {
                    parse_number(s, field)?;
                }
            }
            "f" => {
                self.face.clear();
                for s in fields {
                    if self.face.len() >= MAX_FACE_VERTICES {
                        return Err(ErrorKind::FaceVertexCount {
                            given: line.split_whitespace().count() as u64 - 1,
                            max: MAX_FACE_VERTICES as u64,
                        }
                        .into());
                    }
                    let v = self.face_vertex(s)?;
                    self.face.push(v);
                }
                self.builder.face_as_drawn(
                    &self.face,
                    self.subdivision,
                    &mut self.report,
                    self.line,
                )?;
            }
            "o" | "g" => {
                // The rest of the line is the name; none means the default object.
                self.builder
                    .object(if rest.is_empty() { "default" } else { rest });
            }
            "s" | "l" | "p" => {}
            "usemtl" => {
                if rest.is_empty() {
                    return Err(ErrorKind::MissingField {
                        field: "material name",
                    }
                    .into());
                }
                let m = self
                    .materials
                    .get(rest)
                    .ok_or_else(|| ErrorKind::MissingMaterial(token(rest)))?;
                self.builder.material(*m);
            }
            "mtllib" => {
                let mut any = false;
                for name in fields {
                    any = true;
                    self.library(name, mtl)?;
                }
                if !any {
                    return Err(ErrorKind::MissingField {
                        field: "library name",
                    }
                    .into());
                }
            }
            other => return Err(ErrorKind::UnknownKeyword(token(other)).into()),
        }
        Ok(())
    }

    fn number(&self, s: Option<&str>, field: &'static str) -> Result<f64> {
        parse_number(s.ok_or(ErrorKind::MissingField { field })?, field)
    }

    /// One `v`, `v/vt`, `v//vn` or `v/vt/vn` of an `f` line: the vertex it names.
    fn face_vertex(&self, s: &str) -> Result<DVec3> {
        let mut parts = s.split('/');
        let v = parts.next().unwrap_or("");
        let index = v.parse::<i64>().map_err(|_| bad_index("vertex index", s))?;
        let vt = parts.next();
        let vn = parts.next();
        if parts.next().is_some() {
            return Err(bad_index("vertex index", s));
        }
        // Texture and normal indices are ignored, but must be integers (vt may be empty).
        if let Some(t) = vt.filter(|t| !t.is_empty()) {
            check_index(t, s, "texture index")?;
        }
        if let Some(n) = vn {
            check_index(n, s, "normal index")?;
        }
        let count = self.vertices.len();
        // 1-based from the start, or negative from the end (−1 = last).
        let slot = if index > 0 {
            usize::try_from(index - 1).ok().filter(|&i| i < count)
        } else if index == 0 {
            None
        } else {
            usize::try_from(index.unsigned_abs())
                .ok()
                .and_then(|back| count.checked_sub(back))
        };
        slot.map(|i| self.vertices[i])
            .ok_or_else(|| ErrorKind::FaceIndex { index, count }.into())
    }

    /// Loads the library `name` (once) into the named materials.
    fn library(&mut self, name: &str, mtl: &impl Fn(&str) -> Option<String>) -> Result<()> {
        if self.libraries.iter().any(|l| l == name) {
            return Ok(());
        }
        let text = mtl(name).ok_or_else(|| ErrorKind::MissingMaterialLibrary(token(name)))?;
        parse_mtl(&text, &mut self.materials).map_err(|(line, problem)| {
            Error::from(ErrorKind::InMaterialLibrary {
                library: token(name),
                line,
                problem,
            })
        })?;
        self.libraries.push(String::from(name));
        Ok(())
    }
}

fn bad_index(field: &'static str, s: &str) -> Error {
    ErrorKind::BadNumber {
        field,
        found: token(s),
    }
    .into()
}

/// Checks that an ignored texture or normal index is a non-zero integer.
fn check_index(part: &str, whole: &str, field: &'static str) -> Result<()> {
    match part.parse::<i64>() {
        Ok(i) if i != 0 => Ok(()),
        _ => Err(bad_index(field, whole)),
    }
}

/// Parses one MTL library into `out`; errors carry the library's 1-based line.
fn parse_mtl(
    text: &str,
    out: &mut BTreeMap<String, Material>,
) -> core::result::Result<(), (u32, MaterialProblem)> {
    let mut current: Option<String> = None;
    for (k, raw) in text.lines().enumerate() {
        let line_no = line_number(k);
        let line = content(raw);
        let mut fields = line.split_whitespace();
        let Some(keyword) = fields.next() else {
            continue;
        };
        match keyword {
            "newmtl" => {
                let name = line.trim_start()[keyword.len()..].trim();
                if name.is_empty() {
                    return Err((
                        line_no,
                        MaterialProblem::MissingField {
                            field: "material name",
                        },
                    ));
                }
                if out.contains_key(name) {
                    return Err((line_no, MaterialProblem::DuplicateMaterial));
                }
                out.insert(String::from(name), Material::BLACK);
                current = Some(String::from(name));
            }
            "Kd" | "Ke" => {
                let field = if keyword == "Kd" { "Kd" } else { "Ke" };
                let m = current
                    .as_ref()
                    .and_then(|name| out.get_mut(name))
                    .ok_or((line_no, MaterialProblem::NoCurrentMaterial))?;
                let rgb = mtl_rgb(fields, field).map_err(|p| (line_no, p))?;
                let (rho, emit) = if field == "Kd" {
                    (rgb, m.emittance)
                } else {
                    (m.reflectance, rgb)
                };
                *m = Material::new(rho, emit).map_err(|e| {
                    let problem = match *e.kind() {
                        ErrorKind::Reflectance { value } => MaterialProblem::Reflectance { value },
                        ErrorKind::Emittance { value } => MaterialProblem::Emittance { value },
                        _ => MaterialProblem::NonFiniteNumber { field },
                    };
                    (line_no, problem)
                })?;
            }
            _ => {}
        }
    }
    Ok(())
}

/// `r [g b]` of a `Kd`/`Ke` line (one value means grey).
fn mtl_rgb(
    mut fields: core::str::SplitWhitespace<'_>,
    field: &'static str,
) -> core::result::Result<[f64; 3], MaterialProblem> {
    let number = |s: &str| -> core::result::Result<f64, MaterialProblem> {
        let v: f64 = s
            .parse()
            .map_err(|_| MaterialProblem::BadNumber { field })?;
        if v.is_finite() {
            Ok(v)
        } else {
            Err(MaterialProblem::NonFiniteNumber { field })
        }
    };
    let r = number(
        fields
            .next()
            .ok_or(MaterialProblem::MissingField { field })?,
    )?;
    let Some(g) = fields.next() else {
        return Ok([r; 3]);
    };
    let g = number(g)?;
    let b = number(
        fields
            .next()
            .ok_or(MaterialProblem::MissingField { field })?,
    )?;
    if fields.next().is_some() {
        return Err(MaterialProblem::TrailingField);
    }
    Ok([r, g, b])
}

/// Writes a scene as OBJ and its MTL library (to be saved as `mtl_name`).
///
/// Every **patch** is written as a face, so the discretisation survives the trip; vertices
/// are shared when bit-identical. Faces are grouped with `o` lines by object and `usemtl`
/// lines by material; material `k` is `newmtl mk` with its `Kd` and `Ke`. Numbers use Rust's
/// shortest round-trip formatting, so for a scene whose faces are single patches
/// ([`Subdivision::None`]) `parse_obj(obj, Subdivision::None, …)` gives back the same scene
/// bit for bit (object names as the parser makes them: trimmed, no `#`).
#[must_use]
pub fn write_obj(scene: &Scene, mtl_name: &str) -> (String, String) {
    let mut obj = String::new();
    let _ = writeln!(obj, "# sceneinfo scene: {} patches", scene.n_patches());
    let _ = writeln!(obj, "mtllib {mtl_name}");
    // Vertices, each distinct one once, in order of first use
    let mut index: BTreeMap<[u64; 3], usize> = BTreeMap::new();
    let mut faces: Vec<usize> = Vec::new();
    for i in 0..scene.n_patches() {
        for v in scene.patch_vertices(i) {
            let key = v.to_array().map(f64::to_bits);
            let next = index.len() + 1;
            let k = *index.entry(key).or_insert_with(|| {
                let _ = writeln!(obj, "v {:?} {:?} {:?}", v.x, v.y, v.z);
                next
            });
            faces.push(k);
        }
    }
    // Patches as faces, switching object and material as needed
    let mut object = None;
    let mut material = None;
    let mut at = 0;
    for p in scene.patches() {
        let face = &scene.faces()[p.face];
        if object != Some(face.object) {
            let _ = writeln!(obj, "o {}", scene.objects()[face.object]);
            object = Some(face.object);
        }
        if material != Some(p.material) {
            let _ = writeln!(obj, "usemtl m{}", p.material);
            material = Some(p.material);
        }
        obj.push('f');
        for k in &faces[at..at + p.count] {
            let _ = write!(obj, " {k}");
        }
        obj.push('\n');
        at += p.count;
    }
    let mut mtl = String::new();
    let _ = writeln!(
        mtl,
        "# sceneinfo materials: Kd = reflectance, Ke = emittance"
    );
    for (k, m) in scene.materials().iter().enumerate() {
        let [r, g, b] = m.reflectance;
        let [er, eg, eb] = m.emittance;
        let _ = writeln!(
            mtl,
            "newmtl m{k}\nKd {r:?} {g:?} {b:?}\nKe {er:?} {eg:?} {eb:?}"
        );
    }
    (obj, mtl)
}

#[cfg(test)]
mod tests;
