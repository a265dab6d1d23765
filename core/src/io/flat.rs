//! The flatland text format.
//!
//! UTF-8, one item per line, `#` starts a comment that runs to the end of the line, fields
//! separated by whitespace:
//!
//! ```text
//! seg x0 y0 x1 y1 [n]                   # segment a → b (faces its left) cut into n patches
//! seg x0 y0 x1 y1 cuts t1 t2 …          # … or cut at parameters 0 < t1 < t2 < … < 1
//! poly n x0 y0 x1 y1 … [per_side k]     # closed polygon of n vertices, k patches per side
//! mat rho R G B [emit R G B]            # material of the items that follow
//! mat emit R G B [rho R G B]
//! ```
//!
//! A `mat` line defines a whole new material: a clause it omits is zero. Reflectances must
//! lie in `[0, 1)`, emittances be `≥ 0`. Counts `n` and `k` must be between 1 and
//! [`crate::scene::MAX_PATCHES_PER_SURFACE`], and the scene at most
//! [`crate::scene::MAX_PATCHES`] patches — checked before anything is allocated.

use alloc::string::String;
use alloc::vec::Vec;
use core::fmt::Write;

use crate::error::{Error, ErrorKind, Result, token};
use crate::geom::DVec2;
use crate::scene::{MAX_PATCHES_PER_SURFACE, Material, Scene2, Scene2Builder};

/// Most vertices a `poly` line may list.
pub(crate) const MAX_POLYGON_VERTICES: u64 = 100_000;

/// The fields of one line, consumed left to right.
struct Fields<'a> {
    iter: core::str::SplitWhitespace<'a>,
}

impl<'a> Fields<'a> {
    fn next(&mut self) -> Option<&'a str> {
        self.iter.next()
    }

    fn number(&mut self, field: &'static str) -> Result<f64> {
        let s = self.next().ok_or(ErrorKind::MissingField { field })?;
        parse_number(s, field)
    }

    fn point(&mut self, fx: &'static str, fy: &'static str) -> Result<DVec2> {
        Ok(DVec2::new(self.number(fx)?, self.number(fy)?))
    }

    fn rgb(&mut self, field: &'static str) -> Result<[f64; 3]> {
        Ok([
            self.number(field)?,
            self.number(field)?,
            self.number(field)?,
        ])
    }

    fn finish(&mut self) -> Result<()> {
        match self.next() {
            Some(extra) => Err(ErrorKind::TrailingField(token(extra)).into()),
            None => Ok(()),
        }
    }
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

fn parse_count(s: &str, field: &'static str, max: u64) -> Result<u64> {
    let bad = || {
        Error::from(ErrorKind::BadCount {
            field,
            found: token(s),
        })
    };
    // Digits only: "+3", "3.0" and "-1" are not counts.
    if s.is_empty() || !s.bytes().all(|b| b.is_ascii_digit()) {
        return Err(bad());
    }
    match s.parse::<u64>() {
        Ok(0) => Err(ErrorKind::PatchCount { given: 0, max }.into()),
        Ok(v) if v > max => Err(ErrorKind::PatchCount { given: v, max }.into()),
        Ok(v) => Ok(v),
        // Only overflow remains: all digits but more than u64 holds.
        Err(_) => Err(ErrorKind::PatchCount {
            given: u64::MAX,
            max,
        }
        .into()),
    }
}

/// Parses a `.flat` scene (module docs give the format).
///
/// # Errors
/// The first problem found, with its 1-based line: [`ErrorKind::UnknownKeyword`],
/// [`ErrorKind::BadNumber`], [`ErrorKind::NonFiniteNumber`], [`ErrorKind::BadCount`],
/// [`ErrorKind::MissingField`], [`ErrorKind::TrailingField`],
/// [`ErrorKind::ZeroLengthSegment`], [`ErrorKind::PatchCount`],
/// [`ErrorKind::TooManyPatches`], [`ErrorKind::PolygonVertexCount`],
/// [`ErrorKind::Reflectance`], [`ErrorKind::Emittance`], [`ErrorKind::BadCuts`],
/// [`ErrorKind::CoordinateRange`]; [`ErrorKind::EmptyScene`] (line of the end of input) if
/// nothing was defined.
///
/// # Examples
/// ```
/// let scene = sceneinfo::io::parse_flat("seg 0 0 1 0 4  # floor\nseg 1 1 0 1\n").unwrap();
/// assert_eq!(scene.n_patches(), 5);
/// let err = sceneinfo::io::parse_flat("seg 0 0 0 0\n").unwrap_err();
/// assert_eq!(err.to_string(), "line 1: segment has zero length");
/// ```
pub fn parse_flat(text: &str) -> Result<Scene2> {
    let mut builder = Scene2::builder();
    let mut last_line = 1u32;
    // The line of each surface, to locate coincident surfaces found at the end
    let mut surface_lines: Vec<u32> = Vec::new();
    for (line_no, raw) in super::text::lines(text) {
        last_line = line_no;
        let content = raw.split('#').next().unwrap_or("");
        let mut fields = Fields {
            iter: content.split_whitespace(),
        };
        let Some(keyword) = fields.next() else {
            continue;
        };
        parse_item(keyword, &mut fields, &mut builder).map_err(|e| e.with_line(line_no))?;
        surface_lines.resize(builder.surface_count(), line_no);
    }
    builder.build().map_err(|e| match *e.kind() {
        ErrorKind::EmptyScene => e.with_line(last_line),
        ErrorKind::CoincidentSurfaces { first, second } => {
            locate_coincident(&surface_lines, first, second)
        }
        _ => e,
    })
}

/// [`ErrorKind::CoincidentSurfaces`] located by the lines of the two surfaces: the error
/// is on the later one's line and names the earlier one's.
pub(super) fn locate_coincident(lines: &[u32], first: usize, second: usize) -> Error {
    let line = |k: usize| lines.get(k).copied().unwrap_or(0);
    let (other, here) = (line(first), line(second));
    Error::at_line(
        ErrorKind::CoincidentWith {
            other_line: (other != here).then_some(other),
        },
        here,
    )
}

fn parse_item(keyword: &str, f: &mut Fields<'_>, builder: &mut Scene2Builder) -> Result<()> {
    match keyword {
        "seg" => {
            let a = f.point("x0", "y0")?;
            let b = f.point("x1", "y1")?;
            match f.next() {
                None => {
                    builder.segment(a, b, 1)?;
                }
                Some("cuts") => {
                    let mut cuts = Vec::new();
                    while let Some(s) = f.next() {
                        if cuts.len() as u64 >= MAX_PATCHES_PER_SURFACE {
                            return Err(ErrorKind::PatchCount {
                                given: MAX_PATCHES_PER_SURFACE + 1,
                                max: MAX_PATCHES_PER_SURFACE,
                            }
                            .into());
                        }
                        cuts.push(parse_number(s, "cut")?);
                    }
                    builder.segment_with_cuts(a, b, &cuts)?;
                }
                Some(s) => {
                    let n = parse_count(s, "n", MAX_PATCHES_PER_SURFACE)?;
                    f.finish()?;
                    builder.segment(a, b, n)?;
                }
            }
        }
        "poly" => {
            let s = f.next().ok_or(ErrorKind::MissingField { field: "n" })?;
            let n = parse_count(s, "n", MAX_POLYGON_VERTICES).map_err(|e| match e.kind() {
                ErrorKind::PatchCount { given, .. } => {
                    ErrorKind::PolygonVertexCount { given: *given }.into()
                }
                _ => e,
            })?;
            if n < 3 {
                return Err(ErrorKind::PolygonVertexCount { given: n }.into());
            }
            let mut vertices = Vec::with_capacity(n as usize);
            for _ in 0..n {
                vertices.push(f.point("x", "y")?);
            }
            let per_side = match f.next() {
                None => 1,
                Some("per_side") => {
                    let s = f
                        .next()
                        .ok_or(ErrorKind::MissingField { field: "per_side" })?;
                    parse_count(s, "per_side", MAX_PATCHES_PER_SURFACE)?
                }
                Some(other) => return Err(ErrorKind::TrailingField(token(other)).into()),
            };
            f.finish()?;
            builder.polygon(&vertices, per_side)?;
        }
        "mat" => {
            let mut rho = [0.0; 3];
            let mut emit = [0.0; 3];
            let mut any = false;
            while let Some(clause) = f.next() {
                match clause {
                    "rho" => rho = f.rgb("rho")?,
                    "emit" => emit = f.rgb("emit")?,
                    other => return Err(ErrorKind::UnknownKeyword(token(other)).into()),
                }
                any = true;
            }
            if !any {
                return Err(ErrorKind::MissingField {
                    field: "rho or emit",
                }
                .into());
            }
            builder.material(Material::new(rho, emit)?);
        }
        other => return Err(ErrorKind::UnknownKeyword(token(other)).into()),
    }
    Ok(())
}

/// Writes a scene in the `.flat` format: one `mat` line before each change of material and
/// one `seg` line per surface (with its patch count, or its explicit cuts). Coordinates are
/// the given ones (the scene's [`crate::scene::Frame`] undone, exactly), written with Rust's
/// shortest round-trip formatting, so [`parse_flat`] gives back the same scene bit for bit.
#[must_use]
pub fn write_flat(scene: &Scene2) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "# sceneinfo flatland scene: {} patches",
        scene.n_patches()
    );
    let mut current: Option<usize> = None;
    for s in scene.surfaces() {
        if current != Some(s.material) {
            let m = scene
                .materials()
                .get(s.material)
                .copied()
                .unwrap_or_default();
            let [r, g, b] = m.reflectance;
            let [er, eg, eb] = m.emittance;
            let _ = writeln!(out, "mat rho {r:?} {g:?} {b:?} emit {er:?} {eg:?} {eb:?}");
            current = Some(s.material);
        }
        let frame = scene.frame();
        let (a, b) = (
            frame.to_world_2d(s.segment.a),
            frame.to_world_2d(s.segment.b),
        );
        let _ = write!(out, "seg {:?} {:?} {:?} {:?}", a.x, a.y, b.x, b.y);
        if s.is_uniform() {
            let _ = writeln!(out, " {}", s.cuts.len() + 1);
        } else {
            out.push_str(" cuts");
            for t in &s.cuts {
                let _ = write!(out, " {t:?}");
            }
            out.push('\n');
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use alloc::string::ToString;

    fn err(text: &str) -> String {
        parse_flat(text).unwrap_err().to_string()
    }

    #[test]
    fn parses_all_items() {
        let text = "# a room\nmat rho 0.5 0.5 0.5\npoly 4 0 0 2 0 2 2 0 2 per_side 3\n\
                    mat emit 1 1 1 rho 0.1 0.2 0.3\nseg 0.5 1 1.5 1 cuts 0.25 0.5\n";
        let s = parse_flat(text).unwrap();
        assert_eq!(s.n_patches(), 12 + 3);
        assert_eq!(s.materials().len(), 2);
        assert_eq!(s.patch_material(14).unwrap().emittance, [1.0; 3]);
        assert_eq!(s.patch_material(0).unwrap().reflectance, [0.5; 3]);
    }

    #[test]
    fn round_trips() {
        let text = "mat rho 0.25 0.5 0.75\npoly 3 0 0 1 0 0.3 0.9 per_side 4\nseg 0.1 0.2 0.3 0.4 cuts 0.1 0.7\n";
        let s = parse_flat(text).unwrap();
        let again = parse_flat(&write_flat(&s)).unwrap();
        assert_eq!(s, again);
    }

    #[test]
    fn errors_name_line_and_problem() {
        assert_eq!(err("\n\nfoo 1 2"), "line 3: unknown keyword 'foo'");
        assert_eq!(err("seg 0 0 x 1"), "line 1: x1: 'x' is not a number");
        assert_eq!(
            err("seg 0 0 NaN 1"),
            "line 1: x1: number is NaN, infinite or beyond the range of f64"
        );
        assert_eq!(
            err("seg 0 0 inf 1"),
            "line 1: x1: number is NaN, infinite or beyond the range of f64"
        );
        assert_eq!(err("seg 0 0 1"), "line 1: missing field y1");
        assert_eq!(err("seg 0 0 1 1 2 3"), "line 1: unexpected extra field '3'");
        assert_eq!(err("seg 1 1 1 1"), "line 1: segment has zero length");
        assert_eq!(
            err("seg 0 0 1 1 0"),
            "line 1: patch count 0 is out of range (1 to 1000000)"
        );
        assert_eq!(
            err("seg 0 0 1 1 99999999999999999999999"),
            "line 1: patch count 18446744073709551615 or more is out of range (1 to 1000000)"
        );
        assert_eq!(
            err("seg 0 0 1 1 -2"),
            "line 1: n: '-2' is not a positive integer"
        );
        assert_eq!(
            err("mat rho 1 0 0"),
            "line 1: reflectance 1 is outside [0, 1)"
        );
        assert_eq!(
            err("mat rho -0.1 0 0"),
            "line 1: reflectance -0.1 is outside [0, 1)"
        );
        assert_eq!(err("mat emit 0 -1 0"), "line 1: emittance -1 is negative");
        assert_eq!(err("mat"), "line 1: missing field rho or emit");
        assert_eq!(
            err("poly 2 0 0 1 1"),
            "line 1: polygon needs at least 3 vertices (and at most 100000), got 2"
        );
        assert_eq!(
            err("poly 3 0 0 1 0 1 1 per_side"),
            "line 1: missing field per_side"
        );
        assert_eq!(err("# only a comment\n\n"), "line 2: scene has no patches");
        assert_eq!(err(""), "line 1: scene has no patches");
        assert_eq!(
            err("seg 0 0 1 0 cuts 0.5 0.5"),
            "line 1: cut positions must increase strictly inside (0, 1)"
        );
        assert_eq!(
            err("seg 0 0 1e301 0"),
            "line 1: coordinate too large: every coordinate must lie within ±1e300"
        );
    }

    #[test]
    fn absurd_totals_are_capped_before_allocating() {
        // 5 surfaces × 1,000,000 patches exceeds MAX_PATCHES (4,000,000).
        let text = "seg 0 0 1 0 1000000\n".repeat(5);
        assert_eq!(err(&text), "line 5: scene has more than 4000000 patches");
    }

    #[test]
    fn byte_order_mark_and_every_line_end_read_alike() {
        let text = "mat rho 0.5 0.5 0.5\npoly 4 0 0 2 0 2 2 0 2 per_side 3\n\
                    mat emit 1 1 1\nseg 0.5 1 1.5 1 cuts 0.25 0.5\n";
        let plain = parse_flat(text).unwrap();
        for end in ["\n", "\r\n", "\r"] {
            for bom in ["", "\u{feff}"] {
                let s = parse_flat(&alloc::format!("{bom}{}", text.replace('\n', end))).unwrap();
                assert_eq!(s.n_patches(), plain.n_patches(), "{end:?} {bom:?}");
                assert_eq!(s.materials(), plain.materials(), "{end:?} {bom:?}");
            }
        }
        // Before, the mark made the first keyword unknown.
        assert!(parse_flat("\u{feff}mat rho 0.5 0.5 0.5\nseg 0 0 1 0\n").is_ok());
        // Elsewhere it is still text (and escaped in messages).
        assert_eq!(
            err("seg 0 0 1 0\n\u{feff}seg 0 1 1 1\n"),
            "line 2: unknown keyword '\\u{feff}seg'"
        );
    }

    #[test]
    fn line_numbers_count_cr_only_and_mixed_line_ends() {
        assert_eq!(
            err("\u{feff}seg 0 0 1 0\rseg 0 1 1 1\r\n\n\rseg 0 0 0 0\r"),
            "line 5: segment has zero length"
        );
        // A scene without surfaces: the error is on the last line.
        assert_eq!(err("# a\r# b\r# c\r"), "line 3: scene has no patches");
    }
}
