//! A small SVG writer, colour maps and a colour-bar legend, for `sceneinfo draw`.
//!
//! Coordinates are SVG pixels (y down). Every number is written with two decimals; the
//! writer never emits a non-finite number (it writes 0 instead, and the tests check that the
//! drawings never need to).

use std::fmt::Write as _;

/// A point in pixels.
pub type Point = (f64, f64);

/// An RGB colour.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rgb(pub u8, pub u8, pub u8);

impl std::fmt::Display for Rgb {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "#{:02x}{:02x}{:02x}", self.0, self.1, self.2)
    }
}

/// Matplotlib's viridis at t = 0, 0.1, …, 1 (perceptually uniform, colour-blind safe).
const VIRIDIS: [Rgb; 11] = [
    Rgb(0x44, 0x01, 0x54),
    Rgb(0x48, 0x24, 0x75),
    Rgb(0x41, 0x44, 0x87),
    Rgb(0x35, 0x5f, 0x8d),
    Rgb(0x2a, 0x78, 0x8e),
    Rgb(0x21, 0x91, 0x8c),
    Rgb(0x22, 0xa8, 0x84),
    Rgb(0x44, 0xbf, 0x70),
    Rgb(0x7a, 0xd1, 0x51),
    Rgb(0xbd, 0xdf, 0x26),
    Rgb(0xfd, 0xe7, 0x25),
];

/// Moreland's cool–warm diverging map at t = 0, 1/8, …, 1 (blue, light grey at ½, red).
const COOLWARM: [Rgb; 9] = [
    Rgb(0x3b, 0x4c, 0xc0),
    Rgb(0x62, 0x82, 0xea),
    Rgb(0x8d, 0xb0, 0xfe),
    Rgb(0xb8, 0xd0, 0xf9),
    Rgb(0xdd, 0xdd, 0xdd),
    Rgb(0xf5, 0xc4, 0xad),
    Rgb(0xf4, 0x9a, 0x7b),
    Rgb(0xde, 0x60, 0x4d),
    Rgb(0xb4, 0x04, 0x26),
];

/// A colour map: a table of equally spaced colours, linearly interpolated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ColourMap {
    /// Sequential, dark purple → yellow.
    Viridis,
    /// Diverging, blue → grey → red; the middle is meant for zero.
    CoolWarm,
}

impl ColourMap {
    fn table(self) -> &'static [Rgb] {
        match self {
            Self::Viridis => &VIRIDIS,
            Self::CoolWarm => &COOLWARM,
        }
    }

    /// The colour at `t ∈ [0, 1]` (clamped; NaN counts as 0).
    pub fn at(self, t: f64) -> Rgb {
        let table = self.table();
        let t = if t > 0.0 { t.min(1.0) } else { 0.0 };
        let x = t * (table.len() - 1) as f64;
        let k = (x.floor() as usize).min(table.len() - 2);
        let f = x - k as f64;
        let (a, b) = (table[k], table[k + 1]);
        let mix = |p: u8, q: u8| (f64::from(p) + (f64::from(q) - f64::from(p)) * f).round() as u8;
        Rgb(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
    }

    /// `(offset, colour)` of the table entries, for a gradient.
    fn stops(self) -> impl Iterator<Item = (f64, Rgb)> {
        let table = self.table();
        let last = (table.len() - 1) as f64;
        table
            .iter()
            .enumerate()
            .map(move |(k, &c)| (k as f64 / last, c))
    }
}

/// How values map to `t ∈ [0, 1]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Scale {
    /// `lo ↦ 0`, `hi ↦ 1`, linear; a constant range (`lo == hi`) maps to ½.
    Linear {
        /// Value at the low end.
        lo: f64,
        /// Value at the high end.
        hi: f64,
    },
    /// Two linear slopes meeting at zero: `lo ≤ 0 ↦ 0`, `0 ↦ ½`, `hi ≥ 0 ↦ 1`, so each
    /// sign spans half the map whatever its extent.
    Diverging {
        /// Value at the low end (≤ 0).
        lo: f64,
        /// Value at the high end (≥ 0).
        hi: f64,
    },
    /// Logarithmic between `0 < lo < hi`; values `≤ lo` (zero and negatives too) map to 0.
    Log {
        /// Value at the low end.
        lo: f64,
        /// Value at the high end.
        hi: f64,
    },
}

impl Scale {
    /// The position of `v` on the colour bar, in `[0, 1]`.
    pub fn fraction(self, v: f64) -> f64 {
        let t = match self {
            Self::Linear { lo, hi } if hi > lo => (v - lo) / (hi - lo),
            Self::Linear { .. } => 0.5,
            Self::Diverging { lo, .. } if v < 0.0 => {
                if lo < 0.0 {
                    0.5 - 0.5 * v / lo
                } else {
                    0.5
                }
            }
            Self::Diverging { hi, .. } => {
                if hi > 0.0 {
                    0.5 + 0.5 * v / hi
                } else {
                    0.5
                }
            }
            Self::Log { lo, hi } if hi > lo && lo > 0.0 => {
                if v <= lo {
                    0.0
                } else {
                    (v / lo).log10() / (hi / lo).log10()
                }
            }
            Self::Log { .. } => 0.5,
        };
        if t > 0.0 { t.min(1.0) } else { 0.0 }
    }

    /// The value at position `t` of the colour bar.
    pub fn value_at(self, t: f64) -> f64 {
        match self {
            Self::Linear { lo, hi } => lo + (hi - lo) * t,
            Self::Diverging { lo, hi } => {
                if t < 0.5 {
                    lo * (1.0 - 2.0 * t)
                } else {
                    hi * (2.0 * t - 1.0)
                }
            }
            Self::Log { lo, hi } => lo * (hi / lo).powf(t),
        }
    }
}

/// Escapes text for XML content and attribute values.
pub fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c if c.is_control() => out.push('\u{fffd}'),
            c => out.push(c),
        }
    }
    out
}

/// A value for a label: four significant digits, scientific notation when very small or large.
pub fn number(v: f64) -> String {
    let a = v.abs();
    if v == 0.0 {
        "0".to_owned()
    } else if (1e-3..1e4).contains(&a) {
        let digits = (3 - a.log10().floor() as i32).clamp(0, 6) as usize;
        format!("{v:.digits$}")
    } else {
        format!("{v:.3e}")
    }
}

/// A number as an SVG coordinate (two decimals; 0 if not finite).
struct N(f64);

impl std::fmt::Display for N {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let v = if self.0.is_finite() { self.0 } else { 0.0 };
        // Avoid "-0.00".
        let v = if v.abs() < 0.005 { 0.0 } else { v };
        write!(f, "{v:.2}")
    }
}

/// A number written with full precision (0 if not finite), for a transform's scale.
struct Num(f64);

impl std::fmt::Display for Num {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let v = if self.0.is_finite() { self.0 } else { 0.0 };
        write!(f, "{v}")
    }
}

/// Where a text is anchored.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Anchor {
    /// At its start.
    Start,
    /// At its middle.
    Middle,
    /// At its end.
    End,
}

/// An SVG document being written.
#[derive(Debug)]
pub struct Svg {
    buf: String,
    gradients: usize,
}

impl Svg {
    /// A `width × height` pixel document on a white background.
    pub fn new(width: f64, height: f64, title: &str) -> Self {
        let mut buf = String::new();
        let _ = writeln!(buf, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
        let _ = writeln!(
            buf,
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="sans-serif">"#,
            w = N(width),
            h = N(height)
        );
        let _ = writeln!(buf, "<title>{}</title>", escape(title));
        let _ = writeln!(
            buf,
            r#"<rect x="0" y="0" width="{}" height="{}" fill="white"/>"#,
            N(width),
            N(height)
        );
        Self { buf, gradients: 0 }
    }

    /// A line segment.
    pub fn line(&mut self, a: Point, b: Point, stroke: Rgb, width: f64) {
        let _ = writeln!(
            self.buf,
            r#"<line x1="{}" y1="{}" x2="{}" y2="{}" stroke="{stroke}" stroke-width="{}"/>"#,
            N(a.0),
            N(a.1),
            N(b.0),
            N(b.1),
            N(width)
        );
    }

    /// A line segment with a tooltip.
    pub fn line_titled(
        &mut self,
        a: (f64, f64),
        b: (f64, f64),
        stroke: Rgb,
        width: f64,
        title: &str,
    ) {
        let _ = writeln!(
            self.buf,
            r#"<line x1="{}" y1="{}" x2="{}" y2="{}" stroke="{stroke}" stroke-width="{}"><title>{}</title></line>"#,
            N(a.0),
            N(a.1),
            N(b.0),
            N(b.1),
            N(width),
            escape(title)
        );
    }

    /// Many unconnected segments as one path (cheap for thousands of ticks).
    pub fn segments(&mut self, segs: &[(Point, Point)], stroke: Rgb, width: f64) {
        if segs.is_empty() {
            return;
        }
        self.buf.push_str("<path d=\"");
        for (a, b) in segs {
            let _ = write!(self.buf, "M{} {}L{} {}", N(a.0), N(a.1), N(b.0), N(b.1));
        }
        let _ = writeln!(
            self.buf,
            r#"" fill="none" stroke="{stroke}" stroke-width="{}"/>"#,
            N(width)
        );
    }

    /// A filled rectangle without a border.
    pub fn rect(&mut self, x: f64, y: f64, w: f64, h: f64, fill: Rgb) {
        let _ = writeln!(
            self.buf,
            r#"<rect x="{}" y="{}" width="{}" height="{}" fill="{fill}"/>"#,
            N(x),
            N(y),
            N(w),
            N(h)
        );
    }

    /// An unfilled rectangle.
    pub fn frame(&mut self, x: f64, y: f64, w: f64, h: f64, stroke: Rgb, width: f64) {
        let _ = writeln!(
            self.buf,
            r#"<rect x="{}" y="{}" width="{}" height="{}" fill="none" stroke="{stroke}" stroke-width="{}"/>"#,
            N(x),
            N(y),
            N(w),
            N(h),
            N(width)
        );
    }

    /// Opens a group of crisp-edged cells for a heat map: inside it, `rect` takes cell units,
    /// cell `(0, 0)` at `(x, y)` and each cell `size` pixels square. Integer cell edges keep
    /// neighbouring cells free of hairline gaps.
    pub fn open_cells(&mut self, (x, y): Point, size: f64) {
        let _ = writeln!(
            self.buf,
            r#"<g shape-rendering="crispEdges" transform="translate({} {}) scale({})">"#,
            N(x),
            N(y),
            Num(size)
        );
    }

    /// Closes a group.
    pub fn close_group(&mut self) {
        self.buf.push_str("</g>\n");
    }

    /// A line of text at `(x, y)` (the baseline), `size` px.
    pub fn text(&mut self, x: f64, y: f64, size: f64, anchor: Anchor, content: &str) {
        let anchor = match anchor {
            Anchor::Start => "start",
            Anchor::Middle => "middle",
            Anchor::End => "end",
        };
        let _ = writeln!(
            self.buf,
            r#"<text x="{}" y="{}" font-size="{}" text-anchor="{anchor}">{}</text>"#,
            N(x),
            N(y),
            N(size),
            escape(content)
        );
    }

    /// A horizontal colour bar with its top left corner at `(x, y)` and size `(w, h)`, with the values at its ends and middle
    /// written under it and `label` above it.
    pub fn colour_bar(
        &mut self,
        (x, y): Point,
        (w, h): Point,
        map: ColourMap,
        scale: Scale,
        label: &str,
    ) {
        self.gradients += 1;
        let id = format!("bar{}", self.gradients);
        let _ = writeln!(
            self.buf,
            r#"<defs><linearGradient id="{id}" x1="0" y1="0" x2="1" y2="0">"#
        );
        for (offset, c) in map.stops() {
            let _ = writeln!(
                self.buf,
                r#"<stop offset="{}" stop-color="{c}"/>"#,
                N(offset)
            );
        }
        let _ = writeln!(self.buf, "</linearGradient></defs>");
        let _ = writeln!(
            self.buf,
            r#"<rect x="{}" y="{}" width="{}" height="{}" fill="url(#{id})" stroke="black" stroke-width="0.5"/>"#,
            N(x),
            N(y),
            N(w),
            N(h)
        );
        self.text(x, y - 5.0, 13.0, Anchor::Start, label);
        let ticks = [
            (0.0, Anchor::Start),
            (0.5, Anchor::Middle),
            (1.0, Anchor::End),
        ];
        for (t, anchor) in ticks {
            let tx = x + w * t;
            self.line((tx, y + h), (tx, y + h + 4.0), Rgb(0, 0, 0), 1.0);
            let v = scale.value_at(t);
            let s = if t == 0.0 && matches!(scale, Scale::Log { .. }) {
                format!("≤ {}", number(v))
            } else {
                number(v)
            };
            self.text(tx, y + h + 16.0, 12.0, anchor, &s);
        }
    }

    /// The finished document.
    pub fn finish(mut self) -> String {
        self.buf.push_str("</svg>\n");
        self.buf
    }
}

#[cfg(test)]
pub mod check {
    //! A tiny well-formedness check for the SVG this module writes.

    /// Checks that tags balance, every `<` has its `>`, `&` starts an entity, and every
    /// numeric attribute is a finite number. Returns the number of elements.
    pub fn well_formed(svg: &str) -> Result<usize, String> {
        let mut stack: Vec<&str> = Vec::new();
        let mut elements = 0;
        let mut rest = svg;
        while let Some(open) = rest.find('<') {
            check_text(&rest[..open])?;
            let after = &rest[open + 1..];
            let close = after.find('>').ok_or("a '<' without its '>'")?;
            let tag = &after[..close];
            if tag.contains('<') {
                return Err(format!("'<' inside a tag: {tag}"));
            }
            rest = &after[close + 1..];
            if tag.starts_with('?') {
                if !tag.ends_with('?') {
                    return Err(format!("bad declaration {tag}"));
                }
                continue;
            }
            if let Some(name) = tag.strip_prefix('/') {
                match stack.pop() {
                    Some(open) if open == name.trim() => {}
                    other => return Err(format!("</{name}> closes {other:?}")),
                }
                continue;
            }
            elements += 1;
            let self_closing = tag.ends_with('/');
            let body = tag.trim_end_matches('/');
            let name = body.split_whitespace().next().ok_or("empty tag")?;
            check_attributes(body)?;
            if !self_closing {
                stack.push(name);
            }
        }
        check_text(rest)?;
        if !stack.is_empty() {
            return Err(format!("unclosed {stack:?}"));
        }
        Ok(elements)
    }

    fn check_text(t: &str) -> Result<(), String> {
        if t.contains('>') {
            return Err(format!("stray '>' in {t:?}"));
        }
        for (k, _) in t.match_indices('&') {
            let ent = &t[k..];
            if !["&amp;", "&lt;", "&gt;", "&quot;", "&apos;"]
                .iter()
                .any(|e| ent.starts_with(e))
            {
                return Err(format!("bare '&' in {t:?}"));
            }
        }
        Ok(())
    }

    fn check_attributes(body: &str) -> Result<(), String> {
        const NUMERIC: [&str; 12] = [
            "x",
            "y",
            "x1",
            "y1",
            "x2",
            "y2",
            "width",
            "height",
            "stroke-width",
            "font-size",
            "offset",
            "r",
        ];
        let mut rest = body;
        while let Some(eq) = rest.find("=\"") {
            let name = rest[..eq].rsplit(char::is_whitespace).next().unwrap_or("");
            let after = &rest[eq + 2..];
            let end = after.find('"').ok_or("unterminated attribute")?;
            let value = &after[..end];
            check_text(value)?;
            if NUMERIC.contains(&name) {
                match value.parse::<f64>() {
                    Ok(v) if v.is_finite() => {}
                    _ => return Err(format!("{name}=\"{value}\" is not a finite number")),
                }
            }
            if name == "d" || name == "viewBox" || name == "transform" {
                let separator =
                    |c: char| c.is_ascii_alphabetic() || c.is_whitespace() || "(),".contains(c);
                for tok in value.split(separator) {
                    if !tok.is_empty() && !tok.parse::<f64>().is_ok_and(f64::is_finite) {
                        return Err(format!("{name} holds {tok:?}"));
                    }
                }
            }
            rest = &after[end + 1..];
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn colour_map_endpoints_and_clamping() {
        assert_eq!(ColourMap::Viridis.at(0.0), Rgb(0x44, 0x01, 0x54));
        assert_eq!(ColourMap::Viridis.at(1.0), Rgb(0xfd, 0xe7, 0x25));
        assert_eq!(ColourMap::Viridis.at(0.5), Rgb(0x21, 0x91, 0x8c));
        assert_eq!(ColourMap::Viridis.at(-3.0), ColourMap::Viridis.at(0.0));
        assert_eq!(ColourMap::Viridis.at(7.0), ColourMap::Viridis.at(1.0));
        assert_eq!(ColourMap::Viridis.at(f64::NAN), ColourMap::Viridis.at(0.0));
        assert_eq!(ColourMap::CoolWarm.at(0.0), Rgb(0x3b, 0x4c, 0xc0));
        assert_eq!(ColourMap::CoolWarm.at(0.5), Rgb(0xdd, 0xdd, 0xdd));
        assert_eq!(ColourMap::CoolWarm.at(1.0), Rgb(0xb4, 0x04, 0x26));
        assert_eq!(Rgb(0x44, 0x01, 0x54).to_string(), "#440154");
    }

    #[test]
    fn viridis_gets_lighter_along_the_map() {
        // Perceptual: luminance increases monotonically.
        let lum =
            |c: Rgb| 0.2126 * f64::from(c.0) + 0.7152 * f64::from(c.1) + 0.0722 * f64::from(c.2);
        let mut last = -1.0;
        for k in 0..=100 {
            let l = lum(ColourMap::Viridis.at(f64::from(k) / 100.0));
            assert!(l >= last - 0.5, "{k}: {l} < {last}");
            last = l;
        }
    }

    #[test]
    fn scales() {
        let lin = Scale::Linear { lo: -2.0, hi: 2.0 };
        assert_eq!(lin.fraction(0.0), 0.5);
        assert_eq!(lin.fraction(-5.0), 0.0);
        assert_eq!(lin.fraction(2.0), 1.0);
        assert_eq!(lin.value_at(1.0), 2.0);
        assert_eq!(Scale::Linear { lo: 1.0, hi: 1.0 }.fraction(1.0), 0.5);
        let div = Scale::Diverging { lo: -1.0, hi: 4.0 };
        assert_eq!(div.fraction(-1.0), 0.0);
        assert_eq!(div.fraction(0.0), 0.5);
        assert_eq!(div.fraction(2.0), 0.75);
        assert_eq!(div.fraction(9.0), 1.0);
        assert_eq!(div.value_at(0.0), -1.0);
        assert_eq!(div.value_at(0.5), 0.0);
        assert_eq!(div.value_at(1.0), 4.0);
        assert_eq!(Scale::Diverging { lo: 0.0, hi: 1.0 }.fraction(-1.0), 0.5);
        let log = Scale::Log { lo: 1e-4, hi: 1.0 };
        assert_eq!(log.fraction(-1.0), 0.0);
        assert_eq!(log.fraction(0.0), 0.0);
        assert!((log.fraction(1e-2) - 0.5).abs() < 1e-12);
        assert!((log.value_at(0.5) - 1e-2).abs() < 1e-15);
        assert_eq!(log.fraction(10.0), 1.0);
    }

    #[test]
    fn numbers_for_labels() {
        assert_eq!(number(0.0), "0");
        assert_eq!(number(1.2345678), "1.235");
        assert_eq!(number(0.012345), "0.01235");
        assert_eq!(number(-123.456), "-123.5");
        assert_eq!(number(1.5e-7), "1.500e-7");
    }

    #[test]
    fn documents_are_well_formed() {
        let mut svg = Svg::new(300.0, 200.0, "a <b> & \"c\"");
        svg.line((0.0, 0.0), (f64::NAN, f64::INFINITY), Rgb(1, 2, 3), 2.0);
        svg.line_titled((1.0, 1.0), (2.0, 2.0), Rgb(1, 2, 3), 2.0, "patch 1 & 2");
        svg.segments(
            &[((0.0, 0.0), (1.0, 1.0)), ((2.0, 2.0), (3.0, -3.0))],
            Rgb(0, 0, 0),
            1.0,
        );
        svg.open_cells((3.0, 4.0), 0.5);
        svg.rect(0.0, 0.0, 10.0, 10.0, Rgb(9, 9, 9));
        svg.close_group();
        svg.frame(0.0, 0.0, 10.0, 10.0, Rgb(0, 0, 0), 1.0);
        svg.text(5.0, 5.0, 12.0, Anchor::Middle, "x < y & y > z");
        svg.colour_bar(
            (10.0, 150.0),
            (200.0, 12.0),
            ColourMap::Viridis,
            Scale::Log { lo: 1e-3, hi: 1.0 },
            "I_ij",
        );
        let s = svg.finish();
        assert!(check::well_formed(&s).unwrap() > 10);
        assert!(!s.contains("NaN") && !s.contains("inf"));
    }

    #[test]
    fn the_checker_rejects_broken_documents() {
        assert!(check::well_formed("<a><b></a>").is_err());
        assert!(check::well_formed("<a>").is_err());
        assert!(check::well_formed("<a x=\"NaN\"/>").is_err());
        assert!(check::well_formed("<a>&</a>").is_err());
        assert!(check::well_formed("<a <b/>").is_err());
        assert!(check::well_formed("<a/>b>").is_err());
        assert_eq!(check::well_formed("<a><b/></a>"), Ok(2));
    }
}
