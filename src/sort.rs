//! Sorting for the builder's and the importers' large arrays.

/// Sorts `v` by `key`, which orders it totally (or equal keys are equal elements): a radix sort
/// on one or two threads (a fraction of a comparison sort's instructions), rayon's parallel sort on
/// more (less wall time on large meshes). The same order either way, so a build does not depend
/// on the thread count.
pub(crate) fn sort_total<T: Send + Copy, K: radsort::Key + Ord>(
    v: &mut [T],
    key: impl Fn(&T) -> K + Sync,
) {
    use rayon::prelude::*;
    if rayon::current_num_threads() <= 2 {
        radsort::sort_by_key(v, key);
    } else {
        v.par_sort_unstable_by_key(key);
    }
}
