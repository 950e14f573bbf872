//! Fresh table buffers: allocated untouched (so the parallel passes that write them first
//! also fault their pages in, on every core) and, on Linux, advised to the kernel as huge
//! page candidates (`madvise(MADV_HUGEPAGE)`).
//!
//! A fresh 4 KiB page costs a fault (about 1.4 µs on the development machine: a fresh
//! 128 MiB table, 32 768 faults, ≈ 45 ms, much of a `1.6·10^7`-light build); a 2 MiB page
//! is one fault for 512 of them, and 512 times fewer TLB entries for the random reads of
//! sampling. Where transparent huge pages are off (or `always`, or not Linux) the advice
//! changes nothing. A rebuild into an existing table allocates nothing and faults nothing.

/// Buffers at least this large are advised (smaller ones rarely span an aligned 2 MiB).
const ADVISE_BYTES: usize = 4 << 20;

/// `n` zeroed words, untouched: `calloc` maps large blocks afresh and leaves their pages to
/// fault in when first written. Advised as huge page candidates when large.
pub(super) fn fresh_words(n: usize) -> Vec<u64> {
    let words = vec![0u64; n];
    if n * 8 >= ADVISE_BYTES {
        advise_huge_pages(&words);
    }
    words
}

/// Asks the kernel to back the 2 MiB-aligned part of `words` with huge pages (Linux,
/// glibc); elsewhere nothing.
fn advise_huge_pages(words: &[u64]) {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    #[allow(unsafe_code)]
    {
        const HUGE: usize = 2 << 20;
        /// Linux's `MADV_HUGEPAGE` advice.
        const MADV_HUGEPAGE: std::ffi::c_int = 14;
        unsafe extern "C" {
            /// glibc: gives the kernel advice about a range of the process's pages; returns
            /// 0 on success.
            fn madvise(
                addr: *mut std::ffi::c_void,
                length: usize,
                advice: std::ffi::c_int,
            ) -> std::ffi::c_int;
        }
        let start = words.as_ptr() as usize;
        let end = start + std::mem::size_of_val(words);
        let (from, to) = (start.next_multiple_of(HUGE), end / HUGE * HUGE);
        if to > from {
            // SAFETY: `from..to` lies inside `words`' allocation, which this function's
            // caller owns; MADV_HUGEPAGE only changes how the kernel backs those pages
            // (their contents, zero, are kept) and reads or writes no memory itself. A
            // failure (transparent huge pages not built in) leaves the pages as they were.
            unsafe {
                madvise(from as *mut std::ffi::c_void, to - from, MADV_HUGEPAGE);
            }
        }
    }
    #[cfg(not(all(target_os = "linux", target_env = "gnu")))]
    let _ = words;
}
