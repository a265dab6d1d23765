//! View3D's view-factor output file, written and read, so that View3D's users can compare
//! its matrices with sceneinfo's (and feed sceneinfo's to the tools that read View3D's).
//!
//! The format, from the View3D 3.3 manual (`doc/view3d-manual.tex`, "Program Output",
//! "View Factor Output File"; the manual, not View3D's code, which is GPL):
//!
//! ```text
//! View3D version out encl emit N      header: the format's version, the control values
//!                                     `out` (0 text, 1 binary), `encl`, `emit`; N surfaces
//! A_1 A_2 … A_N                       surface areas
//! F_11 F_12 … F_1N                    N rows of the view factors, F_mn = entry n of row m
//! …
//! e_1 e_2 … e_N                       surface emissivities
//! ```
//!
//! [`write_text`] writes the text form (`out = 0`) with every number in its shortest
//! round-trip decimal (View3D prints six decimals; the values here are exact to their
//! error estimates, so they keep all their digits). The version field says `3.3.1`, the
//! manual's, whose layout the file follows; `encl = 0` (rows are not renormalised) and
//! `emit = 0` (black surfaces: plain view factors, not Hottel's script-F), so the
//! emissivity line, which such a file does not use, says 1 for every surface. The matrix is
//! the patches' (an open scene's background state is left out: its rows sum to less than
//! 1, as View3D's do). [`write_text_with`] writes a `.vs3` file's output surfaces as its
//! controls ask: `encl` and `emit` in the header, the file's emittances on the last line.
//!
//! [`read`] reads the text form, tokens in order (so line breaks inside a list do not
//! matter), and the binary form (`out = 1`): a 32-byte header holding the same six fields
//! and ending in `\r\n`, then `f32` little-endian areas, rows and emissivities. The manual
//! does not give the binary layout; this is what View3D 4.0.0 wrote on x86-64
//! (`tests/data/vs3/room_with_plate.view3d.bin`, read by a test beside its text form).

use std::fmt::Write as _;
use std::path::Path;

use anyhow::{Result, bail};

/// The version field written in the header: the View3D manual's whose layout the file
/// follows.
pub const FORMAT_VERSION: &str = "3.3.1";

/// Most surfaces a file may declare (bounds the tables before the numbers are read).
const MAX_SURFACES: usize = 1 << 20;

/// A View3D output file, read.
#[derive(Clone, Debug, PartialEq)]
pub struct View3dMatrix {
    /// The header's version field.
    pub version: String,
    /// The header's `encl` (rows renormalised as an enclosure's).
    pub encl: bool,
    /// The header's `emit` (Hottel's script-F factors instead of view factors).
    pub emit: bool,
    /// Surface areas, one per surface.
    pub areas: Vec<f64>,
    /// Row-major `N × N` view factors.
    pub form_factors: Vec<f64>,
    /// Surface emissivities (empty when a text file ends before them).
    pub emissivities: Vec<f64>,
}

impl View3dMatrix {
    /// Number of surfaces `N`.
    #[must_use]
    pub fn n(&self) -> usize {
        self.areas.len()
    }
}

/// The text form (`out = 0`) of the `n × n` view factors whose rows `row(i, out)` fills,
/// with the surface `areas` (see the module documentation).
///
/// # Errors
/// `row`'s.
pub fn write_text(
    areas: &[f64],
    row: impl FnMut(usize, &mut [f64]) -> Result<()>,
) -> Result<String> {
    write_text_with(areas, &vec![1.0; areas.len()], false, false, row)
}

/// [`write_text`] with the header's `encl` and `emit` and the emittance line given: the
/// output of a `.vs3` file whose controls ask for the enclosure adjustment or script-F
/// factors (`vs3_scene::Vs3Layout::view3d_matrix`), which the rows hold.
///
/// # Errors
/// `row`'s; `emissivities` not one per surface.
pub fn write_text_with(
    areas: &[f64],
    emissivities: &[f64],
    encl: bool,
    emit: bool,
    mut row: impl FnMut(usize, &mut [f64]) -> Result<()>,
) -> Result<String> {
    let n = areas.len();
    if emissivities.len() != n {
        bail!("{} emittances for {n} surfaces", emissivities.len());
    }
    let mut s = String::with_capacity(n.saturating_mul(n + 2).saturating_mul(12));
    let _ = writeln!(
        s,
        "View3D {FORMAT_VERSION} 0 {} {} {n}",
        u8::from(encl),
        u8::from(emit)
    );
    let line = |s: &mut String, values: &mut dyn Iterator<Item = f64>| {
        for (k, v) in values.enumerate() {
            if k > 0 {
                s.push(' ');
            }
            let _ = write!(s, "{v:?}");
        }
        s.push('\n');
    };
    line(&mut s, &mut areas.iter().copied());
    let mut values = vec![0.0; n];
    // Bounded: the rows
    for i in 0..n {
        row(i, &mut values)?;
        line(&mut s, &mut values.iter().copied());
    }
    line(&mut s, &mut emissivities.iter().copied());
    Ok(s)
}

/// Reads a View3D output file `bytes` from `path`, text or binary (see the module
/// documentation).
///
/// # Errors
/// `file: what` (`file:line: what` in a text file) for a header that is not View3D's, a
/// number that does not parse or is not finite, or a file that ends before its matrix.
pub fn read(path: &Path, bytes: &[u8]) -> Result<View3dMatrix> {
    if bytes.len() >= 32 && &bytes[30..32] == b"\r\n" {
        return read_binary(path, bytes);
    }
    let Ok(text) = std::str::from_utf8(bytes) else {
        bail!(
            "{}: not a View3D output file (neither text nor View3D's binary header)",
            path.display()
        );
    };
    let mut tokens = text
        .lines()
        .enumerate()
        .flat_map(|(k, l)| l.split_whitespace().map(move |t| (k + 1, t)));
    let header: Vec<(usize, &str)> = tokens.by_ref().take(6).collect();
    let (version, encl, emit, n) = header_fields(path, &header)?;
    let mut number = |what: &str| -> Result<f64> {
        let Some((line, t)) = tokens.next() else {
            bail!("{}: the file ends before its {what}", path.display());
        };
        match t.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => bail!(
                "{}:{line}: '{t}' in the {what} is not a finite number",
                path.display()
            ),
        }
    };
    let areas = (0..n)
        .map(|_| number("areas"))
        .collect::<Result<Vec<_>>>()?;
    let form_factors = (0..n * n)
        .map(|_| number("view factors"))
        .collect::<Result<Vec<_>>>()?;
    let mut emissivities = Vec::with_capacity(n);
    // The emissivity line is read when present
    for _ in 0..n {
        match number("emissivities") {
            Ok(v) => emissivities.push(v),
            Err(_) if emissivities.is_empty() => break,
            Err(e) => return Err(e),
        }
    }
    Ok(View3dMatrix {
        version,
        encl,
        emit,
        areas,
        form_factors,
        emissivities,
    })
}

/// The header's fields: version, `encl`, `emit`, `N`.
fn header_fields(path: &Path, header: &[(usize, &str)]) -> Result<(String, bool, bool, usize)> {
    let words: Vec<&str> = header.iter().map(|(_, t)| *t).collect();
    let [name, version, out, encl, emit, n] = words[..] else {
        bail!(
            "{}:1: not a View3D output file (a header 'View3D version out encl emit N' is expected)",
            path.display()
        );
    };
    if name != "View3D" {
        bail!(
            "{}:1: not a View3D output file (the header begins with '{name}', not 'View3D')",
            path.display()
        );
    }
    let flag = |t: &str, what: &str| match t {
        "0" => Ok(false),
        "1" => Ok(true),
        _ => bail!(
            "{}:1: the header's {what} is '{t}', not 0 or 1",
            path.display()
        ),
    };
    flag(out, "out")?;
    let (encl, emit) = (flag(encl, "encl")?, flag(emit, "emit")?);
    let n: usize = match n.parse() {
        Ok(n) if (1..=MAX_SURFACES).contains(&n) => n,
        _ => bail!(
            "{}:1: the header's surface count '{n}' is not a count from 1 to {MAX_SURFACES}",
            path.display()
        ),
    };
    Ok((version.to_owned(), encl, emit, n))
}

/// The binary form: the 32-byte header, then `f32` areas, rows and emissivities.
fn read_binary(path: &Path, bytes: &[u8]) -> Result<View3dMatrix> {
    let head = String::from_utf8_lossy(&bytes[..30]);
    let header: Vec<(usize, &str)> = head.split_whitespace().map(|t| (1, t)).collect();
    let (version, encl, emit, n) = header_fields(path, &header)?;
    let body = &bytes[32..];
    let want = (n + n * n + n) * 4;
    if body.len() != want {
        bail!(
            "{}: a binary View3D file of {n} surfaces holds {want} bytes after its header, this one {}",
            path.display(),
            body.len()
        );
    }
    let mut values = body
        .chunks_exact(4)
        .map(|c| f64::from(f32::from_le_bytes([c[0], c[1], c[2], c[3]])));
    let mut take = |k: usize| -> Vec<f64> { values.by_ref().take(k).collect() };
    let (areas, form_factors, emissivities) = (take(n), take(n * n), take(n));
    if areas
        .iter()
        .chain(&form_factors)
        .chain(&emissivities)
        .any(|v| !v.is_finite())
    {
        bail!(
            "{}: a number of the binary View3D file is not finite",
            path.display()
        );
    }
    Ok(View3dMatrix {
        version,
        encl,
        emit,
        areas,
        form_factors,
        emissivities,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The manual's example output (the unit cube) reads as printed.
    #[test]
    fn reads_the_manuals_example() {
        let text = "View3D 3.3.1 0 1 0 6          \n1 1 1 1 1 1\n\
            0.000000 0.200044 0.200044 0.199825 0.200044 0.200044\n\
            0.200044 0.000000 0.200044 0.200044 0.199825 0.200044\n\
            0.200044 0.200044 0.000000 0.200044 0.200044 0.199825\n\
            0.199825 0.200044 0.200044 0.000000 0.200044 0.200044\n\
            0.200044 0.199825 0.200044 0.200044 0.000000 0.200044\n\
            0.200044 0.200044 0.199825 0.200044 0.200044 0.000000\n\
            0.500 0.500 0.500 0.500 0.500 0.500\n";
        let m = read(Path::new("cube.out"), text.as_bytes()).unwrap();
        assert_eq!(
            (m.n(), m.encl, m.emit, m.version.as_str()),
            (6, true, false, "3.3.1")
        );
        assert_eq!(m.form_factors[3], 0.199825);
        assert_eq!(m.form_factors[6 * 5 + 2], 0.199825);
        assert_eq!(m.emissivities, vec![0.5; 6]);
    }

    /// What `write_text` writes reads back bit for bit; the binary form reads too.
    #[test]
    fn round_trips_and_reads_binary() {
        let areas = [1.0, 0.25, 3.0e-7];
        let f = [0.0, 0.1, 0.2, 0.4, 0.0, 1.0 / 3.0, 1e-300, 0.5, 0.0];
        let text = write_text(&areas, |i, out| {
            out.copy_from_slice(&f[3 * i..3 * i + 3]);
            Ok(())
        })
        .unwrap();
        assert!(text.starts_with("View3D 3.3.1 0 0 0 3\n"), "{text}");
        let m = read(Path::new("f.vf3"), text.as_bytes()).unwrap();
        assert_eq!(
            (m.areas.as_slice(), m.form_factors.as_slice()),
            (&areas[..], &f[..])
        );
        assert_eq!(m.emissivities, vec![1.0; 3]);
        let mut bin = format!("{:<30}", "View3D 3.3.1 1 0 0 3").into_bytes();
        bin.extend_from_slice(b"\r\n");
        for v in areas.iter().chain(&f).chain(&[0.9; 3]) {
            bin.extend_from_slice(&(*v as f32).to_le_bytes());
        }
        let b = read(Path::new("f.bin"), &bin).unwrap();
        assert_eq!(b.form_factors[5], f64::from((1.0f64 / 3.0) as f32));
        assert_eq!(b.emissivities, vec![f64::from(0.9f32); 3]);
    }

    /// Files View3D 4.0.0 itself wrote (tests/data/vs3/README.md says how) on the room with
    /// a plate: its binary form (`out=1`) reads, and each number is the text form's
    /// (`out=0`, same run settings) to the digits the text prints. View3D prints the
    /// `f32` it stores in binary with `%f` (view factors), `%.3f` (emissivities) and `%g`
    /// (areas), so formatting the binary value so must give the text token exactly: a
    /// misread offset, byte order or width fails it.
    #[test]
    fn reads_a_binary_file_view3d_wrote_as_its_text_form() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/vs3");
        let read_file = |name: &str| {
            let path = dir.join(name);
            read(&path, &std::fs::read(&path).unwrap()).unwrap()
        };
        let bin = read_file("room_with_plate.view3d.bin");
        let text = read_file("room_with_plate.view3d.txt");
        // The hexagon's two pieces are one surface (`cmb`): 9 of the file's 10
        assert_eq!(
            (bin.n(), bin.version.as_str(), bin.encl, bin.emit),
            (9, "4.0.0", false, false)
        );
        assert_eq!(
            (text.n(), text.version.as_str(), text.encl, text.emit),
            (9, "4.0.0", false, false)
        );
        let tokens = std::fs::read_to_string(dir.join("room_with_plate.view3d.txt")).unwrap();
        let tokens: Vec<&str> = tokens.split_whitespace().skip(6).collect();
        let n = bin.n();
        let values = bin
            .areas
            .iter()
            .chain(&bin.form_factors)
            .chain(&bin.emissivities);
        assert_eq!(tokens.len(), n + n * n + n);
        for (k, (&v, &t)) in values.zip(&tokens).enumerate() {
            let printed = if k < n {
                // %g of these areas: at most 6 significant digits, no trailing zeros
                format!("{v:.6}")
                    .trim_end_matches('0')
                    .trim_end_matches('.')
                    .to_owned()
            } else if k < n + n * n {
                format!("{v:.6}")
            } else {
                format!("{v:.3}")
            };
            assert_eq!(printed, t, "value {k}: binary {v:e}, text {t}");
        }
        // The text form reads as the same numbers to its six decimals
        for (b, t) in bin.form_factors.iter().zip(&text.form_factors) {
            assert!((b - t).abs() <= 5e-7, "{b} vs {t}");
        }
        // The plate's lower face to the wall y = 0, View3D's value (docs/occlusion.md)
        assert_eq!(text.form_factors[7 * n + 1], 0.161307);
        assert!((bin.form_factors[7 * n + 1] - 0.161307).abs() < 5e-7);
    }

    /// Files that are not View3D's, or end early, are refused with the file and line.
    #[test]
    fn refuses_what_is_not_a_view3d_file() {
        let p = Path::new("x.vf3");
        for (text, says) in [
            ("", "x.vf3:1: not a View3D output file"),
            ("sceneinfo 1 0 0 0 2\n", "begins with 'sceneinfo'"),
            ("View3D 3.3 0 0 0 0\n", "surface count '0'"),
            ("View3D 3.3 2 0 0 1\n1\n0\n", "out is '2'"),
            (
                "View3D 3.3 0 0 0 2\n1 1\n0 0.5\n0.5\n",
                "ends before its view factors",
            ),
            (
                "View3D 3.3 0 0 0 1\n1\nnan\n",
                "x.vf3:3: 'nan' in the view factors",
            ),
        ] {
            let e = read(p, text.as_bytes()).unwrap_err().to_string();
            assert!(e.contains(says), "{text:?}: {e}");
        }
    }
}
