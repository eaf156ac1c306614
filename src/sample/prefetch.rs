//! Asking the CPU for memory ahead of its use. A large robot's distance tables (2 KB each, thousands of
//! them) do not stay in cache from one block of samples to the next, and a block's lookups land
//! anywhere in a table: without a prefetch each lookup waits for its own miss.

/// Bytes per cache line.
const LINE: usize = 64;

/// Starts bringing every cache line of `items` into the cache, without waiting for it. A hint only:
/// what the program computes does not change.
#[inline]
pub(super) fn prefetch<T>(items: &[T]) {
    #[cfg(target_arch = "x86_64")]
    {
        // From the start of the line holding the first byte to the line holding the last.
        let skew = items.as_ptr() as usize % LINE;
        let start = items.as_ptr().cast::<u8>().wrapping_sub(skew);
        let bytes = std::mem::size_of_val(items) + skew;
        for offset in (0..bytes).step_by(LINE) {
            // SAFETY: a prefetch never faults and never changes memory, at any address (these are
            // inside the lines `items` occupies; `wrapping_*` keeps computing them defined), and its
            // instruction belongs to SSE, which every x86_64 target has.
            unsafe {
                std::arch::x86_64::_mm_prefetch::<{ std::arch::x86_64::_MM_HINT_T0 }>(
                    start.wrapping_add(offset).cast(),
                )
            };
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = items;
}
