//! Transparent huge pages for the BVH's large arrays.
//!
//! Incoherent rays read nodes and triangle packets scattered over tens of
//! megabytes; with 4 KiB pages nearly every such read also misses the
//! translation lookaside buffer (about 2,000 entries cover only 8 MiB) and
//! waits for a page-table walk. 2 MiB pages cover the whole BVH of a
//! million triangles with a few dozen entries. Linux hands them out for
//! memory marked with `madvise(MADV_HUGEPAGE)` when transparent huge pages
//! are in "madvise" mode (the default of most distributions), and only to
//! pages that are first touched after the advice, so the arrays are
//! allocated with their final capacity, advised, and only then filled.

/// An empty vector with room for `capacity` elements whose memory (the
/// whole 2 MiB pages within it) is advised to be backed by huge pages. The
/// advice is a hint: where it is not available the vector is an ordinary one.
pub(crate) fn vec_with_huge_pages<T>(capacity: usize) -> Vec<T> {
    let vector = Vec::<T>::with_capacity(capacity);
    advise_huge_pages(
        vector.as_ptr().cast::<u8>(),
        vector.capacity() * std::mem::size_of::<T>(),
    );
    vector
}

#[cfg(target_os = "linux")]
fn advise_huge_pages(start: *const u8, bytes: usize) {
    /// The size of an x86_64 (and arm64 with 4 KiB base pages) huge page.
    const HUGE_PAGE: usize = 2 << 20;
    /// `MADV_HUGEPAGE` of Linux's `<asm-generic/mman-common.h>`.
    const MADV_HUGEPAGE: std::ffi::c_int = 14;
    unsafe extern "C" {
        fn madvise(
            address: *mut std::ffi::c_void,
            length: usize,
            advice: std::ffi::c_int,
        ) -> std::ffi::c_int;
    }
    let begin = (start as usize).next_multiple_of(HUGE_PAGE);
    let end = (start as usize).saturating_add(bytes) / HUGE_PAGE * HUGE_PAGE;
    if end > begin {
        // SAFETY: `[begin, end)` lies within one live allocation of this
        // process; MADV_HUGEPAGE changes how its pages are backed, never
        // their contents. Failure (e.g. huge pages disabled) is harmless,
        // so the result is ignored.
        unsafe {
            madvise(begin as *mut std::ffi::c_void, end - begin, MADV_HUGEPAGE);
        }
    }
}

#[cfg(not(target_os = "linux"))]
fn advise_huge_pages(_start: *const u8, _bytes: usize) {}

#[cfg(test)]
mod tests {
    use super::*;

    /// The vector behaves as any other (the advice changes no contents).
    #[test]
    fn advised_vector_holds_its_elements() {
        let mut vector = vec_with_huge_pages::<[f32; 16]>(100_000);
        assert!(vector.capacity() >= 100_000);
        for i in 0..100_000 {
            vector.push([i as f32; 16]);
        }
        assert!(vector.iter().enumerate().all(|(i, v)| v[15] == i as f32));
        assert!(vec_with_huge_pages::<u32>(0).is_empty());
    }
}
