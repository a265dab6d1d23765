//! Wavefront OBJ/MTL for 3D scenes, as real exporters write them.
//!
//! OBJ (UTF-8, one statement per line, `#` starts a comment that runs to the end of the line,
//! a `\` at the end of a line continues the statement on the next one):
//!
//! ```text
//! v x y z [w]            # a vertex (w, or three r g b colour values, accepted and ignored)
//! f v1 v2 v3 …           # a face (any polygon), counter-clockwise seen from its front;
//!                        # each vertex as v, v/vt, v//vn or v/vt/vn; 1-based, or negative
//!                        # to count back from the last vertex defined (−1 = the last)
//! o name | g name …      # the object of the faces that follow (the rest of the line)
//! mtllib a.mtl [b.mtl …] # material libraries, fetched through the caller's callback
//! usemtl name            # the material of the faces that follow
//! vt …, vn …, vp …, s …  # accepted and ignored (only the indices' syntax is checked)
//! l …, p …               # polylines and points: no area, so accepted and ignored
//! cstype, deg, bmat, …   # every other statement: skipped with a warning (below)
//! ```
//!
//! MTL (same lexical rules):
//!
//! ```text
//! newmtl name            # starts a material: ρ = 0, E = 0 until set
//! Kd r [g b]             # reflectance ρ (one value: grey); above 0.99 clamped, with a warning
//! Ke r [g b]             # emittance E, each ≥ 0
//! Ka r [g b]             # ambient colour: kept; the emittance of a material without Ke
//!                        # when ObjOptions::emit_from_ka is set (old-style lamps)
//! Ks, Ns, Ni, d, Tr, Tf, illum, map_*, bump, disp, decal, refl, Pr, Pm, Ps, Pc, Pcr,
//! aniso, anisor, norm, … # any other statement: skipped silently
//! ```
//!
//! # What is skipped, and what is an error
//!
//! The parser follows what renderers' loaders (tinyobjloader, Blender's importer) draw from
//! the same file, and says in the [`LoadReport`] what it skipped, one entry per class with
//! its first line and count:
//!
//! - **Statements.** Every OBJ statement of the specification that carries no geometry
//!   sceneinfo uses — free-form geometry (`cstype`, `deg`, `bmat`, `step`, `curv`, `curv2`,
//!   `surf`, `parm`, `trim`, `hole`, `scrv`, `sp`, `end`), connectivity (`con`), merging
//!   groups (`mg`), display and render attributes (`bevel`, `c_interp`, `d_interp`, `lod`,
//!   `usemap`, `maplib`, `shadow_obj`, `trace_obj`, `ctech`, `stech`), `call`, `csh`, the
//!   superseded `bsp`, `bzp`, `cdc`, `cdp`, `res`, `fo`, and the crease statement `t` some
//!   exporters write — is skipped with one
//!   [`LoadWarningKind::SkippedStatement`] per keyword. A keyword sceneinfo does not know at
//!   all is skipped too, with one [`LoadWarningKind::UnknownStatement`] per keyword, as
//!   tinyobjloader and Blender do: refusing a whole scene for an exporter's private
//!   statement helps nobody, and the warning still shows a typo. Malformed data of the
//!   statements that are read (`v`, `vt`, `vn`, `vp`, `f`, their indices) stays a located
//!   error: skipping a vertex would shift every index after it.
//! - **Continuations.** A line whose statement (after removing its comment) ends with `\`
//!   continues on the next line; the backslash and the line break read as one space. The
//!   joined statement is located at its first line; later lines keep their own numbers.
//! - **`mtllib`.** The whole rest of the line is tried as one file name first (surrounding
//!   double quotes removed), so names with spaces work (Blender reads it so); if the caller
//!   cannot provide it and the line has several words, each word is tried as a library of
//!   its own (tinyobjloader splits on whitespace; the specification allows several
//!   libraries). A library the caller cannot provide is a
//!   [`LoadWarningKind::MissingMaterialLibrary`], not an error.
//! - **`usemtl`.** A name no library defines, or none, is a
//!   [`LoadWarningKind::UnknownMaterial`]; its faces get the default material, as in
//!   tinyobjloader.
//! - **Materials.** Faces before any `usemtl`, and materials without `Kd`/`Ke`, are
//!   [`Material::BLACK`] (ρ = 0, E = 0): the flatland default, and tinyobjloader's diffuse
//!   default. (Blender defaults `Kd` to 0.8; a default reflectance would make every
//!   material-less file a radiosity scene of invented light bounces, while ρ = 0 leaves it a
//!   visibility scene.) A reflectance above [`Material::MAX_REFLECTANCE`] (exporters write
//!   white as `Kd 1`) is clamped to it with a [`LoadWarningKind::ReflectanceClamped`] per
//!   library (value and line of the first). A material's `Ka` is kept: with
//!   [`ObjOptions::emit_from_ka`] it is the emittance of materials without `Ke` (old
//!   exporters and the Cornell box files wrote lamps as `Ka 20 20 20`); without it, when no
//!   material used emits but some have `Ka` > 0 and no `Ke`, the report says so
//!   ([`LoadWarningKind::AmbientOnlyLamps`]). A material defined twice, a property before
//!   any `newmtl`, a negative emittance and malformed `Kd`/`Ke`/`Ka` numbers are errors.
//!
//! Every face is added as drawn by
//! [`Scene3Builder::face_as_drawn`](crate::scene::Scene3Builder::face_as_drawn) (a valid planar
//! convex face unchanged; repeated vertices removed, nearly planar faces flattened, concave or
//! bent ones triangulated, zero-area ones dropped) and cut by the [`Subdivision`] given; the
//! patch cap [`crate::scene::MAX_PATCHES_3D`] is checked before each face's patches are
//! allocated. The scene is finished by
//! [`Scene3Builder::build_as_drawn`](crate::scene::Scene3Builder::build_as_drawn): duplicate
//! faces dropped, partly covered coincident ones cut to what earlier faces leave. All of it
//! is counted in the [`LoadReport`].

use alloc::borrow::Cow;
use alloc::collections::BTreeMap;
use alloc::string::String;
use alloc::vec::Vec;
use core::fmt::Write;

use crate::error::{Error, ErrorKind, MaterialProblem, Result, token};
use crate::geom::DVec3;
use crate::scene::{LoadReport, LoadWarning, LoadWarningKind};
use crate::scene::{MAX_FACE_VERTICES, Material, Scene3, Subdivision};

/// How [`parse_obj`] reads a file.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct ObjOptions {
    /// How every face is cut into patches.
    pub subdivision: Subdivision,
    /// Whether a material without `Ke` emits its ambient colour `Ka` (old-style lamps, e.g.
    /// `Ka 20 20 20`). Off by default: most exporters write `Ka` as an ambient term of
    /// every material (often `Ka 1 1 1`), which is no light.
    pub emit_from_ka: bool,
}

impl Default for ObjOptions {
    /// Faces not subdivided, `Ka` not emitted.
    fn default() -> Self {
        Self::new(Subdivision::None)
    }
}

impl ObjOptions {
    /// Faces cut by `subdivision`, `Ka` not emitted.
    #[must_use]
    pub fn new(subdivision: Subdivision) -> Self {
        Self {
            subdivision,
            emit_from_ka: false,
        }
    }

    /// The same options with [`Self::emit_from_ka`] set to `on`.
    #[must_use]
    pub fn with_emit_from_ka(mut self, on: bool) -> Self {
        self.emit_from_ka = on;
        self
    }
}

/// The statement part of a line: everything before `#`.
fn content(raw: &str) -> &str {
    raw.split('#').next().unwrap_or("")
}

/// The statements of a text, each with the 1-based number of its first line: comments
/// removed, and lines whose statement ends with `\` joined to the next (the backslash and
/// the line break read as one space).
struct Statements<'a> {
    lines: super::text::Lines<'a>,
}

impl<'a> Statements<'a> {
    fn new(text: &'a str) -> Self {
        Self {
            lines: super::text::lines(text),
        }
    }
}

impl<'a> Iterator for Statements<'a> {
    type Item = (u32, Cow<'a, str>);

    fn next(&mut self) -> Option<Self::Item> {
        let (line_no, raw) = self.lines.next()?;
        let first = content(raw);
        let Some(head) = first.trim_end().strip_suffix('\\') else {
            return Some((line_no, Cow::Borrowed(first)));
        };
        // Join continued lines (bounded by the lines left)
        let mut joined = String::from(head);
        joined.push(' ');
        for (_, raw) in self.lines.by_ref() {
            let part = content(raw);
            if let Some(head) = part.trim_end().strip_suffix('\\') {
                joined.push_str(head);
                joined.push(' ');
            } else {
                joined.push_str(part);
                break;
            }
        }
        Some((line_no, Cow::Owned(joined)))
    }
}

/// The OBJ statements of the specification (and the extension `t`) that carry nothing
/// sceneinfo uses: skipped with a [`LoadWarningKind::SkippedStatement`].
#[rustfmt::skip]
const SKIPPED_STATEMENTS: &[&str] = &[
    // free-form curve and surface attributes, elements and body statements
    "cstype", "deg", "bmat", "step", "curv", "curv2", "surf", "parm", "trim", "hole", "scrv",
    "sp", "end",
    // connectivity, grouping, display and render attributes
    "con", "mg", "bevel", "c_interp", "d_interp", "lod", "usemap", "maplib", "shadow_obj",
    "trace_obj", "ctech", "stech",
    // general statements
    "call", "csh",
    // superseded by the version 3.0 specification
    "bsp", "bzp", "cdc", "cdp", "res", "fo",
    // creases, written by some exporters
    "t",
];

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

/// Parses an OBJ scene (module docs give the rules), cutting every face by
/// `options.subdivision`. `mtl(name)` returns the text of the material library `name` named
/// by an `mtllib` line, or `None` if it cannot. Returns the scene and the [`LoadReport`]:
/// the faces read and what was skipped or repaired.
///
/// # Errors
/// The first problem found, with its 1-based OBJ line: [`ErrorKind::BadNumber`],
/// [`ErrorKind::NonFiniteNumber`], [`ErrorKind::MissingField`],
/// [`ErrorKind::TrailingField`], [`ErrorKind::FaceIndex`], [`ErrorKind::InMaterialLibrary`]
/// (at the `mtllib` line, naming the library's own line), and the face errors of
/// [`Scene3Builder::face_as_drawn`](crate::scene::Scene3Builder::face_as_drawn) (vertex count,
/// non-finite or out-of-range coordinates, too many patches) and
/// [`Scene3Builder::build_as_drawn`](crate::scene::Scene3Builder::build_as_drawn);
/// [`ErrorKind::BadSubdivision`] (no line) for a bad subdivision;
/// [`ErrorKind::EmptyScene`] (line of the end of input) if there is no face.
///
/// # Examples
/// ```
/// use sceneinfo::io::{ObjOptions, parse_obj};
/// use sceneinfo::scene::Subdivision;
///
/// let obj = "mtllib box.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nusemtl lamp\nf 1 2 3 4\n";
/// let mtl = |name: &str| (name == "box.mtl").then(|| "newmtl lamp\nKe 10 10 10\n".into());
/// let (scene, report) = parse_obj(obj, &ObjOptions::new(Subdivision::Grid(4)), mtl).unwrap();
/// assert_eq!(scene.n_patches(), 16);
/// assert_eq!(scene.patch_material(0).unwrap().emittance, [10.0; 3]);
/// assert_eq!(report.faces_read, 1);
/// assert!(report.warnings.is_empty());
///
/// // An old-style lamp: Ka and no Ke emits only with emit_from_ka.
/// let mtl = |_: &str| Some("newmtl lamp\nKa 20 20 20\n".into());
/// let options = ObjOptions::default().with_emit_from_ka(true);
/// let (scene, _) = parse_obj(obj, &options, mtl).unwrap();
/// assert_eq!(scene.patch_material(0).unwrap().emittance, [20.0; 3]);
///
/// let err = parse_obj("v 0 0 0\nv 1 0 0\nf 1 2 3\n", &ObjOptions::default(), |_| None);
/// assert_eq!(
///     err.unwrap_err().to_string(),
///     "line 3: vertex index 3 out of range (2 vertices defined so far; 0 is never valid)"
/// );
/// ```
pub fn parse_obj(
    obj: &str,
    options: &ObjOptions,
    mtl: impl Fn(&str) -> Option<String>,
) -> Result<(Scene3, LoadReport)> {
    options.subdivision.validate()?;
    let mut state = ObjState {
        builder: Scene3::builder(),
        vertices: Vec::new(),
        face: Vec::new(),
        materials: BTreeMap::new(),
        libraries: Vec::new(),
        subdivision: options.subdivision,
        emit_from_ka: options.emit_from_ka,
        report: LoadReport::default(),
        emitter_used: false,
        ambient_lamps: BTreeMap::new(),
    };
    // The line after the last one, for a scene without faces
    let last_line = super::text::lines(obj).last().map_or(1, |(n, _)| n);
    // The line of each face, to locate coincident faces found at the end
    let mut face_lines: Vec<u32> = Vec::new();
    for (line_no, statement) in Statements::new(obj) {
        state
            .statement(&statement, line_no, &mtl)
            .map_err(|e| e.with_line(line_no))?;
        face_lines.resize(state.builder.face_count(), line_no);
    }
    state.finish_report();
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

/// One material of a library as sceneinfo uses it.
#[derive(Clone, Copy, Debug)]
struct MtlEntry {
    material: Material,
    /// `Ka` > 0 in some channel and no `Ke` line: an old-style lamp, if `Ka` is read as
    /// emittance.
    ambient_lamp: bool,
}

/// What the OBJ parser keeps between lines.
struct ObjState {
    builder: crate::scene::Scene3Builder,
    vertices: Vec<DVec3>,
    face: Vec<DVec3>,
    materials: BTreeMap<String, MtlEntry>,
    libraries: Vec<String>,
    subdivision: Subdivision,
    emit_from_ka: bool,
    report: LoadReport,
    /// Whether a `usemtl` named an emitting material.
    emitter_used: bool,
    /// The `usemtl` names of old-style lamps (see [`MtlEntry::ambient_lamp`]) with the line
    /// of their first use.
    ambient_lamps: BTreeMap<String, u32>,
}

impl ObjState {
    fn statement(
        &mut self,
        line: &str,
        line_no: u32,
        mtl: &impl Fn(&str) -> Option<String>,
    ) -> Result<()> {
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
                    Some(line_no),
                )?;
            }
            "o" | "g" => {
                // The rest of the line is the name; none means the default object.
                self.builder
                    .object(if rest.is_empty() { "default" } else { rest });
            }
            "s" | "l" | "p" => {}
            "usemtl" => self.use_material(rest, line_no),
            "mtllib" => self.libraries_of_line(rest, line_no, mtl)?,
            other => {
                // Skipped, one warning per keyword (counted)
                let keyword = token(other);
                let kind = if SKIPPED_STATEMENTS.contains(&other) {
                    LoadWarningKind::SkippedStatement { keyword }
                } else {
                    LoadWarningKind::UnknownStatement { keyword }
                };
                self.report.warn(Some(line_no), kind);
            }
        }
        Ok(())
    }

    fn number(&self, s: Option<&str>, field: &'static str) -> Result<f64> {
        parse_number(s.ok_or(ErrorKind::MissingField { field })?, field)
    }

    /// A `usemtl` line: the material of the faces that follow, or the default one with a
    /// warning when no library defines `name`.
    fn use_material(&mut self, name: &str, line_no: u32) {
        match self.materials.get(name) {
            Some(entry) => {
                let entry = *entry;
                self.builder.material(entry.material);
                if entry.material.is_emitter() {
                    self.emitter_used = true;
                }
                if entry.ambient_lamp && !self.ambient_lamps.contains_key(name) {
                    self.ambient_lamps.insert(String::from(name), line_no);
                }
            }
            None => {
                self.builder.material(Material::BLACK);
                self.report.warn(
                    Some(line_no),
                    LoadWarningKind::UnknownMaterial { name: token(name) },
                );
            }
        }
    }

    /// An `mtllib` line: the whole rest of the line as one name first (double quotes
    /// around it removed), then each word as a library of its own.
    fn libraries_of_line(
        &mut self,
        rest: &str,
        line_no: u32,
        mtl: &impl Fn(&str) -> Option<String>,
    ) -> Result<()> {
        let whole = unquote(rest);
        if whole.is_empty() {
            self.report.warn(
                Some(line_no),
                LoadWarningKind::MissingMaterialLibrary { library: token("") },
            );
            return Ok(());
        }
        if self.library(whole, line_no, mtl)? {
            return Ok(());
        }
        let words = rest.split_whitespace();
        if words.clone().nth(1).is_some() {
            for name in words {
                let name = unquote(name);
                if !self.library(name, line_no, mtl)? {
                    self.warn_missing_library(name, line_no);
                }
            }
        } else {
            self.warn_missing_library(whole, line_no);
        }
        Ok(())
    }

    fn warn_missing_library(&mut self, name: &str, line_no: u32) {
        self.report.warn(
            Some(line_no),
            LoadWarningKind::MissingMaterialLibrary {
                library: token(name),
            },
        );
    }

    /// Loads the library `name` (once) into the named materials; false if the caller
    /// cannot provide it.
    fn library(
        &mut self,
        name: &str,
        line_no: u32,
        mtl: &impl Fn(&str) -> Option<String>,
    ) -> Result<bool> {
        if self.libraries.iter().any(|l| l == name) {
            return Ok(true);
        }
        let Some(text) = mtl(name) else {
            return Ok(false);
        };
        let mut library = MtlLibrary {
            name,
            obj_line: line_no,
            emit_from_ka: self.emit_from_ka,
            out: &mut self.materials,
            report: &mut self.report,
        };
        library.parse(&text).map_err(|(line, problem)| {
            Error::from(ErrorKind::InMaterialLibrary {
                library: token(name),
                line,
                problem,
            })
        })?;
        self.libraries.push(String::from(name));
        Ok(true)
    }

    /// Adds the report's end-of-file entries: old-style lamps when nothing emits.
    fn finish_report(&mut self) {
        if self.emitter_used || self.emit_from_ka {
            return;
        }
        // The lamp used first (lowest line), and how many there are
        let first = self.ambient_lamps.iter().min_by_key(|(_, line)| **line);
        if let Some((name, &line)) = first {
            self.report.warnings.push(LoadWarning {
                kind: LoadWarningKind::AmbientOnlyLamps {
                    material: token(name),
                    materials: self.ambient_lamps.len() as u64,
                },
                first_line: Some(line),
                count: 1,
            });
        }
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
}

/// A name without the double quotes around it (Blender's importer removes them too).
fn unquote(name: &str) -> &str {
    name.strip_prefix('"')
        .and_then(|n| n.strip_suffix('"'))
        .unwrap_or(name)
        .trim()
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

/// A material as its `newmtl` block gives it, before it is made a [`Material`]: each
/// colour with the library line that set it.
#[derive(Default)]
struct MtlDraft {
    kd: Option<([f64; 3], u32)>,
    ke: Option<([f64; 3], u32)>,
    ka: Option<([f64; 3], u32)>,
}

/// One MTL library being read into the parser's materials.
struct MtlLibrary<'a> {
    name: &'a str,
    /// The `mtllib` line, where warnings about the library are located.
    obj_line: u32,
    emit_from_ka: bool,
    out: &'a mut BTreeMap<String, MtlEntry>,
    report: &'a mut LoadReport,
}

type MtlResult<T> = core::result::Result<T, (u32, MaterialProblem)>;

impl MtlLibrary<'_> {
    /// Parses the library; errors carry its 1-based line.
    fn parse(&mut self, text: &str) -> MtlResult<()> {
        let mut current: Option<(String, MtlDraft)> = None;
        for (line_no, line) in Statements::new(text) {
            let mut fields = line.split_whitespace();
            let Some(keyword) = fields.next() else {
                continue;
            };
            let field = match keyword {
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
                    if self.out.contains_key(name)
                        || current.as_ref().is_some_and(|(n, _)| n == name)
                    {
                        return Err((line_no, MaterialProblem::DuplicateMaterial));
                    }
                    if let Some((done, draft)) = current.take() {
                        self.finish(done, &draft)?;
                    }
                    current = Some((String::from(name), MtlDraft::default()));
                    continue;
                }
                "Kd" => "Kd",
                "Ke" => "Ke",
                "Ka" => "Ka",
                // Everything else (Ks, Ns, Ni, d, Tr, Tf, illum, maps, PBR, …) is skipped
                _ => continue,
            };
            let (_, draft) = current
                .as_mut()
                .ok_or((line_no, MaterialProblem::NoCurrentMaterial))?;
            let rgb = mtl_rgb(fields, field).map_err(|p| (line_no, p))?;
            let slot = match field {
                "Kd" => &mut draft.kd,
                "Ke" => &mut draft.ke,
                _ => &mut draft.ka,
            };
            *slot = Some((rgb, line_no));
        }
        if let Some((done, draft)) = current.take() {
            self.finish(done, &draft)?;
        }
        Ok(())
    }

    /// Makes the material `name` of its draft: ρ = Kd (clamped, with a warning), E = Ke, or
    /// Ka with `emit_from_ka` when there is no Ke.
    fn finish(&mut self, name: String, draft: &MtlDraft) -> MtlResult<()> {
        let (rho, kd_line) = draft.kd.unwrap_or(([0.0; 3], 0));
        let ambient_lamp =
            draft.ke.is_none() && draft.ka.is_some_and(|(ka, _)| ka.iter().any(|&a| a > 0.0));
        let emission = match (draft.ke, draft.ka) {
            (Some(ke), _) => Some(ke),
            (None, Some(ka)) if self.emit_from_ka => Some(ka),
            _ => None,
        };
        let (emit, emit_line) = emission.unwrap_or(([0.0; 3], 0));
        let (material, clamped) = Material::clamped(rho, emit).map_err(|e| match *e.kind() {
            ErrorKind::Reflectance { value } => (kd_line, MaterialProblem::Reflectance { value }),
            ErrorKind::Emittance { value } => (emit_line, MaterialProblem::Emittance { value }),
            ErrorKind::EmittanceTooLarge { value, max } => {
                (emit_line, MaterialProblem::EmittanceTooLarge { value, max })
            }
            _ => (kd_line, MaterialProblem::NonFiniteNumber { field: "Kd" }),
        })?;
        if clamped {
            let value = rho.iter().copied().fold(f64::MIN, f64::max);
            self.warn_clamped(kd_line, value);
        }
        self.out.insert(
            name,
            MtlEntry {
                material,
                ambient_lamp,
            },
        );
        Ok(())
    }

    /// One clamped reflectance: the library's entry counts one more, or a new one names
    /// this value and line.
    fn warn_clamped(&mut self, line: u32, value: f64) {
        let library = token(self.name);
        let existing = self.report.warnings.iter_mut().find(|w| {
            matches!(&w.kind, LoadWarningKind::ReflectanceClamped { library: l, .. } if *l == library)
        });
        match existing {
            Some(w) => w.count = w.count.saturating_add(1),
            None => self.report.warnings.push(LoadWarning {
                kind: LoadWarningKind::ReflectanceClamped {
                    library,
                    line,
                    value,
                },
                first_line: Some(self.obj_line),
                count: 1,
            }),
        }
    }
}

/// `r [g b]` of a `Kd`/`Ke`/`Ka` line (one value means grey).
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
/// ([`Subdivision::None`]) `parse_obj(obj, &ObjOptions::default(), …)` gives back the same scene
/// bit for bit (object names as the parser makes them: trimmed, no `#`).
#[must_use]
pub fn write_obj(scene: &Scene3, mtl_name: &str) -> (String, String) {
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
                let v = scene.frame().to_world(*v);
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
