use super::*;
use crate::lines::CHUNK_LINES;
use crate::scene::Scene2;
use crate::tally::LineTracer;
use crate::trace::estimate_2d::Tracer2;
use alloc::string::ToString;

/// The partial of chunks `chunks` of a job over `tracer`.
fn partial_of<T: LineTracer>(
    tracer: &T,
    method: LineMethod,
    lines: u64,
    chunks: Range<u64>,
) -> Partial {
    let mut tally = tracer.new_tally(method);
    for k in chunks.clone() {
        tracer.trace_chunk(11, lines, k, &mut tally);
    }
    Partial {
        job: JobId {
            scene: 0xABCD,
            method,
            seed: 11,
            lines,
        },
        chunks,
        seconds: 0.0,
        sizes: tracer.patch_sizes().to_vec(),
        tally,
    }
}

fn small() -> (Tracer2, u64) {
    let scene = Scene2::regular_polygon(5, 3).unwrap();
    (Tracer2::new(&scene).unwrap(), 3 * CHUNK_LINES + 100)
}

#[test]
fn four_partials_through_bytes_merge_into_the_whole_run_bit_for_bit() {
    let (tracer, lines) = small();
    for method in LineMethod::ALL {
        let whole = partial_of(&tracer, method, lines, 0..4);
        // Out of order, through files.
        let parts: Vec<Partial> = [3..4, 0..1, 2..3, 1..2]
            .into_iter()
            .map(|c| Partial::from_bytes(&partial_of(&tracer, method, lines, c).to_bytes()))
            .collect::<Result<_>>()
            .unwrap();
        let merged = merge_partials(parts).unwrap();
        let (a, b) = (merged.to_bytes(), whole.to_bytes());
        let first_difference = a.iter().zip(&b).position(|(x, y)| x != y);
        assert_eq!((a.len(), first_difference), (b.len(), None), "{method:?}");
        assert_eq!(
            merged.finish().unwrap(),
            whole.tally.clone().finish(&tracer).unwrap()
        );
    }
}

#[test]
fn sparse_counts_round_trip_and_merge() {
    // More patches than DENSE_COUNT_LIMIT: sparse counts, 16 bytes per pair in the file.
    let scene = Scene2::regular_polygon(4, 1500).unwrap();
    let tracer = Tracer2::new(&scene).unwrap();
    let lines = 2 * CHUNK_LINES;
    let whole = partial_of(&tracer, LineMethod::Global, lines, 0..2);
    assert!(!whole.tally.counts.is_dense());
    let a = Partial::from_bytes(&partial_of(&tracer, LineMethod::Global, lines, 0..1).to_bytes());
    let b = Partial::from_bytes(&partial_of(&tracer, LineMethod::Global, lines, 1..2).to_bytes());
    let merged = merge_partials(alloc::vec![b.unwrap(), a.unwrap()]).unwrap();
    let bytes = whole.to_bytes();
    assert!(merged.to_bytes() == bytes);
    let mut pairs = 0u64;
    whole.tally.counts.for_each_raw(|_, _, _, _| pairs += 1);
    // Header 72 bytes; per patch size, leaves and info 8 + 8 + 17; lines cast 8;
    // continuous 3 × 17 + 8 + 16 + 8; pair flag 1; pair count 8; checksum 8.
    let fixed = 72 + 6000 * (8 + 8 + 17) + 8 + (3 * 17 + 8 + 16 + 8) + 1 + 8 + 8;
    assert_eq!(bytes.len() as u64, fixed + 16 * pairs);
}

#[test]
fn every_damage_is_a_clear_error() {
    let (tracer, lines) = small();
    let good = partial_of(&tracer, LineMethod::Global, lines, 1..3).to_bytes();
    assert!(Partial::from_bytes(&good).is_ok());
    // Every truncation and every single-bit flip is refused, never a panic.
    for len in 0..good.len() {
        assert!(Partial::from_bytes(&good[..len]).is_err(), "length {len}");
    }
    for byte in (0..good.len()).step_by(7) {
        let mut bad = good.clone();
        bad[byte] ^= 1 << (byte % 8);
        let err = Partial::from_bytes(&bad).unwrap_err();
        assert!(
            matches!(
                err.kind(),
                ErrorKind::BadPartial { .. } | ErrorKind::PartialVersion { .. }
            ),
            "{err}"
        );
    }
    let mut other = good.clone();
    other[8] = 2;
    assert_eq!(
        Partial::from_bytes(&other).unwrap_err().kind(),
        &ErrorKind::PartialVersion {
            found: 2,
            supported: 1
        }
    );
    assert!(
        Partial::from_bytes(b"P3\n1 1\n")
            .unwrap_err()
            .to_string()
            .contains("not a sceneinfo partial file")
    );
}

#[test]
fn mismatched_overlapping_and_incomplete_partials_are_refused() {
    let (tracer, lines) = small();
    let part = |c: Range<u64>| partial_of(&tracer, LineMethod::Global, lines, c);
    let mut other_seed = part(1..2);
    other_seed.job.seed = 12;
    let err = merge_partials(alloc::vec![part(0..1), other_seed]).unwrap_err();
    assert_eq!(err.kind(), &ErrorKind::PartialMismatch { field: "seed" });
    let mut other_scene = part(1..2);
    other_scene.job.scene = 1;
    let err = merge_partials(alloc::vec![part(0..1), other_scene]).unwrap_err();
    assert_eq!(err.kind(), &ErrorKind::PartialMismatch { field: "scene" });
    let err = merge_partials(alloc::vec![part(0..2), part(1..3)]).unwrap_err();
    assert!(err.to_string().contains("overlap"), "{err}");
    let err = merge_partials(alloc::vec![part(0..1), part(2..4)]).unwrap_err();
    assert!(
        err.to_string().contains("chunks 1..2 are in no partial"),
        "{err}"
    );
    let err = merge_partials(alloc::vec![part(0..1), part(1..3)])
        .unwrap()
        .finish()
        .unwrap_err();
    assert!(
        err.to_string()
            .contains("cover chunks 0..3 of the job's 0..4"),
        "{err}"
    );
}

#[test]
fn fingerprint_sees_every_word() {
    let a = fingerprint(b"seg 0 0 1 0\nseg 1 0 1 1\n");
    assert_eq!(a, fingerprint(b"seg 0 0 1 0\nseg 1 0 1 1\n"));
    assert_ne!(a, fingerprint(b"seg 0 0 1 0\nseg 1 0 1 2\n"));
    assert_ne!(fingerprint(b""), fingerprint(&[0]));
}
