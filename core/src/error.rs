//! The crate's one error type.
//!
//! Every fallible constructor and parser returns [`Error`]: an [`ErrorKind`] saying what was
//! wrong and, for text input, the 1-based line where it was found. The type needs no
//! allocator: offending tokens are kept in a fixed-capacity `Token`.

use core::fmt;

/// Capacity, in bytes, of a [`Token`] quoted in an error message.
pub(crate) const TOKEN_CAPACITY: usize = 32;

/// A short excerpt of the input quoted in an error message: control and invisible
/// characters escaped (see [`token`]), truncated to [`TOKEN_CAPACITY`] bytes between two
/// characters, with `…` appended when cut.
pub(crate) type Token = heapless::String<TOKEN_CAPACITY>;

impl ErrorKind {
    /// Builds a `Token` from arbitrary text, safe to print on a terminal.
    ///
    /// Control characters (ESC, NUL, CR, …) and the invisible format characters that hide or
    /// reorder text (byte-order mark, zero-width spaces and joiners, bidirectional overrides)
    /// are written as Rust's `char::escape_debug` writes them (`\u{1b}`, `\0`, `\r`,
    /// `\u{feff}`); every other character, `é` included, is kept. Text longer than
    /// `TOKEN_CAPACITY` bytes (escapes counted) is cut between two characters, never inside
    /// one or inside an escape, and ends with `…`.
    ///
    /// # Examples
    /// ```
    /// use sceneinfo::ErrorKind;
    /// assert_eq!(ErrorKind::token("caf\u{e9}\u{1b}[31m").as_str(), "café\\u{1b}[31m");
    /// assert_eq!(ErrorKind::token("\u{feff}mat").as_str(), "\\u{feff}mat");
    /// ```
    #[must_use]
    pub fn token(text: &str) -> Token {
        /// Appends one character of `text`, escaped when it must be; `false` (and nothing
        /// appended) when it would pass `limit` bytes.
        fn push(t: &mut Token, c: char, limit: usize) -> bool {
            let mut piece = heapless::String::<16>::new();
            if must_escape(c) {
                for e in c.escape_debug() {
                    let _ = piece.push(e);
                }
            } else {
                let _ = piece.push(c);
            }
            if t.len() + piece.len() > limit {
                return false;
            }
            t.push_str(&piece).is_ok()
        }
        let mut t = Token::new();
        // Whole, when it fits
        if text.chars().all(|c| push(&mut t, c, TOKEN_CAPACITY)) {
            return t;
        }
        // Else as much as leaves room for the ellipsis
        let ellipsis = '…';
        let room = TOKEN_CAPACITY - ellipsis.len_utf8();
        t.clear();
        for c in text.chars() {
            if !push(&mut t, c, room) {
                break;
            }
        }
        let _ = t.push(ellipsis);
        t
    }
}

/// [`ErrorKind::token`], for the crate's own errors.
pub(crate) fn token(text: &str) -> Token {
    ErrorKind::token(text)
}

/// Whether [`ErrorKind::token`] escapes `c`: a control character, or a format character that is
/// invisible or reorders the text around it.
fn must_escape(c: char) -> bool {
    c.is_control()
        || matches!(
            c,
            '\u{ad}'
                | '\u{200b}'..='\u{200f}'
                | '\u{2028}'..='\u{202e}'
                | '\u{2060}'..='\u{2069}'
                | '\u{feff}'
        )
}

/// What went wrong. Marked `#[non_exhaustive]`: later versions add variants.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum ErrorKind {
    // ---- text formats -------------------------------------------------------------------
    /// A line starts with a keyword the format does not know.
    UnknownKeyword(Token),
    /// A field that must be a number is not one.
    BadNumber {
        /// The field's name, e.g. `"x0"`.
        field: &'static str,
        /// The text found there.
        found: Token,
    },
    /// A number is NaN or infinite.
    NonFiniteNumber {
        /// The field's name.
        field: &'static str,
    },
    /// A field that must be a positive integer is not one.
    BadCount {
        /// The field's name, e.g. `"n"`.
        field: &'static str,
        /// The text found there.
        found: Token,
    },
    /// A required field is missing at the end of a line.
    MissingField {
        /// The field's name.
        field: &'static str,
    },
    /// A line has more fields than its item takes.
    TrailingField(Token),
    /// The input is not valid UTF-8.
    InvalidUtf8,
    /// An OBJ face refers to vertex 0 or to a vertex beyond those defined so far.
    FaceIndex {
        /// The index as written (negative indices count back from the last vertex).
        index: i64,
        /// The number of vertices defined before the face.
        count: usize,
    },
    /// An OBJ `usemtl` names a material no loaded MTL library defines.
    MissingMaterial(Token),
    /// An OBJ `mtllib` names a library the caller could not provide.
    MissingMaterialLibrary(Token),
    /// A problem inside an MTL material library; the error's own line is that of the OBJ's
    /// `mtllib` directive.
    InMaterialLibrary {
        /// The library's name as written after `mtllib`.
        library: Token,
        /// The 1-based line inside the library.
        line: u32,
        /// What was wrong there.
        problem: MaterialProblem,
    },

    // ---- geometry and scenes ------------------------------------------------------------
    /// A segment's two endpoints coincide (or are closer than the scene can resolve).
    ZeroLengthSegment,
    /// A polygon has fewer than three vertices or too many.
    PolygonVertexCount {
        /// The number of vertices given.
        given: u64,
    },
    /// A count of patches is zero or beyond the cap.
    PatchCount {
        /// The count given.
        given: u64,
        /// The largest count accepted.
        max: u64,
    },
    /// The whole scene would have more patches than the cap allows.
    TooManyPatches {
        /// The cap.
        max: u64,
    },
    /// A reflectance is outside `[0, 1)`.
    Reflectance {
        /// The offending value.
        value: f64,
    },
    /// An emittance is negative.
    Emittance {
        /// The offending value.
        value: f64,
    },
    /// An emittance exceeds the cap (`scene::Material::MAX_EMITTANCE`): radiosities, powers
    /// and their squares would overflow.
    EmittanceTooLarge {
        /// The offending value.
        value: f64,
        /// The cap (carried, so this module depends on nothing above it).
        max: f64,
    },
    /// A scene has no patches.
    EmptyScene,
    /// Explicit cut positions along a segment are not strictly increasing inside (0, 1).
    BadCuts,
    /// A face given as arrays refers to a vertex past the end of the vertex array
    /// ([`crate::Scene::from_polygons`]; indices count from 0).
    VertexIndex {
        /// The index given.
        index: u64,
        /// The number of vertices.
        count: usize,
    },
    /// A patch index is out of range.
    PatchIndex {
        /// The index given.
        index: usize,
        /// The number of patches.
        len: usize,
    },
    /// A coordinate beyond `crate::geom::MAX_COORDINATE` (lengths, areas and the
    /// exact form factors' tolerances need room below `f64`'s range).
    CoordinateRange,
    /// Two surfaces (flatland segments, or 3D faces) lie on one line or plane, face the
    /// same way and overlap: two surfaces in one place (see `scene::coincident`). Indices
    /// are the surfaces' (segments', faces') in input order.
    CoincidentSurfaces {
        /// The earlier surface.
        first: usize,
        /// The later surface.
        second: usize,
    },
    /// [`ErrorKind::CoincidentSurfaces`] as a parser reports it: the surface on the
    /// error's line coincides with the surface on line `other_line`, or (`None`) with
    /// another side of the polygon on the same line.
    CoincidentWith {
        /// The line of the earlier surface; `None` when it is the same line.
        other_line: Option<u32>,
    },
    /// A preset scene name that the catalogue does not know.
    UnknownPreset(Token),
    /// A 3D face's vertices do not lie in one plane (beyond 10⁻⁶ of its size).
    NonPlanarFace {
        /// The largest distance of a vertex from the face's (Newell) plane.
        deviation: f64,
    },
    /// A 3D face is not convex (a reflex turn, or a self-intersecting star).
    NonConvexFace,
    /// A 3D face has zero area for its size, or a zero-length edge.
    DegenerateFace,
    /// A 3D face has fewer than three vertices or more than the cap.
    FaceVertexCount {
        /// The number of vertices given.
        given: u64,
        /// The most accepted.
        max: u64,
    },
    /// A subdivision parameter is out of range: a grid needs 1 to `max` cells a side, a
    /// triangle subdivision 0 to `max` levels.
    BadSubdivision {
        /// The parameter given.
        given: u64,
        /// The largest accepted.
        max: u64,
    },

    // ---- channels -----------------------------------------------------------------------
    /// Two inputs that must have matching sizes do not.
    DimensionMismatch {
        /// The size required.
        expected: usize,
        /// The size given.
        found: usize,
    },
    /// A probability or matrix entry is NaN or infinite.
    NonFiniteEntry {
        /// Row of the entry (the index, for vectors).
        row: usize,
        /// Column of the entry (0 for vectors).
        col: usize,
    },
    /// A probability or matrix entry is negative.
    NegativeEntry {
        /// Row of the entry (the index, for vectors).
        row: usize,
        /// Column of the entry (0 for vectors).
        col: usize,
    },
    /// A distribution does not sum to one.
    NotNormalized {
        /// Its sum.
        sum: f64,
    },
    /// A row of a transition matrix sums to more than one.
    RowSumAboveOne {
        /// The row.
        row: usize,
        /// Its sum.
        sum: f64,
    },
    /// Exact form factors whose rows sum above one beyond rounding: the scene's extent is
    /// too large beside its smallest feature for `f64` (the units do not matter: scenes
    /// are stored at a moderate scale, `scene::Frame`).
    PrecisionLoss {
        /// The patch whose row overflows.
        patch: usize,
        /// Its row sum.
        sum: f64,
        /// The scene's extent (bounding-box diagonal) over its smallest feature: its shortest
        /// patch, or the closest approach of a surface's end to another surface.
        range: f64,
        /// The range up to which exact results are guaranteed (carried here so the error
        /// module depends on nothing above it).
        guaranteed: f64,
    },
    /// `P_ij > 0` towards a state of zero probability, so `p log(p/0)` is undefined.
    TransitionToNullState {
        /// Source state.
        row: usize,
        /// Target state, whose probability is zero.
        col: usize,
    },
    /// A sparse matrix's structure is malformed (row pointers or column indices).
    MalformedSparse,
    /// A caller-provided buffer is too small.
    BufferTooSmall {
        /// Length needed.
        needed: usize,
        /// Length given.
        found: usize,
    },
    /// A requested size exceeds a documented cap (e.g. path enumeration).
    TooLarge {
        /// What was too large.
        what: &'static str,
        /// The cap.
        max: u64,
    },
    /// Some polygon of a 3D scene may hide part of another, so a computation that assumes
    /// full visibility (exact form factors, the `I_S^c` quadrature) does not apply.
    MayBeOccluded,
    /// A computation produced a NaN or an infinity (its values overflowed `f64`); names the
    /// computation, never a bare "sums to NaN".
    NotFinite {
        /// The computation.
        what: &'static str,
    },
    /// An iteration did not converge within its cap.
    NoConvergence {
        /// What was iterated.
        what: &'static str,
        /// Iterations spent.
        iterations: u64,
    },

    // ---- Monte Carlo ----------------------------------------------------------------------
    /// A line budget of zero.
    NoLines,
    /// A patch received no line sample, so its form-factor row is unknown.
    UnsampledPatch {
        /// The patch.
        patch: usize,
        /// Lines cast.
        lines: u64,
    },
    /// Some patches received no line, so their rows of `F` are unknown and a computation
    /// that needs every row (the radiosity system) cannot run.
    RowsUnknown {
        /// Patches that received no line.
        unsampled: usize,
        /// Patches of the scene.
        n_patches: usize,
        /// Lines cast.
        lines: u64,
        /// About how many lines would reach every patch, when the lines gave a hit rate.
        lines_to_sample_all: Option<u64>,
    },
    /// The caller's executor stopped a line job before it finished, and the computation
    /// needs the whole job (the caller asked to stop: nothing is reported).
    Stopped,
    /// A partial-result file is damaged or not one.
    BadPartial {
        /// What is wrong with it.
        what: &'static str,
    },
    /// A partial-result file of a layout version this build does not read.
    PartialVersion {
        /// The version in the file.
        found: u32,
        /// The version this build reads.
        supported: u32,
    },
    /// Two partial results come from different jobs.
    PartialMismatch {
        /// What differs: `scene`, `method`, `seed`, `lines` or `patches`.
        field: &'static str,
    },
    /// Two partial results overlap or leave chunks between them.
    ChunkRanges {
        /// The chunks merged so far.
        first: core::ops::Range<u64>,
        /// The next partial's chunks (by first chunk).
        second: core::ops::Range<u64>,
    },
    /// Partial results do not cover the whole job.
    MissingChunks {
        /// The chunks present.
        have: core::ops::Range<u64>,
        /// The job's number of chunks.
        total: u64,
    },
    /// Two partial results of exact rows overlap or leave rows between them.
    RowRanges {
        /// The rows merged so far.
        first: core::ops::Range<u64>,
        /// The next partial's rows (by first row).
        second: core::ops::Range<u64>,
    },
    /// Partial results of exact rows do not cover the whole job.
    MissingRows {
        /// The rows present.
        have: core::ops::Range<u64>,
        /// The job's number of rows (patches).
        total: u64,
    },

    /// A job would need more memory than the caller allows (`--max-memory`).
    MemoryLimit {
        /// What needs it, e.g. `"exact form factors"`.
        what: &'static str,
        /// Bytes needed (a lower bound).
        needed: u64,
        /// Bytes allowed.
        limit: u64,
    },

    /// Lines of this method cannot serve the job (bundles of parallel lines are not for
    /// radiosity).
    UnsupportedMethod {
        /// The method's description, e.g. `"bundles of parallel lines"`.
        method: &'static str,
        /// Why, e.g. `"this kind of scene cannot cast them"`.
        reason: &'static str,
    },

    // ---- solvers --------------------------------------------------------------------------
    /// A numeric parameter (e.g. a solver tolerance) is NaN, infinite or out of range.
    BadParameter {
        /// The parameter's name.
        name: &'static str,
        /// The value given.
        value: f64,
    },

    // ---- refinement -----------------------------------------------------------------------
    /// A state split breaks a condition of Proposition 3 (thesis §5.4.1), so its gain in
    /// mutual information is not computed.
    InvalidSplit {
        /// The condition, e.g. `"(b) cover P_ji = sum_k P_j,ik"`.
        condition: &'static str,
        /// The state (or sub-state) index where it fails.
        index: usize,
        /// By how much it fails (or the offending value).
        deviation: f64,
    },

    // ---- hierarchical radiosity -----------------------------------------------------------
    /// A refinement oracle's name is not known.
    UnknownOracle(Token),
    /// A reference solution's polygon lies on no element of the scene compared with it.
    ReferenceOffScene {
        /// Index of the reference polygon.
        polygon: usize,
    },
}

impl fmt::Display for ErrorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        use ErrorKind as K;
        match self {
            K::UnknownKeyword(t) => write!(f, "unknown keyword '{t}'"),
            K::BadNumber { field, found } => write!(f, "{field}: '{found}' is not a number"),
            K::NonFiniteNumber { field } => write!(
                f,
                "{field}: number is NaN, infinite or beyond the range of f64"
            ),
            K::BadCount { field, found } => {
                write!(f, "{field}: '{found}' is not a positive integer")
            }
            K::MissingField { field } => write!(f, "missing field {field}"),
            K::TrailingField(t) => write!(f, "unexpected extra field '{t}'"),
            K::InvalidUtf8 => write!(f, "input is not valid UTF-8"),
            K::FaceIndex { index, count } => write!(
                f,
                "vertex index {index} out of range ({count} vertices defined so far; 0 is never valid)"
            ),
            K::MissingMaterial(t) => write!(f, "material '{t}' is not defined by any mtllib"),
            K::MissingMaterialLibrary(t) => write!(f, "material library '{t}' was not provided"),
            K::InMaterialLibrary {
                library,
                line,
                problem,
            } => write!(f, "material library '{library}' line {line}: {problem}"),
            K::ZeroLengthSegment => write!(f, "segment has zero length"),
            K::PolygonVertexCount { given } => {
                write!(
                    f,
                    "polygon needs at least 3 vertices (and at most 100000), got {given}"
                )
            }
            K::PatchCount { given, max } if *given == u64::MAX => write!(
                f,
                "patch count {given} or more is out of range (1 to {max})"
            ),
            K::PatchCount { given, max } => {
                write!(f, "patch count {given} is out of range (1 to {max})")
            }
            K::TooManyPatches { max } => write!(f, "scene has more than {max} patches"),
            K::Reflectance { value } => write!(f, "reflectance {value} is outside [0, 1)"),
            K::Emittance { value } => write!(f, "emittance {value} is negative"),
            K::EmittanceTooLarge { value, max } => write_emittance_too_large(f, *value, *max),
            K::EmptyScene => write!(f, "scene has no patches"),
            K::BadCuts => write!(f, "cut positions must increase strictly inside (0, 1)"),
            K::VertexIndex { index, count } => write!(
                f,
                "vertex index {index} out of range ({count} vertices, counted from 0)"
            ),
            K::PatchIndex { index, len } => {
                write!(
                    f,
                    "patch index {index} out of range (scene has {len} patches)"
                )
            }
            K::CoordinateRange => write!(
                f,
                "coordinate too large: every coordinate must lie within ±{:e}",
                crate::geom::MAX_COORDINATE
            ),
            K::CoincidentSurfaces { first, second } => write!(
                f,
                "surfaces {first} and {second} coincide: same line or plane, same facing, \
                 overlapping (reverse one of them for a two-sided wall)"
            ),
            K::CoincidentWith {
                other_line: Some(other),
            } => write!(
                f,
                "coincides with a surface of line {other}: same line or plane, same \
                 facing, overlapping (reverse one of them for a two-sided wall)"
            ),
            K::CoincidentWith { other_line: None } => write!(
                f,
                "two sides of this polygon coincide: same line, same facing, overlapping"
            ),
            K::UnknownPreset(t) => write!(f, "unknown preset scene '{t}'"),
            K::NonPlanarFace { deviation } => write!(
                f,
                "face is not planar: a vertex lies {deviation} from its plane (tolerance 1e-6 × its size)"
            ),
            K::NonConvexFace => write!(f, "face is not convex"),
            K::DegenerateFace => write!(f, "face is degenerate (zero area or a zero-length edge)"),
            K::FaceVertexCount { given, max } => {
                write!(f, "face needs 3 to {max} vertices, got {given}")
            }
            K::BadSubdivision { given, max } => write!(
                f,
                "subdivision parameter {given} is out of range (at most {max}; a grid needs at least 1)"
            ),
            K::DimensionMismatch { expected, found } => {
                write!(f, "size mismatch: expected {expected}, found {found}")
            }
            K::NonFiniteEntry { row, col } => write!(f, "entry ({row}, {col}) is NaN or infinite"),
            K::NegativeEntry { row, col } => write!(f, "entry ({row}, {col}) is negative"),
            K::NotNormalized { sum } => write!(f, "distribution sums to {sum}, not 1"),
            K::RowSumAboveOne { row, sum } => write!(f, "row {row} sums to {sum} > 1"),
            K::PrecisionLoss {
                patch,
                sum,
                range,
                guaranteed,
            } => write!(
                f,
                "exact form factors of patch {patch} sum to {sum} > 1: rounding in this scene's \
                 geometry exceeds double precision (it spans {range:.2e} times its smallest \
                 feature, a patch or the gap between a surface's end and another surface; \
                 exact results are guaranteed up to {guaranteed:.0e}); split the scene, or \
                 estimate with --lines"
            ),
            K::TransitionToNullState { row, col } => write!(
                f,
                "transition {row} -> {col} is positive but state {col} has probability 0"
            ),
            K::MalformedSparse => write!(f, "sparse matrix structure is malformed"),
            K::BufferTooSmall { needed, found } => {
                write!(f, "buffer too small: need {needed}, got {found}")
            }
            K::TooLarge { what, max } => write!(f, "{what} exceeds the cap of {max}"),
            K::MayBeOccluded => write!(
                f,
                "some polygon may hide part of another: this needs an unoccluded scene (use line estimates, e.g. --lines N)"
            ),
            K::NotFinite { what } => {
                write!(f, "{what}: not finite (the scene's values overflow f64)")
            }
            K::NoConvergence { what, iterations } => {
                write!(f, "{what} did not converge in {iterations} iterations")
            }
            K::NoLines => write!(f, "the line budget must be at least 1"),
            K::UnsampledPatch { patch, lines } => write!(
                f,
                "patch {patch} received none of the {lines} lines: cast more lines"
            ),
            K::RowsUnknown {
                unsampled,
                n_patches,
                lines,
                lines_to_sample_all,
            } => {
                write!(
                    f,
                    "{unsampled} of the {n_patches} patches received none of the {lines} lines, \
                     so their rows of F are unknown; "
                )?;
                match lines_to_sample_all {
                    Some(m) => write!(f, "about {m} lines would reach every patch"),
                    None => write!(f, "cast more lines"),
                }
            }
            K::Stopped => write!(f, "the line job was stopped before it finished"),
            K::MemoryLimit {
                what,
                needed,
                limit,
            } => write!(
                f,
                "{what} need at least {needed} bytes ({:.1} MiB), more than the {limit} bytes \
                 ({:.1} MiB) allowed",
                *needed as f64 / 1048576.0,
                *limit as f64 / 1048576.0
            ),
            K::BadPartial { what } => write!(f, "bad partial-result file: {what}"),
            K::PartialVersion { found, supported } => write!(
                f,
                "partial-result file has layout version {found}; this build reads version {supported}"
            ),
            K::PartialMismatch { field } => write!(
                f,
                "partial results come from different jobs: their {field} differs"
            ),
            K::ChunkRanges { first, second } => {
                if second.start < first.end {
                    write!(
                        f,
                        "partial results overlap: chunks {}..{} and {}..{}",
                        first.start, first.end, second.start, second.end
                    )
                } else {
                    write!(
                        f,
                        "chunks {}..{} are in no partial result (between {}..{} and {}..{})",
                        first.end, second.start, first.start, first.end, second.start, second.end
                    )
                }
            }
            K::MissingChunks { have, total } => write!(
                f,
                "partial results cover chunks {}..{} of the job's 0..{total}: compute the rest \
                 (measure --chunks A..B --partial) before merging",
                have.start, have.end
            ),
            K::RowRanges { first, second } => {
                if second.start < first.end {
                    write!(
                        f,
                        "partial results overlap: rows {}..{} and {}..{}",
                        first.start, first.end, second.start, second.end
                    )
                } else {
                    write!(
                        f,
                        "rows {}..{} are in no partial result (between {}..{} and {}..{})",
                        first.end, second.start, first.start, first.end, second.start, second.end
                    )
                }
            }
            K::MissingRows { have, total } => write!(
                f,
                "partial results cover rows {}..{} of the job's 0..{total}: compute the rest \
                 (formfactors --rows A..B --partial) before merging",
                have.start, have.end
            ),
            K::UnsupportedMethod { method, reason } => {
                write!(f, "{method} cannot be used here: {reason}")
            }
            K::BadParameter { name, value } => {
                write!(f, "parameter {name} = {value} is out of range")
            }
            K::InvalidSplit {
                condition,
                index,
                deviation,
            } => write!(
                f,
                "state split violates Proposition 3's condition '{condition}' at index {index} (off by {deviation})"
            ),
            K::UnknownOracle(t) => write!(
                f,
                "unknown oracle '{t}' (power, ks, ks-av, mi, mi-increase or regular)"
            ),
            K::ReferenceOffScene { polygon } => write!(
                f,
                "reference polygon {polygon} lies on no surface of the scene: the reference \
                 is of another scene"
            ),
        }
    }
}

/// The crate's error: what went wrong, and for text input, on which line.
#[derive(Clone, Debug, PartialEq)]
pub struct Error {
    kind: ErrorKind,
    line: Option<u32>,
}

impl Error {
    /// An error without a location.
    #[must_use]
    pub const fn new(kind: ErrorKind) -> Self {
        Self { kind, line: None }
    }

    /// An error found on 1-based `line` of a text input.
    #[must_use]
    pub const fn at_line(kind: ErrorKind, line: u32) -> Self {
        Self {
            kind,
            line: Some(line),
        }
    }

    /// Attaches a 1-based line number (keeps an existing one).
    #[must_use]
    pub fn with_line(mut self, line: u32) -> Self {
        if self.line.is_none() {
            self.line = Some(line);
        }
        self
    }

    /// What went wrong.
    #[must_use]
    pub fn kind(&self) -> &ErrorKind {
        &self.kind
    }

    /// The 1-based line of the input where the error was found, if it came from text.
    #[must_use]
    pub fn line(&self) -> Option<u32> {
        self.line
    }
}

impl From<ErrorKind> for Error {
    fn from(kind: ErrorKind) -> Self {
        Self::new(kind)
    }
}

impl fmt::Display for Error {
    /// `line N: what` for text input, `what` otherwise. Front ends prefix the file name,
    /// giving `file:N: what`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line {
            Some(line) => write!(f, "line {line}: {}", self.kind),
            None => write!(f, "{}", self.kind),
        }
    }
}

impl core::error::Error for Error {}

/// The message of [`ErrorKind::EmittanceTooLarge`] and [`MaterialProblem::EmittanceTooLarge`]:
/// the value in exponent form (`1e308`, not 309 digits).
fn write_emittance_too_large(f: &mut fmt::Formatter<'_>, value: f64, max: f64) -> fmt::Result {
    write!(
        f,
        "emittance {value:e} is too large: at most {max:e}, so that radiosities, powers and \
         their squares stay finite"
    )
}

/// Shorthand for `core::result::Result<T, Error>`.
pub type Result<T> = core::result::Result<T, Error>;

/// What was wrong inside an MTL material library ([`ErrorKind::InMaterialLibrary`]).
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum MaterialProblem {
    /// A field that must be a number is not one.
    BadNumber {
        /// The field's name, e.g. `"Kd"`.
        field: &'static str,
    },
    /// A number is NaN or infinite.
    NonFiniteNumber {
        /// The field's name.
        field: &'static str,
    },
    /// A required field is missing at the end of a line.
    MissingField {
        /// The field's name.
        field: &'static str,
    },
    /// A line has more fields than its statement takes.
    TrailingField,
    /// A reflectance (`Kd`) is outside `[0, 1)`.
    Reflectance {
        /// The offending value.
        value: f64,
    },
    /// An emittance (`Ke`) is negative.
    Emittance {
        /// The offending value.
        value: f64,
    },
    /// An emittance (`Ke`) exceeds the cap (`scene::Material::MAX_EMITTANCE`).
    EmittanceTooLarge {
        /// The offending value.
        value: f64,
        /// The cap.
        max: f64,
    },
    /// A property (`Kd`, `Ke`) comes before any `newmtl`.
    NoCurrentMaterial,
    /// A `newmtl` name is defined twice.
    DuplicateMaterial,
}

impl fmt::Display for MaterialProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        use MaterialProblem as P;
        match self {
            P::BadNumber { field } => write!(f, "{field}: not a number"),
            P::NonFiniteNumber { field } => {
                write!(
                    f,
                    "{field}: number is NaN, infinite or beyond the range of f64"
                )
            }
            P::MissingField { field } => write!(f, "missing field {field}"),
            P::TrailingField => write!(f, "unexpected extra field"),
            P::Reflectance { value } => write!(f, "reflectance {value} is outside [0, 1)"),
            P::Emittance { value } => write!(f, "emittance {value} is negative"),
            P::EmittanceTooLarge { value, max } => write_emittance_too_large(f, *value, *max),
            P::NoCurrentMaterial => write!(f, "property before any newmtl"),
            P::DuplicateMaterial => write!(f, "material defined twice"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn token_truncates_at_char_boundary() {
        let long = "ééééééééééééééééééééééééééééé"; // 29 two-byte chars
        let t = token(long);
        assert!(t.len() <= TOKEN_CAPACITY);
        assert!(t.ends_with('…'));
        assert_eq!(token("abc").as_str(), "abc");
    }

    #[test]
    fn token_escapes_control_and_invisible_characters_only() {
        assert_eq!(token("a\u{1b}[2Jb").as_str(), "a\\u{1b}[2Jb");
        assert_eq!(token("n\0ul\r\t").as_str(), "n\\0ul\\r\\t");
        assert_eq!(token("\u{7f}\u{9b}").as_str(), "\\u{7f}\\u{9b}");
        assert_eq!(token("\u{feff}mat").as_str(), "\\u{feff}mat");
        assert_eq!(token("x\u{202e}y\u{200b}").as_str(), "x\\u{202e}y\\u{200b}");
        // Letters, quotes and backslashes stay as they are.
        assert_eq!(token("béton 'a' \\ 漢").as_str(), "béton 'a' \\ 漢");
    }

    #[test]
    fn token_escapes_count_toward_the_capacity_and_are_never_cut() {
        // 31 bytes whole: fits.
        let t = token("\u{1b}\u{1b}\u{1b}\u{1b}\u{1b}ab");
        assert_eq!(t.as_str(), "\\u{1b}\\u{1b}\\u{1b}\\u{1b}\\u{1b}ab");
        // Six escapes are 36 bytes: four and the ellipsis (24 + 3 bytes; a fifth would
        // pass the 29 bytes left for the text).
        let t = token("\u{1b}\u{1b}\u{1b}\u{1b}\u{1b}\u{1b}");
        assert_eq!(t.as_str(), "\\u{1b}\\u{1b}\\u{1b}\\u{1b}…");
        for text in ["\0".repeat(40), "é\u{1b}".repeat(9), "\u{feff}".repeat(5)] {
            let t = token(&text);
            assert!(t.len() <= TOKEN_CAPACITY, "{t}");
            assert!(t.ends_with('…'), "{t}");
            assert!(!t.contains('\u{1b}') && !t.contains('\0') && !t.contains('\u{feff}'));
        }
    }

    #[test]
    fn messages_quote_escaped_tokens() {
        let e = Error::at_line(ErrorKind::UnknownKeyword(token("\u{1b}]0;x\u{7}seg")), 3);
        assert_eq!(
            alloc_free_display(&e),
            "line 3: unknown keyword '\\u{1b}]0;x\\u{7}seg'"
        );
    }

    #[test]
    fn display_names_line() {
        let e = Error::at_line(ErrorKind::ZeroLengthSegment, 7);
        assert_eq!(alloc_free_display(&e), "line 7: segment has zero length");
    }

    fn alloc_free_display(e: &Error) -> heapless::String<128> {
        use core::fmt::Write;
        let mut s = heapless::String::<128>::new();
        write!(s, "{e}").unwrap();
        s
    }
}
