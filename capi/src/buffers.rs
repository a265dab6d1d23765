//! The pointers of the C boundary, checked: caller arrays read as slices, handles read as
//! references, results written into caller buffers with explicit lengths, new handles
//! handed out.
//!
//! Every check happens here, before any read or write: NULL, alignment, a byte length that
//! fits in `isize`, a buffer long enough.

use std::mem::size_of;
use std::ptr;

use crate::status::{Failure, Outcome, SiStatus};

/// `*ptr`, or `T::default()` when `ptr` is NULL (an optional job or options struct).
///
/// # Safety
/// `ptr` must be NULL or point to one initialised, aligned `T`.
pub(crate) unsafe fn input_or_default<T: Copy + Default>(ptr: *const T, what: &str) -> Outcome<T> {
    // SAFETY: NULL (no item read) or one valid T by the caller's contract
    let items = unsafe { input(ptr, usize::from(!ptr.is_null()), what) }?;
    Ok(items.first().copied().unwrap_or_default())
}

/// The `len` items at `ptr`, as a slice (`len == 0`: empty, whatever `ptr` is).
///
/// # Safety
/// When `len > 0` and `ptr` is not NULL, `ptr` must point to `len` initialised items that
/// stay valid and unmodified for `'a`.
pub(crate) unsafe fn input<'a, T>(ptr: *const T, len: usize, what: &str) -> Outcome<&'a [T]> {
    if len == 0 {
        return Ok(&[]);
    }
    if ptr.is_null() {
        return Err(Failure::null(what));
    }
    if !ptr.is_aligned() {
        return Err(Failure::invalid(format!("{what} is not aligned")));
    }
    if len
        .checked_mul(size_of::<T>())
        .is_none_or(|bytes| bytes > isize::MAX as usize)
    {
        return Err(Failure::invalid(format!(
            "{what}: {len} items do not fit in memory"
        )));
    }
    // SAFETY: non-NULL, aligned, `len` items of at most isize::MAX bytes, valid for 'a by
    // the caller's contract
    Ok(unsafe { std::slice::from_raw_parts(ptr, len) })
}

/// The object a handle points to.
///
/// # Safety
/// `handle` must be NULL or a pointer this library handed out and that has not been freed.
pub(crate) unsafe fn handle<'a, T>(handle: *const T, what: &str) -> Outcome<&'a T> {
    // SAFETY: by the caller's contract, a live handle or NULL (then `None`)
    unsafe { handle.as_ref() }.ok_or_else(|| Failure::null(what))
}

/// Checks an out-pointer for a new handle and sets `*out = NULL`, so that a failing call
/// leaves NULL there.
///
/// # Safety
/// `out` must be NULL or valid for writing one pointer.
pub(crate) unsafe fn clear_out<T>(out: *mut *mut T, what: &str) -> Outcome<()> {
    if out.is_null() {
        return Err(Failure::null(what));
    }
    // SAFETY: non-NULL and writable by the caller's contract
    unsafe { out.write(ptr::null_mut()) };
    Ok(())
}

/// Hands `value` to the caller as a new handle in `*out` (checked by [`clear_out`]).
///
/// # Safety
/// As [`clear_out`], which must have accepted `out`.
pub(crate) unsafe fn give<T>(out: *mut *mut T, value: T) {
    // SAFETY: `out` was checked non-NULL and writable by `clear_out`
    unsafe { out.write(Box::into_raw(Box::new(value))) };
}

/// Frees a handle handed out by [`give`] (NULL: nothing).
///
/// # Safety
/// `handle` must be NULL or a pointer [`give`] handed out for a `T` and not freed since.
pub(crate) unsafe fn free<T>(handle: *mut T) {
    if !handle.is_null() {
        // SAFETY: made by Box::into_raw in `give`, freed once by the caller's contract
        drop(unsafe { Box::from_raw(handle) });
    }
}

/// Writes `data` into the caller's buffer `out` of `out_len` values, and `data.len()` into
/// `*out_needed` (when not NULL) whatever happens, so a caller can ask for the length with
/// `out = NULL, out_len = 0`.
///
/// # Errors
/// [`SiStatus::SI_ERR_BUFFER_TOO_SMALL`] when `out_len < data.len()` (nothing written to
/// `out`); [`SiStatus::SI_ERR_NULL_ARGUMENT`] when `out` is NULL and `data` is not empty.
///
/// # Safety
/// `out` must be NULL or valid for writing `out_len` values; `out_needed` NULL or valid
/// for writing one `usize`.
pub(crate) unsafe fn copy_out<T: Copy>(
    data: &[T],
    out: *mut T,
    out_len: usize,
    out_needed: *mut usize,
    what: &str,
) -> Outcome<()> {
    if !out_needed.is_null() {
        // SAFETY: non-NULL and writable by the caller's contract
        unsafe { out_needed.write(data.len()) };
    }
    if out_len < data.len() {
        return Err(Failure::new(
            SiStatus::SI_ERR_BUFFER_TOO_SMALL,
            format!(
                "{what}: the buffer holds {out_len} values, {} are needed",
                data.len()
            ),
        ));
    }
    if data.is_empty() {
        return Ok(());
    }
    if out.is_null() {
        return Err(Failure::null(what));
    }
    if !out.is_aligned() {
        return Err(Failure::invalid(format!(
            "{what}: the buffer is not aligned"
        )));
    }
    // SAFETY: `out` is non-NULL, aligned and holds at least `data.len()` values by the
    // caller's contract; a caller buffer cannot overlap the library's own `data`
    unsafe { ptr::copy_nonoverlapping(data.as_ptr(), out, data.len()) };
    Ok(())
}

/// Writes `value` into `*out`.
///
/// # Errors
/// [`SiStatus::SI_ERR_NULL_ARGUMENT`] when `out` is NULL.
///
/// # Safety
/// `out` must be NULL or valid for writing one `T`.
pub(crate) unsafe fn write_out<T>(out: *mut T, value: T, what: &str) -> Outcome<()> {
    if out.is_null() {
        return Err(Failure::null(what));
    }
    if !out.is_aligned() {
        return Err(Failure::invalid(format!("{what} is not aligned")));
    }
    // SAFETY: non-NULL, aligned and writable by the caller's contract
    unsafe { out.write(value) };
    Ok(())
}
