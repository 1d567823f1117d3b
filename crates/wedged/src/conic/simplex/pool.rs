//! Recycled buffers for the dense basis inverses, one free list per thread.
//!
//! Every search node clones its parent's basis with its inverse (`(3m + 1)^2` values: 180 KiB
//! at m = 50, 450 KiB at m = 80) and drops it soon after. glibc serves such blocks from the
//! heap once it has seen a few of them, but not when the process fixes its trim threshold:
//! Dask's worker processes are started with `MALLOC_TRIM_THRESHOLD_=65536`, and then every
//! block above 128 KiB is a fresh `mmap` whose pages fault in one by one and an `munmap`. The
//! m = 50 plug took 18.1 s instead of 12.6 s as a command with that variable set (1.5 million
//! page faults against 2,700), and shards ran at half speed in Dask workers. A free list
//! makes the search's cost independent of the allocator's settings.

use std::cell::RefCell;

/// Buffers shorter than this go to the allocator as usual (small blocks are cheap).
const LEAST: usize = 4096;

/// At most this many buffers, and this many values in all, wait on one thread's list.
const KEEP: usize = 32;
const KEEP_VALUES: usize = 8 << 20;

thread_local! {
    static FREE: RefCell<Vec<Vec<f64>>> = const { RefCell::new(Vec::new()) };
}

/// A buffer of `len` values, each `0.0`.
pub(super) fn zeroed(len: usize) -> Vec<f64> {
    match take(len) {
        Some(mut v) => {
            v.clear();
            v.resize(len, 0.0);
            v
        }
        None => vec![0.0; len],
    }
}

/// A copy of `values`.
pub(super) fn copy_of(values: &[f64]) -> Vec<f64> {
    match take(values.len()) {
        Some(mut v) => {
            v.clear();
            v.extend_from_slice(values);
            v
        }
        None => values.to_vec(),
    }
}

/// Hands `v` back for reuse (or to the allocator when the list is full or `v` is small).
pub(super) fn recycle(v: Vec<f64>) {
    if v.capacity() < LEAST {
        return;
    }
    // A thread being torn down has no list any more: `v` is simply freed.
    let _ = FREE.try_with(|free| {
        let mut free = free.borrow_mut();
        let held: usize = free.iter().map(|b| b.capacity()).sum();
        if free.len() < KEEP && held + v.capacity() <= KEEP_VALUES {
            free.push(v);
        }
    });
}

/// A buffer from this thread's list that holds `len` values, newest first.
fn take(len: usize) -> Option<Vec<f64>> {
    if len < LEAST {
        return None;
    }
    FREE.try_with(|free| {
        let mut free = free.borrow_mut();
        let k = free.iter().rposition(|b| b.capacity() >= len)?;
        Some(free.swap_remove(k))
    })
    .ok()
    .flatten()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn buffers_come_back_with_the_asked_contents() {
        let a = copy_of(&vec![3.0; 5000]);
        let pointer = a.as_ptr();
        recycle(a);
        let b = zeroed(4500);
        assert_eq!(b.as_ptr(), pointer, "the recycled buffer is reused");
        assert_eq!(b.len(), 4500);
        assert!(b.iter().all(|&x| x == 0.0));
        recycle(b);
        let c = copy_of(&[1.0; 4096]);
        assert_eq!(c.as_ptr(), pointer);
        assert!(c.iter().all(|&x| x == 1.0) && c.len() == 4096);
        // Small buffers are not kept; a full list frees the rest.
        recycle(vec![0.0; 10]);
        assert!(take(10).is_none());
        for _ in 0..KEEP + 3 {
            recycle(vec![0.0; LEAST]);
        }
        FREE.with(|free| assert!(free.borrow().len() <= KEEP));
    }
}
