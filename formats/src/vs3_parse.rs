//! The records of a View3D `.vs3` file, read line by line ([`parse`]), for
//! [`crate::vs3_scene`], which turns them into a scene. Both geometry formats of the manual
//! are read: `F 3` (vertices `V`, then surfaces naming four vertex numbers) and `F 3a`
//! (each surface followed by its plane and shape, [`blast_corners`]).

use std::collections::HashMap;
use std::path::Path;

use anyhow::Result;
use sceneinfo::geom::DVec3;

use crate::vs3_controls::Vs3FileControls;

/// Most vertices or surfaces a file may number (bounds the tables).
pub(crate) const MAX_NUMBER: usize = 1 << 26;

/// The manual's four surface types (besides the subsurface, which is an `S` with a base).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Kind {
    /// `S`: radiates (a subsurface when its base is not 0).
    Radiating,
    /// `M`: a mask, facing its base, which sees only the base.
    Mask,
    /// `N`: a null surface, cut out of its base and dropped.
    Null,
    /// `O`: blocks sight lines but has no row or column of the view factors.
    Obstruction,
}

impl Kind {
    /// The record letter, for messages.
    pub(crate) fn letter(self) -> char {
        match self {
            Self::Radiating => 'S',
            Self::Mask => 'M',
            Self::Null => 'N',
            Self::Obstruction => 'O',
        }
    }
}

/// One surface record: its number, type, corners (counter-clockwise seen from the front),
/// base (0: none), the surface it combines with (0: none), name and line.
#[derive(Clone, Debug)]
pub(crate) struct Record {
    pub number: usize,
    pub kind: Kind,
    pub corners: Vec<DVec3>,
    pub base: usize,
    pub combine: usize,
    pub name: String,
    /// The emittance column (`None`: not given).
    pub emissivity: Option<f64>,
    pub line: usize,
}

/// The geometry formats read.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Geometry {
    /// `F 3`: vertices, then surfaces naming them.
    Vertices,
    /// `F 3a`: each surface followed by its plane and shape.
    Blast,
}

/// A `F 3a` surface whose plane and shape numbers are still being read.
struct PendingBlast {
    record: Record,
    shape: char,
    numbers: Vec<f64>,
}

impl PendingBlast {
    /// How many numbers the shape needs after the origin, azimuth and tilt.
    fn needed(&self) -> usize {
        5 + match self.shape {
            'R' => 2,
            'T' => 6,
            _ => 8,
        }
    }
}

/// The surface records of the `.vs3` text `text` from `path`, in the file's order, and its
/// controls (the `C` lines, [`Vs3FileControls`]).
///
/// # Errors
/// `file:line: what` for a line that cannot be read (see [`crate::vs3_scene`]'s table).
pub(crate) fn parse(path: &Path, text: &str) -> Result<(Vec<Record>, Vs3FileControls)> {
    let at = |line: usize, what: &str| anyhow::anyhow!("{}:{line}: {what}", path.display());
    // By number (a map: a file may number its vertices sparsely, up to MAX_NUMBER)
    let mut vertices: HashMap<usize, DVec3> = HashMap::new();
    let mut records: Vec<Record> = Vec::new();
    let mut geometry = None;
    let mut pending: Option<PendingBlast> = None;
    let mut controls = Vs3FileControls::default();
    // Bounded: the lines of the file
    for (k, raw) in text.lines().enumerate() {
        let line = k + 1;
        // A comment may follow the data on a line
        let data = raw.split(['!', '/']).next().unwrap_or("").trim();
        let mut tokens = data.split_whitespace();
        let Some(keyword) = tokens.next() else {
            continue;
        };
        let first = keyword.chars().next().unwrap_or(' ');
        // F 3a: the numbers of the surface above, on as many lines as they take
        if let Some(p) = pending.as_mut()
            && (first.is_ascii_digit() || matches!(first, '-' | '+' | '.'))
        {
            for token in data.split_whitespace() {
                if p.numbers.len() == p.needed() {
                    return Err(at(
                        line,
                        &format!("more numbers than surface {} takes", p.record.number),
                    ));
                }
                p.numbers.push(finite(token).ok_or_else(|| {
                    at(
                        line,
                        &format!("bad number {token:?} for surface {}", p.record.number),
                    )
                })?);
            }
            if p.numbers.len() == p.needed()
                && let Some(p) = pending.take()
            {
                records.push(finish_blast(p, &at)?);
            }
            continue;
        }
        if let Some(p) = &pending {
            return Err(at(
                line,
                &format!(
                    "surface {} (line {}) has {} of its {} plane and shape numbers",
                    p.record.number,
                    p.record.line,
                    p.numbers.len(),
                    p.needed()
                ),
            ));
        }
        let fields: Vec<&str> = tokens.collect();
        let kind = match first.to_ascii_uppercase() {
            'T' => continue,
            'C' => {
                controls.read_line(path, line, &fields.join(" "))?;
                continue;
            }
            'E' | '*' => break,
            'F' => {
                geometry = Some(match fields.first().copied() {
                    Some("3") => Geometry::Vertices,
                    Some("3a" | "3A") => Geometry::Blast,
                    other => {
                        return Err(at(
                            line,
                            &format!(
                                "geometry format F {} is not read (F 3 and F 3a are; 2 and 1 are \
                                 other programs')",
                                other.unwrap_or("")
                            ),
                        ));
                    }
                });
                continue;
            }
            'V' => {
                if geometry != Some(Geometry::Vertices) {
                    return Err(at(line, "vertices (V) belong to geometry format F 3"));
                }
                let (n, p) = vertex(&fields, &|w| at(line, w))?;
                vertices.insert(n, p);
                continue;
            }
            'S' => Kind::Radiating,
            'M' => Kind::Mask,
            'N' => Kind::Null,
            'O' => Kind::Obstruction,
            _ => return Err(at(line, &format!("unknown line kind {keyword:?}"))),
        };
        match geometry {
            None => return Err(at(line, "a surface before the geometry line (F 3 or F 3a)")),
            Some(Geometry::Vertices) => {
                records.push(surface_by_vertices(kind, &fields, &vertices, line, &at)?);
            }
            Some(Geometry::Blast) => pending = Some(blast_head(kind, &fields, line, &at)?),
        }
    }
    if let Some(p) = pending {
        return Err(at(
            p.record.line,
            &format!(
                "the file ends before surface {}'s plane and shape numbers",
                p.record.number
            ),
        ));
    }
    if geometry.is_none() {
        anyhow::bail!("{}: no geometry line (F 3 or F 3a)", path.display());
    }
    Ok((records, controls))
}

/// A finite number.
fn finite(s: &str) -> Option<f64> {
    s.parse::<f64>().ok().filter(|v| v.is_finite())
}

/// A positive surface or vertex number.
pub(crate) fn number(s: &str) -> Option<usize> {
    s.parse::<usize>()
        .ok()
        .filter(|&n| n > 0 && n <= MAX_NUMBER)
}

/// A number that may be 0 (`v4`, `base`, `cmb`).
fn number_or_zero(s: &str) -> Option<usize> {
    s.parse::<usize>().ok().filter(|&n| n <= MAX_NUMBER)
}

/// The emittance column, when given: a finite number (View3D replaces one outside
/// `(0, 1)` by 0.001 or 0.999 with a warning; sceneinfo uses it only with `emit=1`, where
/// [`crate::vs3_controls::script_f`] asks `(0, 1]`).
fn emissivity(
    field: Option<&str>,
    line: usize,
    at: &dyn Fn(usize, &str) -> anyhow::Error,
) -> Result<Option<f64>> {
    field
        .map(|f| finite(f).ok_or_else(|| at(line, &format!("bad emittance {f:?}"))))
        .transpose()
}

/// `V n x y z`.
fn vertex(fields: &[&str], at: &dyn Fn(&str) -> anyhow::Error) -> Result<(usize, DVec3)> {
    if fields.len() < 4 {
        return Err(at("a vertex needs a number and x y z"));
    }
    let n = number(fields[0]).ok_or_else(|| at("bad vertex number"))?;
    let mut c = [0.0; 3];
    for (slot, field) in c.iter_mut().zip(&fields[1..4]) {
        *slot = finite(field).ok_or_else(|| at(&format!("bad coordinate {field:?}")))?;
    }
    Ok((n, DVec3::from(c)))
}

/// `K n v1 v2 v3 v4 base cmb [emit name]` (`F 3`; `v4 = 0`: a triangle).
fn surface_by_vertices(
    kind: Kind,
    fields: &[&str],
    vertices: &HashMap<usize, DVec3>,
    line: usize,
    at: &dyn Fn(usize, &str) -> anyhow::Error,
) -> Result<Record> {
    if fields.len() < 7 {
        return Err(at(
            line,
            "a surface needs: number v1 v2 v3 v4 base cmb [emit name]",
        ));
    }
    let field = |i: usize, what: &str| {
        number_or_zero(fields[i]).ok_or_else(|| at(line, &format!("bad {what}")))
    };
    let n = number(fields[0]).ok_or_else(|| at(line, "bad surface number"))?;
    let mut corners = Vec::with_capacity(4);
    for i in 1..=4 {
        let v = field(i, "vertex number")?;
        if v == 0 && i == 4 {
            break;
        }
        let p = vertices.get(&v).copied().ok_or_else(|| {
            at(
                line,
                &format!("vertex {v} is not defined before it is used"),
            )
        })?;
        corners.push(p);
    }
    Ok(Record {
        number: n,
        kind,
        corners,
        base: field(5, "base")?,
        combine: field(6, "cmb")?,
        name: fields.get(8).copied().unwrap_or("").to_owned(),
        emissivity: emissivity(fields.get(7).copied(), line, at)?,
        line,
    })
}

/// `K n shape base cmb [emit name]` (`F 3a`), its numbers to follow.
fn blast_head(
    kind: Kind,
    fields: &[&str],
    line: usize,
    at: &dyn Fn(usize, &str) -> anyhow::Error,
) -> Result<PendingBlast> {
    if fields.len() < 4 {
        return Err(at(
            line,
            "a F 3a surface needs: number shape base cmb [emit name], then its plane and shape",
        ));
    }
    let n = number(fields[0]).ok_or_else(|| at(line, "bad surface number"))?;
    let shape = match fields[1].to_ascii_uppercase().as_str() {
        "R" => 'R',
        "Q" => 'Q',
        "T" => 'T',
        other => {
            return Err(at(
                line,
                &format!(
                    "shape {other:?} is not one of R (rectangle), Q (quadrilateral), T (triangle)"
                ),
            ));
        }
    };
    let field = |i: usize, what: &str| {
        number_or_zero(fields[i]).ok_or_else(|| at(line, &format!("bad {what}")))
    };
    Ok(PendingBlast {
        record: Record {
            number: n,
            kind,
            corners: Vec::new(),
            base: field(2, "base")?,
            combine: field(3, "cmb")?,
            name: fields.get(5).copied().unwrap_or("").to_owned(),
            emissivity: emissivity(fields.get(4).copied(), line, at)?,
            line,
        },
        shape,
        numbers: Vec::with_capacity(13),
    })
}

/// The finished `F 3a` surface: its corners from its numbers ([`blast_corners`]).
fn finish_blast(p: PendingBlast, at: &dyn Fn(usize, &str) -> anyhow::Error) -> Result<Record> {
    let mut record = p.record;
    record.corners = blast_corners(p.shape, &p.numbers).ok_or_else(|| {
        at(
            record.line,
            "a rectangle's width and height must be positive",
        )
    })?;
    Ok(record)
}

/// `sin` and `cos` of `degrees`, exact at multiples of 90° (so that walls and floors given
/// by their azimuth and tilt have exact coordinates, as in a `F 3` file).
fn sin_cos_degrees(degrees: f64) -> (f64, f64) {
    let quarter = degrees / 90.0;
    if quarter == quarter.round() {
        match quarter.rem_euclid(4.0) as u8 {
            0 => (0.0, 1.0),
            1 => (1.0, 0.0),
            2 => (0.0, -1.0),
            _ => (-1.0, 0.0),
        }
    } else {
        degrees.to_radians().sin_cos()
    }
}

/// The corners of a `F 3a` surface from `numbers`: the origin `x y z`, the plane's azimuth
/// `a` (degrees clockwise from `+y`, north) and tilt `t` (0 facing up, 90 vertical, 180
/// facing down), then the rectangle's width and height (`R`) or the corners' plane
/// coordinates (`Q`: four pairs, `T`: three), counter-clockwise seen from the front.
///
/// The manual gives the angles and that the origin is a rectangle's lower left corner seen
/// from the front; the plane's axes follow: the front normal
/// `n = (sin t sin a, sin t cos a, cos t)`, the plane's `x` axis horizontal and to the right
/// of a viewer facing the front, `X = (−cos a, sin a, 0)`, and `Y = n × X` (up the plane
/// for a wall). Checked on the manual's Pinney & Bean room, given in both formats: the
/// same corners (`blast_geometry_is_the_vertex_geometry`). `None` for a rectangle of
/// non-positive width or height.
pub(crate) fn blast_corners(shape: char, numbers: &[f64]) -> Option<Vec<DVec3>> {
    let origin = DVec3::new(numbers[0], numbers[1], numbers[2]);
    let (sin_a, cos_a) = sin_cos_degrees(numbers[3]);
    let (sin_t, cos_t) = sin_cos_degrees(numbers[4]);
    let normal = DVec3::new(sin_t * sin_a, sin_t * cos_a, cos_t);
    let x_axis = DVec3::new(-cos_a, sin_a, 0.0);
    let y_axis = normal.cross(x_axis);
    let at = |u: f64, v: f64| origin + u * x_axis + v * y_axis;
    let rest = &numbers[5..];
    Some(match shape {
        'R' => {
            let (w, h) = (rest[0], rest[1]);
            if w <= 0.0 || h <= 0.0 {
                return None;
            }
            vec![at(0.0, 0.0), at(w, 0.0), at(w, h), at(0.0, h)]
        }
        _ => rest.chunks_exact(2).map(|c| at(c[0], c[1])).collect(),
    })
}
