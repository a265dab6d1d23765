//! `sceneinfo field` and `measure --bounces` through the real binary (issue 20, items 1–2):
//! JSON keys and values against closed forms, the PNG map, a path's animation complexity,
//! the 3D field by rasterisation at the centre of a cube, and refusals (bad points, a grid
//! of a 3D scene, unwritable outputs) with exit 2.

mod common;

use common::{bin, number, stdout_of, temp};

/// The numbers of the array after `"key":[` (`null` → NaN).
fn values(json: &str, key: &str) -> Vec<f64> {
    let at = json
        .find(&format!("\"{key}\":["))
        .unwrap_or_else(|| panic!("no {key} in {json}"));
    let rest = &json[at + key.len() + 4..];
    let end = rest.find(']').unwrap();
    rest[..end]
        .split(',')
        .map(|x| x.parse().unwrap_or(f64::NAN))
        .collect()
}

fn write(name: &str, text: &str) -> std::path::PathBuf {
    let path = temp(name);
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn centre_of_a_square_sees_four_quarters() {
    let square = write("square.flat", "poly 4 0 0 2 0 2 2 0 2\n");
    let json = stdout_of(&["field", square.to_str().unwrap(), "--at", "1,1", "--json"]);
    assert_eq!(number(&json, "h"), 2.0);
    assert!(number(&json, "i").abs() < 1e-15);
    let p = values(&json, "p");
    assert_eq!(p.len(), 5, "{json}");
    for q in &p[..4] {
        assert!((q - 0.25).abs() < 1e-15);
    }
    assert_eq!(p[4], 0.0);
    // The continuous term exceeds the discrete one: δ(x) > 0
    assert!(number(&json, "discretisation_error") > 0.0);
}

#[test]
fn grid_png_and_path() {
    let room = write(
        "occluded.flat",
        "poly 4 0 0 4 0 4 3 0 3 per_side 4\nseg 1.5 1 2.5 1 2\nseg 2.5 1 1.5 1 2\n",
    );
    let png = temp("field.png");
    let json = stdout_of(&[
        "field",
        room.to_str().unwrap(),
        "--grid",
        "8",
        "--png",
        png.to_str().unwrap(),
        "--path",
        "0.5,2:3.5,2",
        "--samples",
        "16",
        "--json",
    ]);
    assert_eq!(number(&json, "nx"), 8.0);
    assert_eq!(number(&json, "ny"), 6.0);
    let i = values(&json, "i");
    assert!(i.len() >= 48 && i[..48].iter().all(|v| v.is_finite() && *v >= 0.0));
    let bytes = std::fs::read(&png).unwrap();
    assert_eq!(&bytes[1..4], b"PNG");
    // A path in free space: every sample defined; C = ∫ I ds, its mean C / length
    let c = number(&json, "animation_complexity");
    let mean = number(&json, "mean_i");
    assert!((c / 3.0 - mean).abs() < 1e-12, "{c} {mean}");
    assert!(number(&json, "i_c_integral") >= c);
    // The table says the same
    let table = stdout_of(&[
        "field",
        room.to_str().unwrap(),
        "--path",
        "0.5,2:3.5,2",
        "--samples",
        "16",
    ]);
    assert!(table.contains("animation complexity"), "{table}");
}

#[test]
fn bounces_start_at_i_s_and_never_rise() {
    let room = write("bounce.flat", "poly 4 0 0 3 0 3 2 0 2 per_side 3\n");
    let measure = stdout_of(&["measure", room.to_str().unwrap(), "--json"]);
    let json = stdout_of(&[
        "measure",
        room.to_str().unwrap(),
        "--bounces",
        "30",
        "--json",
    ]);
    let curve = values(&json, "i_n");
    assert_eq!(curve.len(), 30);
    assert!((curve[0] - number(&measure, "i_s")).abs() < 1e-12);
    assert!(curve.windows(2).all(|w| w[1] <= w[0] + 1e-12));
    assert!(curve[29] < 1e-6 * curve[0]);
    assert!((number(&json, "excess_entropy") - curve[0]).abs() < 1e-9);
    let table = stdout_of(&["measure", room.to_str().unwrap(), "--bounces", "5"]);
    assert!(table.contains("I(X_0;X_n)"), "{table}");
}

/// `--walks`: the random-walk columns agree with the exact curve, exactly at n = 1 (the
/// last step is averaged over the rows, so one bounce is the rows themselves) and within
/// 3σ after (12 patches, 20,000 walks, seed 3); `--walks-only` prints the same columns
/// without the exact curve.
#[test]
fn walks_agree_with_the_exact_curve() {
    let room = write("walks.flat", "poly 4 0 0 3 0 3 2 0 2 per_side 3\n");
    let r = room.to_str().unwrap();
    let args = [
        "measure",
        r,
        "--bounces",
        "6",
        "--walks",
        "20000",
        "--seed",
        "3",
        "--json",
    ];
    let json = stdout_of(&args);
    let exact = values(&json, "i_n");
    let walks = values(&json, "i_n_walks");
    let sigma = values(&json, "i_n_walks_sigma");
    let bias = values(&json, "i_n_walks_bias");
    assert_eq!((walks.len(), sigma.len(), bias.len()), (6, 6, 6));
    assert!(
        (walks[0] - exact[0]).abs() < 1e-12 && sigma[0] == 0.0,
        "{json}"
    );
    for k in 1..6 {
        assert!(sigma[k] > 0.0 && bias[k] > 0.0, "{json}");
        assert!(
            (walks[k] - exact[k]).abs() <= 3.0 * sigma[k],
            "n={}: {json}",
            k + 1
        );
    }
    let mut only = args.to_vec();
    only.push("--walks-only");
    let alone = stdout_of(&only);
    assert!(!alone.contains("\"i_n\""), "{alone}");
    assert_eq!(values(&alone, "i_n_walks"), walks);
    assert!((number(&alone, "i_s") - exact[0]).abs() < 1e-12);
}

/// A curve too large for dense powers is refused with a pointer to `--walks` (100 patches,
/// 100,000 bounces: `(N − 1) n³` is 10¹¹, over the cap), before any work.
#[test]
fn too_large_for_dense_powers_points_to_walks() {
    let room = write("large.flat", "poly 4 0 0 3 0 3 2 0 2 per_side 25\n");
    let out = bin()
        .args(["measure", room.to_str().unwrap(), "--bounces", "100000"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("--walks W"), "{err}");
}

#[test]
fn refusals_exit_2() {
    let square = write("refuse.flat", "poly 4 0 0 1 0 1 1 0 1\n");
    let s = square.to_str().unwrap();
    for args in [
        vec!["field", s, "--at", "nan,1"],
        vec!["field", s, "--at", "1"],
        vec!["field", s, "--path", "0,0"],
        vec!["field", s],
        vec!["field", s, "--grid", "0"],
        vec!["measure", s, "--bounces", "0"],
    ] {
        let out = bin().args(&args).output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{args:?}");
    }
    // A 3D scene: rasterised --at and --path; --grid and 2D points refused
    let cube = common::preset(&["cube", "--grid", "1"], "field-cube.obj");
    let c = cube.to_str().unwrap();
    let json = stdout_of(&[
        "field",
        c,
        "--at",
        "0.5,0.5,0.5",
        "--json",
        "--resolution",
        "64",
    ]);
    // Six faces, each one cube-map face exactly: H = log₂ 6, I = 0
    assert!((number(&json, "h") - 6f64.log2()).abs() < 1e-9, "{json}");
    assert!(number(&json, "i").abs() < 1e-9);
    for args in [
        vec!["field", c, "--grid", "4"],
        vec!["field", c, "--at", "0.5,0.5"],
    ] {
        let out = bin().args(&args).output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(String::from_utf8_lossy(&out.stderr).contains("valid, but"));
    }
    // An unwritable picture is refused before the job
    let out = bin()
        .args(["field", s, "--grid", "4", "--png", "/nonexistent-dir/x.png"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("/nonexistent-dir/x.png"));
    // A bad scene file names its line
    let bad = write("bad.flat", "poly 4 0 0 1 0 1 1 0 1\nseg 0 0 0 0\n");
    let out = bin()
        .args(["field", bad.to_str().unwrap(), "--at", "0.5,0.5"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&out.stderr).contains("bad.flat:2:"),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}
