//! Pictures shared by commands: the flatland scene picture (`draw FILE.flat --svg`, and
//! `refine FILE.flat --svg` of the refined mesh), its legend and the choice of colour map
//! for a per-patch quantity (the SVG of `draw`, the PLY of `draw FILE.obj`). Here rather
//! than in `draw` so that commands never use each other (`tests/layers.rs`).

use sceneinfo::scene::Scene2;

use crate::args::Colour;
use crate::svg::{Anchor, ColourMap, Rgb, Scale, Svg, number};

/// Patches get a tooltip with their value up to this many patches.
const TOOLTIP_LIMIT: usize = 5000;
/// Patches are drawn this many pixels in front of their surface.
const FRONT_OFFSET: f64 = 2.0;
/// Patch boundaries are ticked on surfaces whose patches are at least this long, in pixels.
const MIN_TICKED_PATCH: f64 = 6.0;
/// Blank space around a picture, in pixels.
pub const MARGIN: f64 = 30.0;

/// The legend's name of a quantity.
pub fn quantity_name(c: Colour) -> &'static str {
    match c {
        Colour::I => "I_i: information transfer of patch i (6.8), bits",
        Colour::H => "H_i: entropy of patch i (3.2), bits",
        Colour::Ic => "I_i^c: continuous information transfer of patch i (6.37), bits",
        Colour::Delta => "I_i^c − I_i: discretisation error of patch i (§6.5.2), bits",
    }
}

/// The smallest and largest of `values` (`(0, 0)` for none).
pub fn range(values: impl IntoIterator<Item = f64>) -> (f64, f64) {
    values
        .into_iter()
        .fold(None, |acc: Option<(f64, f64)>, v| match acc {
            None => Some((v, v)),
            Some((lo, hi)) => Some((lo.min(v), hi.max(v))),
        })
        .unwrap_or((0.0, 0.0))
}

/// The colour map and scale for the patches: diverging about zero for the signed
/// discretisation error, viridis from the smallest to the largest value otherwise.
pub fn patch_colours(colour: Colour, values: &[f64]) -> (ColourMap, Scale) {
    let (lo, hi) = range(values.iter().copied());
    match colour {
        Colour::Delta => (
            ColourMap::CoolWarm,
            Scale::Diverging {
                lo: lo.min(0.0),
                hi: hi.max(0.0),
            },
        ),
        _ => (ColourMap::Viridis, Scale::Linear { lo, hi }),
    }
}

/// The text and colour bar under a picture.
pub struct Legend {
    /// The first line: the scene's name and size.
    pub heading: String,
    /// Lines under it: where the numbers come from.
    pub notes: Vec<String>,
    /// The colour bar's label.
    pub label: String,
    /// The colour map of the bar.
    pub map: ColourMap,
    /// The values the bar spans.
    pub scale: Scale,
}

impl Legend {
    /// Its height in pixels.
    pub fn height(&self) -> f64 {
        16.0 * self.notes.len() as f64 + 112.0
    }

    /// Draws it with its top at `top`.
    pub fn draw(&self, svg: &mut Svg, top: f64, width: f64) {
        let mut y = top + 18.0;
        svg.text(MARGIN, y, 14.0, Anchor::Start, &self.heading);
        for note in &self.notes {
            y += 16.0;
            svg.text(MARGIN, y, 12.0, Anchor::Start, note);
        }
        let bar_width = (width - 2.0 * MARGIN).min(420.0);
        svg.colour_bar(
            (MARGIN, y + 34.0),
            (bar_width, 14.0),
            self.map,
            self.scale,
            &self.label,
        );
    }
}

/// Maps scene coordinates (y up) to picture pixels (y down).
#[derive(Clone, Copy, Debug)]
struct View {
    min_x: f64,
    max_y: f64,
    scale: f64,
    left: f64,
    top: f64,
}

impl View {
    fn px(&self, p: sceneinfo::geom::DVec2) -> (f64, f64) {
        (
            self.left + (p.x - self.min_x) * self.scale,
            self.top + (self.max_y - p.y) * self.scale,
        )
    }

    /// Pixel position of `p` moved [`FRONT_OFFSET`] pixels towards the front of a surface of
    /// unit normal `n` (so the two sides of a two-sided wall both show).
    fn front(&self, p: sceneinfo::geom::DVec2, n: sceneinfo::geom::DVec2) -> (f64, f64) {
        let (x, y) = self.px(p);
        (x + n.x * FRONT_OFFSET, y - n.y * FRONT_OFFSET)
    }
}

/// The scene picture: patches as coloured strokes over a dark casing, small ticks at patch
/// boundaries, a one-sided tick at each surface's midpoint on its front side, and a legend.
pub fn scene_picture(
    scene: &Scene2,
    values: &[f64],
    colour: Colour,
    name: &str,
    notes: &[String],
    width: f64,
) -> String {
    let (lo, hi) = scene.bounds();
    let (dx, dy) = (hi.x - lo.x, hi.y - lo.y);
    let inner = width - 2.0 * MARGIN;
    let max_height = 1.25 * width - 2.0 * MARGIN;
    let scale = match (dx > 0.0, dy > 0.0) {
        (true, true) => (inner / dx).min(max_height / dy),
        (true, false) => inner / dx,
        _ => max_height / dy,
    };
    let height = dy * scale + 2.0 * MARGIN;
    let view = View {
        min_x: lo.x,
        max_y: hi.y,
        scale,
        left: MARGIN + (inner - dx * scale) / 2.0,
        top: MARGIN,
    };
    let patches = scene.patches();
    let casing: Vec<_> = patches
        .iter()
        .map(|p| {
            let n = p.segment.normal();
            (view.front(p.segment.a, n), view.front(p.segment.b, n))
        })
        .collect();

    // Patch boundaries: a short tick across the stroke at every patch end.
    let mut ticks = Vec::new();
    let mut normals = Vec::new();
    let mut crowded = false;
    for s in scene.surfaces() {
        let n = s.segment.normal();
        let across = (n.x, -n.y);
        let tick = |p: (f64, f64), len: f64| {
            (
                (p.0 - across.0 * len, p.1 - across.1 * len),
                (p.0 + across.0 * len, p.1 + across.1 * len),
            )
        };
        let k = s.patches.len() as f64;
        if s.segment.length() * view.scale / k >= MIN_TICKED_PATCH {
            for p in &patches[s.patches.clone()] {
                ticks.push(tick(view.front(p.segment.a, n), 4.0));
            }
            ticks.push(tick(view.front(s.segment.b, n), 4.0));
        } else {
            crowded = true;
        }
        let m = view.front(s.segment.midpoint(), n);
        normals.push((m, (m.0 + across.0 * 12.0, m.1 + across.1 * 12.0)));
    }
    let (map, value_scale) = patch_colours(colour, values);
    let (vlo, vhi) = range(values.iter().copied());
    let mut legend_notes = notes.to_vec();
    legend_notes.push(
        "short black ticks: patch boundaries; red ticks: front side of each surface".to_owned(),
    );
    if crowded {
        legend_notes.push(format!(
            "(no boundary ticks on surfaces whose patches are shorter than {MIN_TICKED_PATCH} px)"
        ));
    }
    let legend = Legend {
        heading: format!(
            "{name}: {} patches, {} surfaces",
            scene.n_patches(),
            scene.surfaces().len()
        ),
        notes: legend_notes,
        label: format!(
            "{}; from {} to {}",
            quantity_name(colour),
            number(vlo),
            number(vhi)
        ),
        map,
        scale: value_scale,
    };
    let mut svg = Svg::new(
        width,
        height + legend.height(),
        &format!("sceneinfo draw {name}"),
    );

    svg.segments(&casing, Rgb(0x20, 0x20, 0x20), 4.5);
    for (i, (p, &(a, b))) in patches.iter().zip(&casing).enumerate() {
        let v = values.get(i).copied().unwrap_or(0.0);
        let c = map.at(value_scale.fraction(v));
        if patches.len() <= TOOLTIP_LIMIT {
            svg.line_titled(
                a,
                b,
                c,
                3.0,
                &format!("patch {i} (surface {}): {} bits", p.surface, number(v)),
            );
        } else {
            svg.line(a, b, c, 3.0);
        }
    }
    svg.segments(&ticks, Rgb(0x20, 0x20, 0x20), 1.0);
    svg.segments(&normals, Rgb(0xd0, 0x10, 0x10), 1.5);

    legend.draw(&mut svg, height, width);
    svg.finish()
}
