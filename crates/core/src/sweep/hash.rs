//! Content hashes: a point's identity (what it computes from) and a design's.

use sha2::{Digest, Sha256};

/// Hex of the first 128 bits of SHA-256: enough to tell points apart in any sweep (a collision
/// among 10⁹ points has probability ~10⁻²¹) and short enough for a table column.
pub fn short_hash(bytes: &[u8]) -> String {
    short_hash_of_digest(&Sha256::digest(bytes))
}

/// The first 128 bits of a SHA-256 digest as hex (for digests computed incrementally).
pub fn short_hash_of_digest(digest: &[u8]) -> String {
    digest.iter().take(16).map(|b| format!("{b:02x}")).collect()
}

/// The identity of a point: its job and its parameters in a canonical order, with each input
/// file replaced by the hash of its content, so editing a pattern or a photo re-runs the points
/// that read it while renaming the spec or reordering axes does not.
pub fn point_hash(job: &str, params: &[(String, String)]) -> String {
    let mut sorted: Vec<&(String, String)> = params.iter().collect();
    sorted.sort();
    let mut text = String::from(job);
    for (k, v) in sorted {
        text.push('\n');
        text.push_str(k);
        text.push('=');
        text.push_str(v);
    }
    short_hash(text.as_bytes())
}
