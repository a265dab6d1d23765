//! The thesis' published numbers, as data.
//!
//! Values are copied from M. Feixas, *An Information-Theory Framework for the Study of the
//! Complexity of Visibility and Radiosity in a Scene* (UPC, 2002), rounded as printed there
//! (3 decimals). `sceneinfo reproduce` and the test-suite compare the crate's results
//! against them; keeping them in one place means both use the same numbers.

/// The patches-per-side columns of Tables 3.4, 3.5 and 4.10.
pub const POLYGON_PER_SIDE: [u64; 3] = [10, 30, 50];

/// The side counts of the rows of Tables 3.4, 3.5 and 4.10 (regular polygons).
pub const POLYGON_SIDES: [usize; 10] = [3, 4, 5, 6, 7, 8, 9, 10, 11, 12];

/// Table 3.4: `H_S` of regular polygons (rows: 3–12 sides; columns: 10, 30, 50 patches per
/// side), exact form factors by the string rule.
pub const TABLE_3_4_H_S: [[f64; 3]; 10] = [
    [3.739, 5.248, 5.969],
    [4.590, 6.138, 6.867],
    [5.094, 6.657, 7.389],
    [5.455, 7.025, 7.758],
    [5.737, 7.311, 8.045],
    [5.969, 7.545, 8.281],
    [6.166, 7.745, 8.480],
    [6.338, 7.918, 8.654],
    [6.491, 8.072, 8.808],
    [6.628, 8.210, 8.946],
];

/// Table 3.5: `I_S` of regular polygons (same layout as [`TABLE_3_4_H_S`]).
pub const TABLE_3_5_I_S: [[f64; 3]; 10] = [
    [1.168, 1.244, 1.260],
    [0.732, 0.769, 0.777],
    [0.550, 0.572, 0.577],
    [0.452, 0.467, 0.470],
    [0.393, 0.404, 0.406],
    [0.353, 0.362, 0.363],
    [0.326, 0.332, 0.333],
    [0.306, 0.311, 0.312],
    [0.290, 0.295, 0.296],
    [0.279, 0.282, 0.283],
];

/// Table 4.10, last column: `I_S^c` of regular polygons of 3–12 sides (10⁵ global lines in
/// the thesis, so each value carries a Monte Carlo error of a few thousandths).
pub const TABLE_4_10_I_S_CONTINUOUS: [f64; 10] = [
    1.284, 0.788, 0.583, 0.475, 0.408, 0.366, 0.336, 0.314, 0.297, 0.284,
];

/// Table 4.11: the thesis' rounded exact values and its Monte Carlo (10⁵ global lines)
/// results for the circle, the regular hexagon, the square and the equilateral triangle:
/// `(name, exact, monte_carlo)`.
pub const TABLE_4_11: [(&str, f64, f64); 4] = [
    ("circle", 0.209, 0.209),
    ("hexagon", 0.475, 0.475),
    ("square", 0.789, 0.788),
    ("equilateral triangle", 1.285, 1.284),
];

/// Table 4.12 (Proposition 2): for the rotating square (Fig. 4.19i) and the pentagonal star
/// (Fig. 4.18i): `(name, I^c of a subscene, number of subscenes N, I_S^c of the scene)`.
pub const TABLE_4_12: [(&str, f64, u32, f64); 2] = [
    ("square rotation", 1.474, 4, 3.477),
    ("pentagonal star", 1.750, 5, 4.067),
];

/// Values quoted in the text of §4.5.2: `(what, I_S^c)`.
pub const SECTION_4_5_2_QUOTES: [(&str, f64); 4] = [
    ("triangle of Fig. 4.13(d)", 2.311),
    ("L-shaped room of Fig. 4.14(c)", 1.218),
    ("L-shaped room of Fig. 4.14(d)", 1.319),
    ("square advanced into a corner, Fig. 4.20(i)", 3.304),
];

/// Tables 3.2 and 3.8: the empty unit cube cut into 10², 20², 30² patches per face (600,
/// 2400, 5400 patches): `(patches, lines, H_S, I_S, E(MSE))` by global lines. The thesis does
/// not state its `E(MSE)` normalisation: its values are a constant multiple of `n − ΣF²`.
pub const TABLE_3_8: [(usize, f64, f64, f64, f64); 9] = [
    (600, 1e7, 7.821, 1.408, 497.7),
    (600, 1e8, 7.837, 1.392, 497.7),
    (600, 1e9, 7.838, 1.391, 497.7),
    (2400, 1e7, 9.420, 1.809, 2012.7),
    (2400, 1e8, 9.705, 1.524, 2013.0),
    (2400, 1e9, 9.731, 1.498, 2013.0),
    (5400, 1e7, 9.684, 2.715, 4543.9),
    (5400, 1e8, 10.708, 1.691, 4545.8),
    (5400, 1e9, 10.852, 1.547, 4546.1),
];

/// Table 4.3's 10⁵-line rows for the same cubes: `(patches, H_S, I_S, I_S^c)`.
pub const TABLE_4_3_FEW_LINES: [(usize, f64, f64, f64); 3] = [
    (600, 6.482, 2.747, 1.610),
    (2400, 5.342, 5.887, 1.608),
    (5400, 4.313, 8.086, 1.610),
];

/// Table 3.3: the empty cube and the cube rooms with 27, 64 and 512 small cubes, random (a)
/// and clustered (b, c), 10⁷ global lines: `(preset, figure, H_S, I_S, H_S/H_P)`.
pub const TABLE_3_3: [(&str, &str, f64, f64, f64); 7] = [
    ("cube", "Fig. 3.5a", 7.821, 1.408, 0.847),
    ("cubes-27-random", "Fig. 3.7a", 7.780, 1.669, 0.823),
    ("cubes-27-clustered", "Fig. 3.7b", 7.589, 1.861, 0.803),
    ("cubes-64-random", "Fig. 3.8a", 7.709, 2.009, 0.793),
    ("cubes-64-clustered", "Fig. 3.8b", 7.606, 2.112, 0.783),
    ("cubes-512-random", "Fig. 3.3a", 6.761, 4.779, 0.586),
    ("cubes-512-clustered", "Fig. 3.3c", 4.849, 6.692, 0.420),
];

/// Table 4.2: `I_S^c` of the rooms with tables and chairs (Fig. 4.2 a–f), 10⁶ global lines.
pub const TABLE_4_2: [(&str, f64); 6] = [
    ("table-chairs-a", 3.837),
    ("table-chairs-b", 4.102),
    ("table-chairs-c", 5.023),
    ("table-chairs-d", 5.043),
    ("table-chairs-e", 5.044),
    ("table-chairs-f", 5.089),
];

/// Table 4.1: `I_S^c` of the platonic solids and the Cornell box (10⁶ global lines):
/// `(name, I_S^c)`.
pub const TABLE_4_1: [(&str, f64); 7] = [
    ("sphere", 0.0),
    ("icosahedron", 0.543),
    ("dodecahedron", 0.825),
    ("octahedron", 1.258),
    ("cube", 1.609),
    ("tetrahedron", 2.626),
    ("Cornell box", 3.274),
];

/// Independent high-precision `I_S^c` of the regular solids quoted by the project's issue
/// tracker (not the thesis): `(name, value, uncertainty)`. The thesis' dodecahedron and
/// tetrahedron are off beyond their Monte Carlo error.
pub const PLATONIC_REFERENCE: [(&str, f64, f64); 5] = [
    ("icosahedron", 0.5425, 0.0005),
    ("dodecahedron", 0.8135, 0.0001),
    ("octahedron", 1.2581, 0.0005),
    ("cube", 1.6105, 0.0005),
    ("tetrahedron", 2.6203, 0.0005),
];

/// Half a unit in the last printed place of the tables above: the rounding error of a
/// correct value.
pub const TABLE_ROUNDING: f64 = 0.0005;

/// Table 4.4: the room with 512 random cubes (Fig. 3.3a): `(global lines, I_S, I_S^c)`.
/// `I_S` falls as lines grow (few lines per patch overstate the correlation); `I_S^c` is
/// stable from 10⁴ lines.
pub const TABLE_4_4: [(f64, f64, f64); 4] = [
    (1e4, 8.773, 5.650),
    (1e5, 6.398, 5.636),
    (1e6, 5.171, 5.631),
    (1e7, 4.779, 5.632),
];

/// Table 4.5: the tetrahedron (Fig. 4.3) with 4, 151 and 793 patches, 10⁷ local lines:
/// `(patches, I_S, I_S^c)`.
pub const TABLE_4_5: [(usize, f64, f64); 3] =
    [(4, 0.415, 2.626), (151, 1.217, 2.626), (793, 1.445, 2.626)];

/// Table 4.6: the Cornell box (Fig. 4.4) with 19, 196, 826 and 1924 patches:
/// `(patches, global lines, I_S, I_S^c)`.
pub const TABLE_4_6: [(usize, f64, f64, f64); 4] = [
    (19, 1e7, 0.690, 3.273),
    (196, 1e7, 2.199, 3.273),
    (826, 1e7, 2.558, 3.273),
    (1924, 1e8, 2.752, 3.273),
];

/// Table 4.7: 64 cubes expanding from the centre to the walls, cubes discretised finer
/// (Fig. 4.5 a–f; 1536 + 384 patches), 10⁸ global lines: `(I_S, I_S^c)` per scene.
pub const TABLE_4_7: [(f64, f64); 6] = [
    (5.492, 6.430),
    (5.054, 5.678),
    (4.672, 5.177),
    (4.395, 4.867),
    (4.356, 5.015),
    (4.775, 6.055),
];

/// Table 4.8: the same scenes with the walls discretised finer (Fig. 4.6 a–f; 384 + 1536
/// patches): `(I_S, I_S^c)` per scene.
pub const TABLE_4_8: [(f64, f64); 6] = [
    (5.110, 6.430),
    (4.809, 5.678),
    (4.543, 5.177),
    (4.348, 4.867),
    (4.483, 5.015),
    (4.932, 6.055),
];

/// Fig. 6.12: the 6-patch equilateral triangle with each patch split in two, symmetrically
/// about the sides' midpoints; `I_S` is largest for the cut at this fraction of the side from
/// the vertex (15.6%).
pub const FIGURE_6_12_BEST_CUT: f64 = 0.156;

/// One row of Tables 6.1 and 6.2: a discretisation of a scene and its measures.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiscretisationRow {
    /// The scene (a catalogue name, or `"triangle"`).
    pub scene: &'static str,
    /// How it was discretised: `optimal`, `regular`, `power` or `de` (DE-based).
    pub algorithm: &'static str,
    /// `I_S^c`.
    pub i_s_continuous: f64,
    /// `I_S`.
    pub i_s: f64,
    /// `H_S`.
    pub h_s: f64,
    /// `H_J`.
    pub h_j: f64,
    /// `E(MSE)`, printed as a whole number.
    pub e_mse: f64,
    /// `δ̄` in per cent.
    pub delta_percent: f64,
}

const fn row(scene: &'static str, algorithm: &'static str, v: [f64; 6]) -> DiscretisationRow {
    DiscretisationRow {
        scene,
        algorithm,
        i_s_continuous: v[0],
        i_s: v[1],
        h_s: v[2],
        h_j: v[3],
        e_mse: v[4],
        delta_percent: v[5],
    }
}

/// Table 6.1: the equilateral triangle with each half side cut into three (18 patches), the
/// `I_S`-maximising cuts (`optimal`) and the regular ones.
pub const TABLE_6_1: [DiscretisationRow; 2] = [
    row(
        "triangle",
        "optimal",
        [1.285, 1.137, 2.896, 6.929, 14.0, 11.52],
    ),
    row(
        "triangle",
        "regular",
        [1.285, 1.097, 3.073, 7.243, 15.0, 14.63],
    ),
];

/// Table 6.2: scenes I and II (the catalogue's `refinement-1`, `refinement-2`: our versions
/// of the thesis' drawings) refined from 26 to 208 patches by the regular, power-based and
/// DE-based (`de`) strategies.
pub const TABLE_6_2: [DiscretisationRow; 6] = [
    row(
        "refinement-1",
        "regular",
        [2.519, 2.492, 5.208, 12.908, 68.0, 1.07],
    ),
    row(
        "refinement-1",
        "power",
        [2.519, 2.490, 5.220, 12.930, 68.0, 1.15],
    ),
    row(
        "refinement-1",
        "de",
        [2.519, 2.496, 4.715, 11.926, 67.0, 0.90],
    ),
    row(
        "refinement-2",
        "regular",
        [3.245, 3.173, 4.530, 12.233, 63.0, 2.21],
    ),
    row(
        "refinement-2",
        "power",
        [3.245, 3.185, 4.280, 11.745, 62.0, 1.84],
    ),
    row(
        "refinement-2",
        "de",
        [3.245, 3.195, 3.899, 10.993, 61.0, 1.54],
    ),
];

/// The patch counts of Figs. 6.15–6.19 (from the 26 patches of scenes I and II).
pub const REFINEMENT_PATCH_COUNTS: [usize; 4] = [26, 52, 104, 208];

/// §6.1, Figs. 6.2 and 6.3: the cut parallel to the shared edge that gains the most
/// information, as a fraction of the side from the edge, for two squares sharing an edge
/// (40%) and for a square in the corner of three (39%).
pub const SECTION_6_1_BEST_PARALLEL_CUT: [(&str, f64); 2] =
    [("two squares", 0.40), ("corner of three squares", 0.39)];

/// §6.1: the best cut of a patch with radiosity `B(l) = lⁿ B`, `n = 1..4`, by mutual
/// information (the thesis' expression from 5.42) and by mean square error.
pub const SECTION_6_1_GRADIENT_CUTS: [(u32, f64, f64); 4] = [
    (1, 0.48, 0.5),
    (2, 0.61, 0.64),
    (3, 0.68, 0.72),
    (4, 0.74, 0.77),
];
