//! `sceneinfo merge`: combines partial results (`measure … --partial`) into the result of
//! one run of the whole job — bit for bit, since tallies are exact integers and fixed-point
//! sums — or into one larger partial result.

use std::io::Write;
use std::path::Path;
use std::time::Instant;

use anyhow::Result;
use sceneinfo::Measurement;
use sceneinfo::io::partial::Partial;

use crate::args::MergeArgs;
use crate::output::{located, write_atomic};
use crate::report::{Timing, print_report};

pub fn run(args: &MergeArgs) -> Result<()> {
    let start = Instant::now();
    let mut parts = Vec::with_capacity(args.files.len());
    for path in &args.files {
        // A regular file within the input cap, like every file the CLI reads
        let bytes = crate::formats::read_capped_to(
            path,
            crate::formats::input_cap(crate::formats::MAX_FILE_BYTES),
            "partial results",
        )?;
        parts.push(Partial::from_bytes(&bytes).map_err(|e| located(path, &e))?);
    }
    let first = &args.files[0];
    let merged = Partial::merge(parts).map_err(|e| anyhow::anyhow!("merge: {}", e.kind()))?;
    if let Some(out) = &args.partial {
        let bytes = merged.to_bytes();
        write_atomic(out, &bytes)?;
        writeln!(
            std::io::stdout().lock(),
            "wrote {}: chunks {}..{} of a job of {} lines, {} bytes",
            out.display(),
            merged.chunks.start,
            merged.chunks.end,
            merged.job.lines,
            bytes.len()
        )?;
        return Ok(());
    }
    let earlier = merged.seconds;
    // One run of the whole job, bit for bit: its measures, or, when some patch received no
    // line, I_S^c and no discrete measures
    let m =
        Measurement::from_partial(merged).map_err(|e| anyhow::anyhow!("merge: {}", e.kind()))?;
    print_report(
        Path::new(first),
        &m,
        None,
        Timing { start, earlier },
        args.json,
        args.matrix.as_deref(),
    )
}
