//! Seed derivation: every random choice flows from one user seed. Parallel jobs get their own seed
//! derived from that seed and the job's key (never from a thread or an execution order), so results
//! do not depend on the number of threads.

/// SplitMix64 finaliser: a well-mixed 64-bit value from any 64-bit input.
pub fn mix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The seed of the job named `key` (e.g. `"sc1/10/hstar/3"`) under the user seed `base`.
/// Stable across platforms and versions: FNV-1a over the key's bytes, then mixed with `base`.
pub fn derive_seed(base: u64, key: &str) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in key.bytes() {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01B3);
    }
    mix64(base ^ mix64(h))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn derived_seeds_are_stable_and_distinct() {
        assert_eq!(derive_seed(7, "a"), derive_seed(7, "a"));
        assert_ne!(derive_seed(7, "a"), derive_seed(7, "b"));
        assert_ne!(derive_seed(7, "a"), derive_seed(8, "a"));
        // Pinned value: a change here would silently change every experiment's seeds.
        assert_eq!(mix64(0), 0xE220_A839_7B1D_CDAF);
    }
}
