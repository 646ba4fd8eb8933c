//! Deterministic byte-level mutants of a valid input: byte flips, truncations, insertions,
//! deletions, declared-size blow-ups and inserted JSON tokens, one to three at a time.

/// Values written over 4- or 8-byte words to make a declared size or offset absurd.
const BLOW_UPS: [i64; 8] = [
    -1,
    i32::MAX as i64,
    i32::MIN as i64,
    u32::MAX as i64,
    1 << 31,
    1 << 40,
    1 << 50,
    i64::MAX,
];

/// Text fragments that change a JSON document's shape or numbers.
const TOKENS: [&str; 10] = [
    "\"",
    "{",
    "]",
    ",",
    "null",
    "1e999",
    "-1",
    "99999999999999999999",
    "\"\\ud800\"",
    "[[[[",
];

/// The `index`-th mutant of `base` for `seed`: the same arguments always give the same bytes.
pub fn mutant(base: &[u8], seed: u64, index: u64) -> Vec<u8> {
    let mut rng = fastrand::Rng::with_seed(seed ^ index.wrapping_mul(0x9E37_79B9_7F4A_7C15));
    let mut bytes = base.to_vec();
    for _ in 0..rng.usize(1..=3) {
        mutate_once(&mut rng, &mut bytes);
    }
    bytes
}

/// A position in `len` bytes: half the time near either end (where headers, footers and
/// declared sizes live), otherwise anywhere.
fn position(rng: &mut fastrand::Rng, len: usize) -> usize {
    if len == 0 {
        return 0;
    }
    let edge = 1024.min(len);
    match rng.u8(0..4) {
        0 => rng.usize(0..edge),
        1 => len - edge + rng.usize(0..edge),
        _ => rng.usize(0..len),
    }
}

fn mutate_once(rng: &mut fastrand::Rng, bytes: &mut Vec<u8>) {
    let len = bytes.len();
    match rng.u8(0..6) {
        // Flip 1 to 4 bytes.
        0 if len > 0 => {
            for _ in 0..rng.usize(1..=4) {
                let at = position(rng, len);
                bytes[at] ^= rng.u8(1..=255);
            }
        }
        // Cut short.
        1 if len > 0 => bytes.truncate(rng.usize(0..len)),
        // Insert 1 to 16 random bytes.
        2 => {
            let at = position(rng, len + 1).min(len);
            let extra: Vec<u8> = (0..rng.usize(1..=16)).map(|_| rng.u8(..)).collect();
            bytes.splice(at..at, extra);
        }
        // Delete 1 to 64 bytes.
        3 if len > 0 => {
            let at = position(rng, len);
            let end = (at + rng.usize(1..=64)).min(len);
            bytes.drain(at..end);
        }
        // Blow up a declared size: an aligned 4- or 8-byte word set to an absurd value.
        4 if len >= 8 => {
            let value = BLOW_UPS[rng.usize(0..BLOW_UPS.len())];
            let width = if rng.bool() { 4 } else { 8 };
            let at = (position(rng, len - width + 1) / width * width).min(len - width);
            let le = value.to_le_bytes();
            bytes[at..at + width].copy_from_slice(&le[..width]);
        }
        // Insert a JSON token.
        _ => {
            let at = position(rng, len + 1).min(len);
            let token = TOKENS[rng.usize(0..TOKENS.len())].as_bytes();
            bytes.splice(at..at, token.iter().copied());
        }
    }
}

#[test]
fn mutants_are_deterministic_and_differ() {
    let base: Vec<u8> = (0..=255u8).cycle().take(4096).collect();
    let a: Vec<Vec<u8>> = (0..200).map(|i| mutant(&base, 7, i)).collect();
    let b: Vec<Vec<u8>> = (0..200).map(|i| mutant(&base, 7, i)).collect();
    assert_eq!(a, b, "same seed and index, same mutant");
    assert!(
        a.iter().all(|m| *m != base),
        "every mutant changes the input"
    );
    let distinct: std::collections::BTreeSet<&Vec<u8>> = a.iter().collect();
    assert!(
        distinct.len() > 190,
        "{} distinct mutants of 200",
        distinct.len()
    );
    assert!(a.iter().any(|m| m.len() < base.len()), "some are cut short");
    assert!(a.iter().any(|m| m.len() > base.len()), "some grow");
}
