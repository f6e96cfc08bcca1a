//! A bucket queue on small integer keys for searches whose keys never fall below the one last
//! taken (A* with a consistent heuristic, keyed by `f`): one vector per key, entries of a key
//! taken last in first out, and a cursor on the least key that may hold entries. Kept between
//! searches, it allocates only when a larger key than ever before is queued.

/// Entries of type `T` keyed `0, 1, 2, ...` (callers subtract their least key).
#[derive(Debug)]
pub struct BucketQueue<T> {
    buckets: Vec<Vec<T>>,
    /// Buckets `used..` are empty.
    used: usize,
    /// Buckets `..cursor` are empty.
    cursor: usize,
}

impl<T> Default for BucketQueue<T> {
    fn default() -> Self {
        BucketQueue {
            buckets: Vec::new(),
            used: 0,
            cursor: 0,
        }
    }
}

impl<T> BucketQueue<T> {
    /// Empties the queue (only the buckets the last search used are touched).
    pub fn clear(&mut self) {
        for b in &mut self.buckets[..self.used] {
            b.clear();
        }
        self.used = 0;
        self.cursor = 0;
    }

    /// Queues `item` at `key`; a key below the cursor (a heuristic that is not consistent) is
    /// taken as the cursor's.
    #[inline]
    pub fn push(&mut self, key: usize, item: T) {
        let k = key.max(self.cursor);
        if k >= self.buckets.len() {
            self.buckets.resize_with(k + 1, Vec::new);
        }
        self.used = self.used.max(k + 1);
        self.buckets[k].push(item);
    }

    /// Takes an entry of the least key, with its key (the latest queued of that key first).
    #[inline]
    pub fn pop(&mut self) -> Option<(usize, T)> {
        while self.cursor < self.used {
            if let Some(e) = self.buckets[self.cursor].pop() {
                return Some((self.cursor, e));
            }
            self.cursor += 1;
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn least_key_first_and_last_in_first_out_within_a_key() {
        let mut q = BucketQueue::default();
        q.push(3, 'a');
        q.push(1, 'b');
        q.push(1, 'c');
        assert_eq!(q.pop(), Some((1, 'c')));
        q.push(0, 'd'); // below the cursor: taken as key 1
        assert_eq!(q.pop(), Some((1, 'd')));
        assert_eq!(q.pop(), Some((1, 'b')));
        assert_eq!(q.pop(), Some((3, 'a')));
        assert_eq!(q.pop(), None);
        q.clear();
        q.push(0, 'e');
        assert_eq!(q.pop(), Some((0, 'e')));
    }
}
