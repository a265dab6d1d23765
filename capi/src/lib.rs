//! sceneinfo's C library: opaque handles over the core's façade ([`sceneinfo::Scene`],
//! [`sceneinfo::measure`], [`sceneinfo::Measurement`], [`sceneinfo::solve_radiosity`]),
//! with the header `capi/include/sceneinfo.h` written by cbindgen from these items.
//!
//! The rules every entry point keeps (docs/c-api.md says them for C programmers):
//!
//! - **Handles** (`SiScene`, `SiMeasurement`, `SiLighting`, `SiExactRows`) are made by one
//!   call (`si_scene_from_file`, `si_measure`, `si_radiosity`, `si_exact_rows`, …), owned
//!   by the caller, and freed by their `si_*_free` (NULL is a no-op). A handle owns all its
//!   data: freeing a scene does not invalidate its measurements.
//! - **Errors**: a fallible call returns an `SiStatus`; on failure a message (`file:line:
//!   what`) is kept per thread until the next fallible call ([`status`]).
//! - **Buffers**: arrays are copied into caller buffers with explicit lengths; the length
//!   needed is always written to `*out_needed`, and a short buffer is
//!   `SI_ERR_BUFFER_TOO_SMALL` with nothing written.
//! - **No panic crosses the boundary**: every body runs under `catch_unwind`; a panic is
//!   `SI_ERR_INTERNAL`. Pointers are checked for NULL and alignment, lengths for overflow,
//!   before any read.
//! - **Threads**: handles are read-only after creation; one scene may be measured from
//!   several threads at once. A line job's threads give the same bits as one thread.
//!
//! No numerics live here: every number comes from the core.

mod buffers;
pub mod measure;
pub mod radiosity;
pub mod rows;
pub mod scene;
pub mod status;
mod threads;

/// The library's version, `"MAJOR.MINOR.PATCH"` (the workspace's). Ownership: a static
/// string; do not free it.
#[unsafe(no_mangle)]
pub extern "C" fn si_version() -> *const std::ffi::c_char {
    const VERSION: &std::ffi::CStr = match std::ffi::CStr::from_bytes_with_nul(
        concat!(env!("CARGO_PKG_VERSION"), "\0").as_bytes(),
    ) {
        Ok(v) => v,
        Err(_) => c"unknown",
    };
    VERSION.as_ptr()
}

#[cfg(test)]
mod tests;
