//! OASIS (SEMI P39) primitive encodings: unsigned and signed integers, reals, strings,
//! g-deltas, point lists and repetitions, and the CRC-32 the END record's validation covers.

use std::io::Write;

/// The file's first bytes.
pub const MAGIC: &[u8] = b"%SEMI-OASIS\r\n";

/// Record ids (SEMI P39 table 5) this writer and reader know.
pub mod record {
    pub const PAD: u64 = 0;
    pub const START: u64 = 1;
    pub const END: u64 = 2;
    pub const CELLNAME_IMPLICIT: u64 = 3;
    pub const CELLNAME: u64 = 4;
    pub const TEXTSTRING_IMPLICIT: u64 = 5;
    pub const TEXTSTRING: u64 = 6;
    pub const PROPNAME_IMPLICIT: u64 = 7;
    pub const PROPNAME: u64 = 8;
    pub const PROPSTRING_IMPLICIT: u64 = 9;
    pub const PROPSTRING: u64 = 10;
    pub const LAYERNAME_GEOMETRY: u64 = 11;
    pub const LAYERNAME_TEXT: u64 = 12;
    pub const CELL_REF: u64 = 13;
    pub const CELL_NAMED: u64 = 14;
    pub const XYABSOLUTE: u64 = 15;
    pub const XYRELATIVE: u64 = 16;
    pub const PLACEMENT: u64 = 17;
    pub const PLACEMENT_TRANSFORM: u64 = 18;
    pub const TEXT: u64 = 19;
    pub const RECTANGLE: u64 = 20;
    pub const POLYGON: u64 = 21;
    pub const PATH: u64 = 22;
    pub const TRAPEZOID_AB: u64 = 23;
    pub const TRAPEZOID_A: u64 = 24;
    pub const TRAPEZOID_B: u64 = 25;
    pub const CTRAPEZOID: u64 = 26;
    pub const CIRCLE: u64 = 27;
    pub const PROPERTY: u64 = 28;
    pub const LAST_PROPERTY: u64 = 29;
    pub const XNAME_IMPLICIT: u64 = 30;
    pub const XNAME: u64 = 31;
    pub const XELEMENT: u64 = 32;
    pub const XGEOMETRY: u64 = 33;
    pub const CBLOCK: u64 = 34;
}

/// The END record is exactly this long, validation included.
pub const END_RECORD_BYTES: usize = 256;

/// A byte sink that keeps the running CRC-32 and the byte count (the END record's validation
/// signature covers every byte before it).
pub struct Sink<W: Write> {
    inner: W,
    crc: crc32fast::Hasher,
    /// Bytes written so far.
    pub bytes: u64,
}

impl<W: Write> Sink<W> {
    /// Wraps `inner`.
    pub fn new(inner: W) -> Self {
        Sink {
            inner,
            crc: crc32fast::Hasher::new(),
            bytes: 0,
        }
    }

    /// Writes raw bytes.
    pub fn raw(&mut self, b: &[u8]) -> std::io::Result<()> {
        self.crc.update(b);
        self.bytes += b.len() as u64;
        self.inner.write_all(b)
    }

    /// The CRC-32 of everything written so far.
    pub fn crc(&self) -> u32 {
        self.crc.clone().finalize()
    }

    /// The wrapped writer.
    pub fn into_inner(self) -> W {
        self.inner
    }
}

/// Little-endian base-128 with a continuation bit (OASIS `unsigned-integer`).
pub fn put_u(out: &mut Vec<u8>, mut v: u64) {
    loop {
        let b = (v & 0x7f) as u8;
        v >>= 7;
        if v == 0 {
            out.push(b);
            return;
        }
        out.push(b | 0x80);
    }
}

/// An unsigned integer whose lowest `low_bits` bits carry `tag`: signed integers (1 bit, the
/// sign), 1-, 2- and 3-deltas and g-deltas share this layout.
fn put_tagged(out: &mut Vec<u8>, magnitude: u64, low_bits: u32, tag: u64) {
    put_u(out, (magnitude << low_bits) | tag);
}

/// OASIS `signed-integer`: magnitude shifted left one bit, the sign in bit 0.
pub fn put_s(out: &mut Vec<u8>, v: i64) {
    put_tagged(out, v.unsigned_abs(), 1, u64::from(v < 0));
}

/// A `real` that is a whole non-negative number (type 0).
pub fn put_real_whole(out: &mut Vec<u8>, v: u64) {
    out.push(0);
    put_u(out, v);
}

/// A string (a-, b- or n-string: length then bytes).
pub fn put_str(out: &mut Vec<u8>, s: &[u8]) {
    put_u(out, s.len() as u64);
    out.extend_from_slice(s);
}

/// Octangular directions of deltas: E, N, W, S, NE, NW, SW, SE.
fn direction(dx: i64, dy: i64) -> Option<(u64, u64)> {
    let (ax, ay) = (dx.unsigned_abs(), dy.unsigned_abs());
    match (dx.signum(), dy.signum()) {
        (1, 0) => Some((0, ax)),
        (0, 1) => Some((1, ay)),
        (-1, 0) => Some((2, ax)),
        (0, -1) => Some((3, ay)),
        (1, 1) if ax == ay => Some((4, ax)),
        (-1, 1) if ax == ay => Some((5, ax)),
        (-1, -1) if ax == ay => Some((6, ax)),
        (1, -1) if ax == ay => Some((7, ax)),
        (0, 0) => Some((0, 0)),
        _ => None,
    }
}

/// A `g-delta`: one integer for an octangular displacement, two for any other.
pub fn put_gdelta(out: &mut Vec<u8>, dx: i64, dy: i64) {
    match direction(dx, dy) {
        Some((dir, m)) => put_tagged(out, m, 4, dir << 1),
        None => {
            put_tagged(out, dx.unsigned_abs(), 2, (u64::from(dx < 0) << 1) | 1);
            put_s(out, dy);
        }
    }
}

/// A polygon's point list (vertices after the first, relative to the previous; the closing
/// edge is implied): type 2 (Manhattan 2-deltas) when every edge is axis-parallel, else type 4
/// (g-deltas).
pub fn put_polygon_points(out: &mut Vec<u8>, pts: &[[i64; 2]]) {
    let deltas = || {
        pts.windows(2)
            .map(|w| (w[1][0] - w[0][0], w[1][1] - w[0][1]))
    };
    let manhattan = deltas().all(|(dx, dy)| dx == 0 || dy == 0);
    out.push(if manhattan { 2 } else { 4 });
    put_u(out, pts.len().saturating_sub(1) as u64);
    for (dx, dy) in deltas() {
        if manhattan {
            // 2-delta: direction E, N, W, S in the low two bits.
            let (dir, m) = direction(dx, dy).unwrap_or((0, 0));
            put_tagged(out, m, 2, dir);
        } else {
            put_gdelta(out, dx, dy);
        }
    }
}

/// A path's point list (type 4, every vertex after the first relative to the previous).
pub fn put_path_points(out: &mut Vec<u8>, pts: &[[i64; 2]]) {
    out.push(4);
    put_u(out, pts.len().saturating_sub(1) as u64);
    for w in pts.windows(2) {
        put_gdelta(out, w[1][0] - w[0][0], w[1][1] - w[0][1]);
    }
}

/// The padding that makes an END record with a CRC-32 exactly [`END_RECORD_BYTES`] long:
/// id (1) + padding string (2-byte length + pad) + scheme (1) + signature (4).
pub const END_PADDING: usize = END_RECORD_BYTES - 1 - 2 - 1 - 4;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integers_match_the_standard_examples() {
        // SEMI P39 §7.2/7.3 examples.
        let enc = |v: u64| {
            let mut o = Vec::new();
            put_u(&mut o, v);
            o
        };
        assert_eq!(enc(0), [0x00]);
        assert_eq!(enc(127), [0x7f]);
        assert_eq!(enc(128), [0x80, 0x01]);
        assert_eq!(enc(16383), [0xff, 0x7f]);
        assert_eq!(enc(16384), [0x80, 0x80, 0x01]);
        let s = |v: i64| {
            let mut o = Vec::new();
            put_s(&mut o, v);
            o
        };
        assert_eq!(s(0), [0x00]);
        assert_eq!(s(1), [0x02]);
        assert_eq!(s(-1), [0x03]);
        assert_eq!(s(63), [0x7e]);
        assert_eq!(s(-64), [0x81, 0x01]);
    }

    #[test]
    fn padding_makes_a_256_byte_end_record() {
        let mut pad_len = Vec::new();
        put_u(&mut pad_len, END_PADDING as u64);
        assert_eq!(pad_len.len(), 2);
        assert_eq!(1 + pad_len.len() + END_PADDING + 1 + 4, END_RECORD_BYTES);
    }
}
