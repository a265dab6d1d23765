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

// ---- chapter 5: the radiosity channel ---------------------------------------------------

/// A row of a colour table: `(figure, patches, lines in millions, first quantity (R, G, B),
/// second quantity (R, G, B))`.
pub type RgbRow = (&'static str, usize, f64, [f64; 3], [f64; 3]);

/// Table 5.1: the labyrinth of Fig. 5.1 with constant radiosity (`ρ_i + E_i = 1`):
/// `(setting, H_P, H_S, I_S)` for visibility and radiosity. The thesis prints 4–6 decimals;
/// its two rows differ by up to 0.0043, which is its numerical error (they are equal in
/// exact arithmetic, 5.8–5.9).
pub const TABLE_5_1: [(&str, f64, f64, f64); 2] = [
    ("visibility", 10.6883, 6.47804, 4.21022),
    ("radiosity", 10.6842, 6.47833, 4.20591),
];

/// Table 5.2: the Cornell box (Fig. 5.2), regular meshes (I.a–c) and meshes from a
/// mutual-information-based oracle (II.a–c): `(figure, patches, lines in millions,
/// I_S (R, G, B), H_S (R, G, B))`.
pub const TABLE_5_2: [RgbRow; 6] = [
    (
        "Fig.5.2I.a",
        121,
        10.0,
        [0.935, 0.965, 0.960],
        [3.138, 2.636, 2.285],
    ),
    (
        "Fig.5.2I.b",
        481,
        10.0,
        [0.958, 0.974, 0.959],
        [4.210, 3.658, 3.278],
    ),
    (
        "Fig.5.2I.c",
        1924,
        100.0,
        [1.004, 1.014, 0.993],
        [6.170, 5.616, 5.243],
    ),
    (
        "Fig.5.2II.a",
        121,
        10.0,
        [1.009, 1.028, 1.014],
        [3.407, 2.989, 2.694],
    ),
    (
        "Fig.5.2II.b",
        493,
        10.0,
        [1.017, 1.017, 0.996],
        [5.077, 4.538, 4.214],
    ),
    (
        "Fig.5.2II.c",
        1933,
        100.0,
        [1.052, 1.046, 1.020],
        [6.849, 6.339, 6.059],
    ),
];

/// Table 5.3: the tetrahedron (Fig. 4.3) with one blue face: `(figure, patches, lines in
/// millions, I_S (R, G, B), H_S (R, G, B))`. The 151- and 793-patch meshes are irregular.
pub const TABLE_5_3: [RgbRow; 3] = [
    (
        "Fig.4.3a",
        4,
        10.0,
        [1.000, 1.000, 0.000],
        [0.000, 0.000, 1.362],
    ),
    (
        "Fig.4.3b",
        151,
        10.0,
        [2.912, 2.158, 0.000],
        [4.003, 3.077, 6.117],
    ),
    (
        "Fig.4.3c",
        793,
        10.0,
        [3.432, 2.765, 0.000],
        [5.696, 4.854, 8.259],
    ),
];

/// Table 5.4: continuous radiosity mutual information `I_S^c` (R, G, B): `(figure, patches,
/// lines in millions, I_S^c)`.
pub const TABLE_5_4: [(&str, usize, f64, [f64; 3]); 13] = [
    ("Fig.4.4a", 19, 10.0, [1.676, 1.676, 1.676]),
    ("Fig.4.4b", 196, 10.0, [1.654, 1.654, 1.654]),
    ("Fig.4.4c", 826, 10.0, [1.286, 1.286, 1.286]),
    ("Fig.4.9a", 1924, 100.0, [1.163, 1.163, 1.163]),
    ("Fig.4.9b", 1924, 100.0, [1.129, 1.129, 1.129]),
    ("Fig.4.9c", 1924, 100.0, [1.375, 1.375, 1.375]),
    ("Fig.5.3a", 444, 50.0, [2.443, 2.443, 2.443]),
    ("Fig.5.3b", 759, 100.0, [2.455, 2.455, 2.455]),
    ("Fig.5.4a", 2029, 100.0, [2.149, 1.481, 1.980]),
    ("Fig.5.4b", 546, 100.0, [5.087, 5.300, 0.541]),
    ("Fig.4.3a", 4, 10.0, [3.219, 3.197, 0.000]),
    ("Fig.4.3b", 151, 10.0, [3.419, 3.102, 0.000]),
    ("Fig.4.3c", 793, 10.0, [3.629, 3.158, 0.000]),
];

/// Table 5.5: `I_S` and `I_S^c` (R, G, B) of the Cornell box at regular (Fig. 5.2I, 5.5a) and
/// oracle-driven (Fig. 5.2II, 5.5b) meshes: `(figure, patches, lines in millions, I_S,
/// I_S^c)`.
pub const TABLE_5_5: [RgbRow; 8] = [
    (
        "Fig.5.2I.a",
        121,
        10.0,
        [0.935, 0.965, 0.960],
        [1.132, 1.144, 1.107],
    ),
    (
        "Fig.5.2I.b",
        481,
        10.0,
        [0.958, 0.974, 0.959],
        [1.055, 1.066, 1.037],
    ),
    (
        "Fig.5.2I.c",
        1924,
        100.0,
        [1.004, 1.014, 0.993],
        [1.044, 1.051, 1.024],
    ),
    (
        "Fig.5.5a",
        7744,
        1000.0,
        [1.027, 1.028, 1.013],
        [1.032, 1.032, 1.016],
    ),
    (
        "Fig.5.2II.a",
        121,
        10.0,
        [1.009, 1.028, 1.014],
        [1.194, 1.194, 1.138],
    ),
    (
        "Fig.5.2II.b",
        493,
        10.0,
        [1.017, 1.017, 0.996],
        [1.082, 1.080, 1.043],
    ),
    (
        "Fig.5.2II.c",
        1933,
        100.0,
        [1.052, 1.046, 1.020],
        [1.070, 1.064, 1.032],
    ),
    (
        "Fig.5.5b",
        6595,
        500.0,
        [1.078, 1.064, 1.046],
        [1.056, 1.048, 1.027],
    ),
];

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

/// Figure 6.6: leaves of the Cornell box meshes of the power-based, KS-based (2.50) and
/// MI-based (6.30) oracles, coarse (I) and fine (II), with 10 point pairs per evaluation.
pub const FIGURE_6_6_PATCHES: [(&str, usize, usize); 3] = [
    ("power", 1051, 1979),
    ("ks-av", 1039, 1955),
    ("mi", 1047, 1995),
];

/// Figure 6.9: leaves of the KS-based and MI-based Cornell box meshes with 4 point pairs
/// per evaluation (the robustness experiment).
pub const FIGURE_6_9_PATCHES: [(&str, usize); 2] = [("ks-av", 875), ("mi", 891)];

// ---- the flatland catalogue (`sceneinfo::scene::catalogue`) -----------------------------

/// The values the thesis prints for scenes of the flatland catalogue, by catalogue name:
/// `I_S^c` in bits (Figs. 4.12–4.22, Table 4.12, Figs. 6.15–6.16), except for the
/// `64-squares-*` scenes (Fig. 3.12), whose value is the discrete `I_S` of Table 3.6 (Monte
/// Carlo, 80 + 256 patches). Scenes the thesis prints nothing for are absent. Each catalogue
/// constructor documents how its geometry was set to give its value.
pub const CATALOGUE: [(&str, f64); 18] = [
    ("koch-0", 1.285),
    ("triangle-0", 1.284),
    ("triangle-3", 2.311),
    ("l-room-0", 0.788),
    ("l-room-2", 1.218),
    ("l-room-3", 1.319),
    ("pentagonal-star-0", 0.583),
    ("pentagonal-star-8", 4.067),
    ("pentagonal-star-subscene", 1.750),
    ("rotating-square-8", 3.477),
    ("rotating-square-subscene", 1.474),
    ("square-to-corner-8", 3.304),
    ("rect-1", 0.789),
    ("64-squares-a", 6.148),
    ("64-squares-b", 5.391),
    ("64-squares-c", 4.990),
    ("refinement-1", 2.519),
    ("refinement-2", 3.245),
];

/// The value [`CATALOGUE`] holds for the catalogue scene `name`, if the thesis prints one.
#[must_use]
pub fn catalogue_value(name: &str) -> Option<f64> {
    CATALOGUE.iter().find(|(n, _)| *n == name).map(|&(_, v)| v)
}

/// Table 3.6: `H_S` of the three 64-squares scenes (Fig. 3.12 a–c; 10⁶ global lines), whose
/// `I_S` is in [`CATALOGUE`].
pub const TABLE_3_6_H_S: [(&str, f64); 3] = [
    ("64-squares-a", 2.244),
    ("64-squares-b", 3.001),
    ("64-squares-c", 3.443),
];

/// Fig. 4.14b's L-shaped room: the `I_S^c` the catalogue's Fig. 4.14 trend test has always
/// used. The thesis' text (§4.5.2) quotes only (a), (c) and (d), and our copy lacks the
/// figure's labels, so this value is not in [`CATALOGUE`] and `reproduce` does not compare
/// with it.
pub const FIGURE_4_14_B: f64 = 0.929;
