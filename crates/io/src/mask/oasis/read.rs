//! The OASIS reader of `udc-studio import`: every record of SEMI P39 is parsed (CBLOCK
//! compression, modal variables, name tables anywhere, all point-list and repetition types),
//! and the top cell is flattened onto one layer/datatype like the GDSII reader does.
//! Trapezoids, circles and paths on the imported layer are refused with a message: the
//! studio's masks and KLayout's conversions of them contain none.

use std::collections::{HashMap, HashSet};
use std::io::Read;
use std::path::Path;

use super::encode::{MAGIC, record};
use crate::IoError;
use crate::error::OasisError;
use crate::mask::flat_size::{self, CellSize, FlatSizeError};
use crate::mask::gds::{Affine, Flat};

/// Most placements and repeated shapes one file may expand to.
const MAX_EXPANDED: usize = 20_000_000;

/// Most bytes a CBLOCK may claim to inflate to.
const MAX_CBLOCK_BYTES: u64 = 1 << 30;

#[derive(Clone, PartialEq, Eq, Hash)]
enum CellKey {
    Num(u64),
    Name(String),
}

struct Placed {
    cell: CellKey,
    flip: bool,
    mag: f64,
    angle_deg: f64,
    at: [i64; 2],
    offsets: Vec<[i64; 2]>,
}

/// Vertices (database units) and the offsets of every repeated instance.
type Repeated = (Vec<[i64; 2]>, Vec<[i64; 2]>);

#[derive(Default)]
struct CellData {
    polygons: Vec<Repeated>,
    texts: Vec<String>,
    placements: Vec<Placed>,
}

/// An END record's validation (SEMI P39 §14.4): scheme 1 is the CRC-32 of ISO 3309 (zlib's),
/// scheme 2 the sum of the bytes modulo 2^32, each over every byte of the file before the
/// signature, the magic included; the signature is stored least significant byte first.
#[derive(Debug, Clone, Copy)]
struct Validation {
    /// Scheme 2 (checksum-32) rather than 1 (CRC-32).
    checksum: bool,
    /// Where the signature starts, in the bytes after the magic.
    covers: usize,
    /// The signature the file carries.
    stored: u32,
}

impl Validation {
    /// Checks the signature over `file` (the whole file, magic included).
    fn check(&self, file: &[u8]) -> R<()> {
        let covered = &file[..(MAGIC.len() + self.covers).min(file.len())];
        let computed = if self.checksum {
            covered
                .iter()
                .fold(0u32, |sum, &b| sum.wrapping_add(u32::from(b)))
        } else {
            crc32fast::hash(covered)
        };
        if computed == self.stored {
            return Ok(());
        }
        Err(OasisError::ValidationMismatch {
            scheme: if self.checksum {
                "checksum-32"
            } else {
                "CRC-32"
            },
            stored: self.stored,
            computed,
        })
    }
}

/// The modal variables (SEMI P39 §10), reset at each CELL record.
#[derive(Default)]
struct Modal {
    relative: bool,
    placement_xy: [i64; 2],
    placement_cell: Option<CellKey>,
    geometry_xy: [i64; 2],
    text_xy: [i64; 2],
    layer: u64,
    datatype: u64,
    textlayer: u64,
    texttype: u64,
    text: Option<TextRef>,
    width: u64,
    height: u64,
    polygon_points: Vec<[i64; 2]>,
    repetition: Vec<[i64; 2]>,
}

#[derive(Clone)]
enum TextRef {
    Num(u64),
    Inline(String),
}

struct State {
    unit_per_um: f64,
    cellnames: HashMap<u64, String>,
    next_cellname: u64,
    textstrings: HashMap<u64, String>,
    next_textstring: u64,
    cells: HashMap<CellKey, CellData>,
    order: Vec<CellKey>,
    current: Option<CellKey>,
    modal: Modal,
    expanded: usize,
    ended: bool,
    /// The END record's validation signature, when it has one.
    validation: Option<Validation>,
    /// START's offset flag was 1: the table offsets are in the END record.
    offsets_in_end: bool,
    /// Where the outer stream's END record ends, in the bytes after the magic.
    end_at: Option<usize>,
    in_cblock: bool,
    want: (u64, u64),
}

/// A displacement of magnitude `m` in octangular direction `dir` (E, N, W, S, NE, NW, SW, SE):
/// 2-, 3- and g-deltas share it.
fn octant(m: i64, dir: u64) -> [i64; 2] {
    match dir {
        0 => [m, 0],
        1 => [0, m],
        2 => [-m, 0],
        3 => [0, -m],
        4 => [m, m],
        5 => [-m, m],
        6 => [-m, -m],
        _ => [m, -m],
    }
}

struct Bytes<'a> {
    data: &'a [u8],
    pos: usize,
}

type R<T> = Result<T, OasisError>;

impl Bytes<'_> {
    fn byte(&mut self) -> R<u8> {
        let b = *self
            .data
            .get(self.pos)
            .ok_or(OasisError::EndsInRecord { byte: self.pos })?;
        self.pos += 1;
        Ok(b)
    }
    fn take(&mut self, n: u64) -> R<&[u8]> {
        let n = usize::try_from(n).map_err(|_| OasisError::LengthTooLarge)?;
        let end = self.pos.checked_add(n).filter(|&e| e <= self.data.len());
        let end = end.ok_or(OasisError::PastEnd { bytes: n })?;
        let s = &self.data[self.pos..end];
        self.pos = end;
        Ok(s)
    }
    fn u(&mut self) -> R<u64> {
        // Any number of bytes: a writer may pad with zero continuation bytes (KLayout writes
        // its END record's padding length as 0x80 0x80 … 0x00); only set bits past the 64th
        // overflow.
        let mut v = 0u64;
        let mut shift = 0u32;
        loop {
            let b = self.byte()?;
            let payload = u64::from(b & 0x7f);
            if payload != 0 {
                v |= payload
                    .checked_shl(shift)
                    .filter(|x| shift < 64 && x >> shift == payload)
                    .ok_or(OasisError::Overflow64)?;
            }
            if b & 0x80 == 0 {
                return Ok(v);
            }
            shift = shift.saturating_add(7);
        }
    }
    fn tagged(&mut self, low_bits: u32) -> R<(i64, u64)> {
        let v = self.u()?;
        let m = i64::try_from(v >> low_bits).map_err(|_| OasisError::Overflow)?;
        Ok((m, v & ((1 << low_bits) - 1)))
    }
    fn s(&mut self) -> R<i64> {
        let (m, sign) = self.tagged(1)?;
        Ok(if sign == 1 { -m } else { m })
    }
    fn string(&mut self) -> R<String> {
        let n = self.u()?;
        Ok(String::from_utf8_lossy(self.take(n)?).into_owned())
    }
    fn real(&mut self) -> R<f64> {
        let kind = self.u()?;
        self.real_of(kind)
    }
    fn real_of(&mut self, kind: u64) -> R<f64> {
        Ok(match kind {
            0 => self.u()? as f64,
            1 => -(self.u()? as f64),
            2 => 1.0 / self.u()? as f64,
            3 => -1.0 / self.u()? as f64,
            4 => self.u()? as f64 / self.u()? as f64,
            5 => -(self.u()? as f64) / self.u()? as f64,
            6 => f64::from(f32::from_le_bytes(
                self.take(4)?
                    .try_into()
                    .map_err(|_| OasisError::ShortReal)?,
            )),
            7 => f64::from_le_bytes(
                self.take(8)?
                    .try_into()
                    .map_err(|_| OasisError::ShortReal)?,
            ),
            t => return Err(OasisError::UnknownReal(t)),
        })
    }
    fn delta(&mut self, low_bits: u32) -> R<[i64; 2]> {
        let (m, dir) = self.tagged(low_bits)?;
        Ok(octant(m, dir))
    }
    fn gdelta(&mut self) -> R<[i64; 2]> {
        let first = *self.data.get(self.pos).ok_or(OasisError::EndsInGDelta)?;
        if first & 1 == 0 {
            let (m, bits) = self.tagged(4)?;
            Ok(octant(m, bits >> 1))
        } else {
            let (m, bits) = self.tagged(2)?;
            let x = if bits & 2 != 0 { -m } else { m };
            Ok([x, self.s()?])
        }
    }
    fn interval(&mut self) -> R<()> {
        match self.u()? {
            0 => {}
            1..=3 => {
                self.u()?;
            }
            4 => {
                self.u()?;
                self.u()?;
            }
            t => return Err(OasisError::UnknownInterval(t)),
        }
        Ok(())
    }
}

impl State {
    fn count(&mut self, n: usize) -> R<()> {
        // A repetition may claim u64::MAX instances: the total saturates instead of wrapping.
        self.expanded = self.expanded.saturating_add(n);
        if self.expanded > MAX_EXPANDED {
            return Err(OasisError::TooManyShapes { max: MAX_EXPANDED });
        }
        Ok(())
    }

    /// A point list as vertices from the origin (the first vertex is `[0, 0]`).
    fn point_list(&mut self, b: &mut Bytes, polygon: bool) -> R<Vec<[i64; 2]>> {
        let kind = b.u()?;
        let n = b.u()?;
        self.count(n as usize)?;
        let mut pts = vec![[0i64, 0i64]];
        let mut last = [0i64, 0i64];
        match kind {
            0 | 1 => {
                let mut horizontal = kind == 0;
                for _ in 0..n {
                    let d = b.s()?;
                    last = add(last, if horizontal { [d, 0] } else { [0, d] })?;
                    pts.push(last);
                    horizontal = !horizontal;
                }
                if polygon {
                    // The implied vertex that makes the closing edge axis-parallel.
                    pts.push(if horizontal {
                        [0, last[1]]
                    } else {
                        [last[0], 0]
                    });
                }
            }
            2..=4 => {
                for _ in 0..n {
                    let d = match kind {
                        2 => b.delta(2)?,
                        3 => b.delta(3)?,
                        _ => b.gdelta()?,
                    };
                    last = add(last, d)?;
                    pts.push(last);
                }
            }
            5 => {
                let mut step = [0i64, 0i64];
                for _ in 0..n {
                    let d = b.gdelta()?;
                    step = add(step, d)?;
                    last = add(last, step)?;
                    pts.push(last);
                }
            }
            t => return Err(OasisError::UnknownPointList(t)),
        }
        Ok(pts)
    }

    /// A repetition as the offsets of every instance (the first is `[0, 0]`).
    fn repetition(&mut self, b: &mut Bytes) -> R<Vec<[i64; 2]>> {
        let kind = b.u()?;
        if kind == 0 {
            return Ok(self.modal.repetition.clone());
        }
        let dims = |b: &mut Bytes| -> R<u64> { Ok(b.u()?.saturating_add(2)) };
        let mut out = Vec::new();
        let grid2 = |nx: u64, ny: u64, vx: [i64; 2], vy: [i64; 2], out: &mut Vec<[i64; 2]>| {
            for j in 0..ny as i64 {
                for i in 0..nx as i64 {
                    out.push(add(times(vx, i)?, times(vy, j)?)?);
                }
            }
            Ok::<(), OasisError>(())
        };
        let size = |n: u64, this: &mut State| this.count(usize::try_from(n).unwrap_or(usize::MAX));
        match kind {
            1 => {
                let (nx, ny) = (dims(b)?, dims(b)?);
                size(nx.saturating_mul(ny), self)?;
                let (sx, sy) = (b.u()? as i64, b.u()? as i64);
                grid2(nx, ny, [sx, 0], [0, sy], &mut out)?;
            }
            2 | 3 => {
                let n = dims(b)?;
                size(n, self)?;
                let s = b.u()? as i64;
                let v = if kind == 2 { [s, 0] } else { [0, s] };
                grid2(n, 1, v, [0, 0], &mut out)?;
            }
            4..=7 => {
                let n = dims(b)?;
                size(n, self)?;
                let grid = if kind % 2 == 1 { b.u()? as i64 } else { 1 };
                let mut at = 0i64;
                out.push([0, 0]);
                for _ in 1..n {
                    let step = (b.u()? as i64).checked_mul(grid);
                    at = step
                        .and_then(|s| at.checked_add(s))
                        .ok_or(OasisError::Overflow)?;
                    out.push(if kind <= 5 { [at, 0] } else { [0, at] });
                }
            }
            8 => {
                let (nx, ny) = (dims(b)?, dims(b)?);
                size(nx.saturating_mul(ny), self)?;
                let (vx, vy) = (b.gdelta()?, b.gdelta()?);
                grid2(nx, ny, vx, vy, &mut out)?;
            }
            9 => {
                let n = dims(b)?;
                size(n, self)?;
                let v = b.gdelta()?;
                grid2(n, 1, v, [0, 0], &mut out)?;
            }
            10 | 11 => {
                let n = dims(b)?;
                size(n, self)?;
                let grid = if kind == 11 { b.u()? as i64 } else { 1 };
                let mut at = [0i64, 0i64];
                out.push(at);
                for _ in 1..n {
                    let d = b.gdelta()?;
                    at = add(at, times(d, grid)?)?;
                    out.push(at);
                }
            }
            t => return Err(OasisError::UnknownRepetition(t)),
        }
        self.modal.repetition = out.clone();
        Ok(out)
    }

    fn xy(&self, modal: [i64; 2], x: Option<i64>, y: Option<i64>) -> R<[i64; 2]> {
        let pick = |m: i64, v: Option<i64>| match v {
            Some(v) if self.modal.relative => m.checked_add(v).ok_or(OasisError::Overflow),
            Some(v) => Ok(v),
            None => Ok(m),
        };
        Ok([pick(modal[0], x)?, pick(modal[1], y)?])
    }

    fn cell(&mut self) -> R<&mut CellData> {
        let key = self.current.clone().ok_or(OasisError::ElementOutsideCell)?;
        Ok(self.cells.entry(key).or_default())
    }

    fn records(&mut self, b: &mut Bytes) -> R<()> {
        while b.pos < b.data.len() && !self.ended {
            let at = b.pos;
            let id = b.u()?;
            self.record(b, id).map_err(|e| OasisError::Record {
                id,
                byte: at,
                error: Box::new(e),
            })?;
        }
        Ok(())
    }

    fn record(&mut self, b: &mut Bytes, id: u64) -> R<()> {
        use record::*;
        match id {
            PAD | XYABSOLUTE | XYRELATIVE | LAST_PROPERTY => {
                if id == XYABSOLUTE || id == XYRELATIVE {
                    self.modal.relative = id == XYRELATIVE;
                }
            }
            START => {
                b.string()?;
                self.unit_per_um = b.real()?;
                if !(self.unit_per_um.is_finite() && self.unit_per_um > 0.0) {
                    return Err(OasisError::UnitNotPositive {
                        unit: self.unit_per_um,
                    });
                }
                // Offset flag 0: the table offsets follow here; 1: they are in the END record.
                if b.u()? == 0 {
                    for _ in 0..12 {
                        b.u()?;
                    }
                } else {
                    self.offsets_in_end = true;
                }
            }
            END => {
                // The table offsets when START deferred them here, padding, then the validation
                // scheme and its signature (SEMI P39 §14.4). The signature covers every byte of
                // the file before it, so only the outer stream's END can carry one.
                if self.offsets_in_end {
                    for _ in 0..12 {
                        b.u()?;
                    }
                }
                b.string()?;
                let scheme = b.u()?;
                let signature_at = b.pos;
                let signature = match scheme {
                    0 => None,
                    1 | 2 => {
                        let s = b.take(4)?;
                        Some(u32::from_le_bytes([s[0], s[1], s[2], s[3]]))
                    }
                    other => return Err(OasisError::UnknownValidation(other)),
                };
                if !self.in_cblock {
                    self.validation = signature.map(|stored| Validation {
                        checksum: scheme == 2,
                        covers: signature_at,
                        stored,
                    });
                    self.end_at = Some(b.pos);
                }
                self.ended = true;
            }
            CELLNAME_IMPLICIT | CELLNAME => {
                let (n, name) = named(b, id == CELLNAME, &mut self.next_cellname)?;
                self.cellnames.insert(n, name);
            }
            TEXTSTRING_IMPLICIT | TEXTSTRING => {
                let (n, s) = named(b, id == TEXTSTRING, &mut self.next_textstring)?;
                self.textstrings.insert(n, s);
            }
            PROPNAME_IMPLICIT | PROPSTRING_IMPLICIT => {
                b.string()?;
            }
            PROPNAME | PROPSTRING => {
                b.string()?;
                b.u()?;
            }
            LAYERNAME_GEOMETRY | LAYERNAME_TEXT => {
                b.string()?;
                b.interval()?;
                b.interval()?;
            }
            CELL_REF | CELL_NAMED => {
                let key = if id == CELL_REF {
                    CellKey::Num(b.u()?)
                } else {
                    CellKey::Name(b.string()?)
                };
                if !self.cells.contains_key(&key) {
                    self.order.push(key.clone());
                }
                self.cells.entry(key.clone()).or_default();
                self.current = Some(key);
                self.modal = Modal::default();
            }
            PLACEMENT | PLACEMENT_TRANSFORM => self.placement(b, id == PLACEMENT_TRANSFORM)?,
            TEXT => self.text(b)?,
            RECTANGLE | POLYGON | PATH | TRAPEZOID_AB | TRAPEZOID_A | TRAPEZOID_B | CTRAPEZOID
            | CIRCLE => self.geometry(b, id)?,
            PROPERTY => {
                let info = b.byte()?;
                if info & 0b100 != 0 {
                    if info & 0b10 != 0 {
                        b.u()?;
                    } else {
                        b.string()?;
                    }
                }
                if info & 0b1000 == 0 {
                    let mut n = u64::from(info >> 4);
                    if n == 15 {
                        n = b.u()?;
                    }
                    for _ in 0..n {
                        match b.u()? {
                            t @ 0..=7 => {
                                b.real_of(t)?;
                            }
                            8 | 13..=15 => {
                                b.u()?;
                            }
                            9 => {
                                b.s()?;
                            }
                            10..=12 => {
                                b.string()?;
                            }
                            t => return Err(OasisError::UnknownPropertyValue(t)),
                        }
                    }
                }
            }
            XNAME_IMPLICIT => {
                b.u()?;
                b.string()?;
            }
            XNAME => {
                b.u()?;
                b.string()?;
                b.u()?;
            }
            XELEMENT => {
                b.u()?;
                b.string()?;
            }
            XGEOMETRY => {
                let info = b.byte()?;
                b.u()?;
                if info & 1 != 0 {
                    self.modal.layer = b.u()?;
                }
                if info & 2 != 0 {
                    self.modal.datatype = b.u()?;
                }
                b.string()?;
                if info & 0x10 != 0 {
                    b.s()?;
                }
                if info & 0x08 != 0 {
                    b.s()?;
                }
                if info & 0x04 != 0 {
                    self.repetition(b)?;
                }
            }
            CBLOCK => {
                let kind = b.u()?;
                let (full, packed) = (b.u()?, b.u()?);
                if kind != 0 {
                    return Err(OasisError::UnknownCompression(kind));
                }
                if full > MAX_CBLOCK_BYTES {
                    return Err(OasisError::CblockTooLarge { bytes: full });
                }
                // SEMI P39 forbids a CBLOCK inside a CBLOCK; refusing it also bounds the
                // recursion a crafted file could ask for.
                if self.in_cblock {
                    return Err(OasisError::NestedCblock);
                }
                // The packed bytes first: a claimed length is only trusted once the file has
                // that many bytes. Deflate expands at most about 1032×: no more is reserved.
                let packed = b.take(packed)?;
                let reserve = full.min((packed.len() as u64).saturating_mul(1032));
                let mut data = Vec::with_capacity(reserve as usize);
                flate2::read::DeflateDecoder::new(packed)
                    .take(full)
                    .read_to_end(&mut data)
                    .map_err(OasisError::Inflate)?;
                self.in_cblock = true;
                let inner = self.records(&mut Bytes {
                    data: &data,
                    pos: 0,
                });
                self.in_cblock = false;
                inner?;
            }
            other => return Err(OasisError::UnknownRecord(other)),
        }
        Ok(())
    }

    fn placement(&mut self, b: &mut Bytes, transform: bool) -> R<()> {
        let info = b.byte()?;
        if info & 0x80 != 0 {
            let key = if info & 0x40 != 0 {
                CellKey::Num(b.u()?)
            } else {
                CellKey::Name(b.string()?)
            };
            self.modal.placement_cell = Some(key);
        }
        let cell = self
            .modal
            .placement_cell
            .clone()
            .ok_or(OasisError::PlacementWithoutCell)?;
        let (mut mag, mut angle_deg) = (1.0, 0.0);
        if transform {
            if info & 0x04 != 0 {
                mag = b.real()?;
            }
            if info & 0x02 != 0 {
                angle_deg = b.real()?;
            }
        } else {
            angle_deg = f64::from((info >> 1) & 3) * 90.0;
        }
        let x = if info & 0x20 != 0 { Some(b.s()?) } else { None };
        let y = if info & 0x10 != 0 { Some(b.s()?) } else { None };
        let at = self.xy(self.modal.placement_xy, x, y)?;
        self.modal.placement_xy = at;
        let offsets = if info & 0x08 != 0 {
            self.repetition(b)?
        } else {
            vec![[0, 0]]
        };
        self.count(offsets.len())?;
        self.cell()?.placements.push(Placed {
            cell,
            flip: info & 1 != 0,
            mag,
            angle_deg,
            at,
            offsets,
        });
        Ok(())
    }

    fn text(&mut self, b: &mut Bytes) -> R<()> {
        let info = b.byte()?;
        if info & 0x40 != 0 {
            self.modal.text = Some(if info & 0x20 != 0 {
                TextRef::Num(b.u()?)
            } else {
                TextRef::Inline(b.string()?)
            });
        }
        if info & 0x01 != 0 {
            self.modal.textlayer = b.u()?;
        }
        if info & 0x02 != 0 {
            self.modal.texttype = b.u()?;
        }
        let x = if info & 0x10 != 0 { Some(b.s()?) } else { None };
        let y = if info & 0x08 != 0 { Some(b.s()?) } else { None };
        self.modal.text_xy = self.xy(self.modal.text_xy, x, y)?;
        if info & 0x04 != 0 {
            self.repetition(b)?;
        }
        let s = match self.modal.text.clone() {
            Some(TextRef::Inline(s)) => s,
            // Text strings may be defined after use (tables at the END); resolved later.
            Some(TextRef::Num(n)) => format!("\u{0}{n}"),
            None => return Err(OasisError::TextWithoutString),
        };
        self.cell()?.texts.push(s);
        Ok(())
    }

    fn geometry(&mut self, b: &mut Bytes, id: u64) -> R<()> {
        use record::*;
        let info = b.byte()?;
        if info & 0x01 != 0 {
            self.modal.layer = b.u()?;
        }
        if info & 0x02 != 0 {
            self.modal.datatype = b.u()?;
        }
        let mut shape: Option<Vec<[i64; 2]>> = None;
        let mut unsupported = None;
        match id {
            RECTANGLE => {
                if info & 0x40 != 0 {
                    self.modal.width = b.u()?;
                }
                if info & 0x20 != 0 {
                    self.modal.height = b.u()?;
                }
                if info & 0x80 != 0 {
                    self.modal.height = self.modal.width;
                }
                let (w, h) = (self.modal.width as i64, self.modal.height as i64);
                shape = Some(vec![[0, 0], [w, 0], [w, h], [0, h]]);
            }
            POLYGON => {
                if info & 0x20 != 0 {
                    self.modal.polygon_points = self.point_list(b, true)?;
                }
                shape = Some(self.modal.polygon_points.clone());
            }
            PATH => {
                if info & 0x40 != 0 {
                    b.u()?;
                }
                if info & 0x80 != 0 {
                    let scheme = b.u()?;
                    if scheme >> 2 & 3 == 3 {
                        b.s()?;
                    }
                    if scheme & 3 == 3 {
                        b.s()?;
                    }
                }
                if info & 0x20 != 0 {
                    self.point_list(b, false)?;
                }
                unsupported = Some("PATH");
            }
            TRAPEZOID_AB | TRAPEZOID_A | TRAPEZOID_B | CTRAPEZOID => {
                if id == CTRAPEZOID && info & 0x80 != 0 {
                    b.u()?;
                }
                if info & 0x40 != 0 {
                    b.u()?;
                }
                if info & 0x20 != 0 {
                    b.u()?;
                }
                if id != CTRAPEZOID {
                    if id != TRAPEZOID_B {
                        b.s()?;
                    }
                    if id != TRAPEZOID_A {
                        b.s()?;
                    }
                }
                unsupported = Some("TRAPEZOID");
            }
            _ => {
                if info & 0x20 != 0 {
                    b.u()?;
                }
                unsupported = Some("CIRCLE");
            }
        }
        let x = if info & 0x10 != 0 { Some(b.s()?) } else { None };
        let y = if info & 0x08 != 0 { Some(b.s()?) } else { None };
        let at = self.xy(self.modal.geometry_xy, x, y)?;
        self.modal.geometry_xy = at;
        let offsets = if info & 0x04 != 0 {
            self.repetition(b)?
        } else {
            vec![[0, 0]]
        };
        if (self.modal.layer, self.modal.datatype) != self.want {
            return Ok(());
        }
        if let Some(kind) = unsupported {
            return Err(OasisError::Unsupported {
                kind,
                layer: self.want.0,
                datatype: self.want.1,
            });
        }
        self.count(offsets.len())?;
        if let Some(pts) = shape {
            let pts = pts.iter().map(|p| add(*p, at)).collect::<R<_>>()?;
            self.cell()?.polygons.push((pts, offsets));
        }
        Ok(())
    }
}

/// `a + b`: coordinates and offsets come from the file, so a sum past i64 is an error, not a
/// panic (or, in a release build, a wrapped coordinate).
fn add(a: [i64; 2], b: [i64; 2]) -> R<[i64; 2]> {
    let sum = |x: i64, y: i64| x.checked_add(y).ok_or(OasisError::Overflow);
    Ok([sum(a[0], b[0])?, sum(a[1], b[1])?])
}

/// `k · v`, an error past i64 as [`add`].
fn times(v: [i64; 2], k: i64) -> R<[i64; 2]> {
    let product = |x: i64| x.checked_mul(k).ok_or(OasisError::Overflow);
    Ok([product(v[0])?, product(v[1])?])
}

/// A name record's string and reference number: explicit, or the next implicit one.
fn named(b: &mut Bytes, explicit: bool, next: &mut u64) -> R<(u64, String)> {
    let s = b.string()?;
    let n = if explicit { b.u()? } else { *next };
    *next = n.saturating_add(1);
    Ok((n, s))
}

/// Reads an OASIS file and expands its top cell (the one no other cell places).
pub(crate) fn read(path: &Path, layer: i16, datatype: i16) -> Result<Flat, IoError> {
    let err = |error: OasisError| IoError::Oasis {
        path: path.to_path_buf(),
        error,
    };
    let bytes =
        crate::safe_file::read_bounded(path, super::super::MAX_MASK_BYTES, "read the mask")?;
    let Some(body) = bytes.strip_prefix(MAGIC) else {
        return Err(err(OasisError::NotOasis));
    };
    // A signed END record in its place (the last 256 bytes: record id, padding, scheme,
    // signature) is checked before any record is parsed: a damaged byte is reported as damage,
    // not as whatever a parser makes of it. Anything else is judged after the parse.
    if body.len() >= 256 && u64::from(body[body.len() - 256]) == record::END {
        let scheme = body[body.len() - 5];
        if scheme == 1 || scheme == 2 {
            let s = &body[body.len() - 4..];
            Validation {
                checksum: scheme == 2,
                covers: body.len() - 4,
                stored: u32::from_le_bytes([s[0], s[1], s[2], s[3]]),
            }
            .check(&bytes)
            .map_err(err)?;
        }
    }
    let mut state = State {
        unit_per_um: 1000.0,
        cellnames: HashMap::new(),
        next_cellname: 0,
        textstrings: HashMap::new(),
        next_textstring: 0,
        cells: HashMap::new(),
        order: Vec::new(),
        current: None,
        modal: Modal::default(),
        expanded: 0,
        ended: false,
        validation: None,
        offsets_in_end: false,
        end_at: None,
        in_cblock: false,
        want: (layer.max(0) as u64, datatype.max(0) as u64),
    };
    state
        .records(&mut Bytes { data: body, pos: 0 })
        .map_err(|e| err(OasisError::Unreadable(Box::new(e))))?;
    if !state.ended {
        return Err(err(OasisError::NoEnd));
    }
    // Before anything is expanded: a damaged file is never read as a different design. The END
    // record is the file's last 256 bytes (SEMI P39 §14.4): one that ends elsewhere was found
    // by a misread (a damaged header can turn its validation off), so it is refused too.
    if state.end_at != Some(body.len()) {
        return Err(err(OasisError::EndNotLast));
    }
    if let Some(v) = &state.validation {
        v.check(&bytes).map_err(err)?;
    }
    flatten(state).map_err(err)
}

fn flatten(s: State) -> R<Flat> {
    let canon = |k: &CellKey| -> String {
        match k {
            CellKey::Num(n) => s
                .cellnames
                .get(n)
                .cloned()
                .unwrap_or_else(|| format!("#{n}")),
            CellKey::Name(n) => n.clone(),
        }
    };
    let names: Vec<String> = s.order.iter().map(canon).collect();
    let cells: Vec<&CellData> = s.order.iter().map(|k| &s.cells[k]).collect();
    let index: HashMap<&str, usize> = names
        .iter()
        .enumerate()
        .map(|(i, n)| (n.as_str(), i))
        .collect();
    let place = |k: &CellKey| -> R<usize> {
        let name = canon(k);
        index
            .get(name.as_str())
            .copied()
            .ok_or(OasisError::MissingCell { name })
    };
    let text = |t: &String| -> String {
        match t.strip_prefix('\u{0}').and_then(|n| n.parse::<u64>().ok()) {
            Some(n) => s.textstrings.get(&n).cloned().unwrap_or_default(),
            None => t.clone(),
        }
    };
    // Each placement's cell, resolved once: the expansion below pushes indices, not names.
    let placed: Vec<Vec<usize>> = cells
        .iter()
        .map(|c| c.placements.iter().map(|p| place(&p.cell)).collect())
        .collect::<R<_>>()?;
    let referenced: HashSet<usize> = placed.iter().flatten().copied().collect();
    let tops: Vec<usize> = (0..cells.len())
        .filter(|i| !referenced.contains(i))
        .collect();
    let &[top] = tops.as_slice() else {
        return Err(OasisError::TopCells {
            found: tops.iter().map(|&i| names[i].clone()).collect(),
        });
    };
    let sizes: Vec<CellSize> = cells
        .iter()
        .zip(&placed)
        .map(|(c, placed)| CellSize {
            own_bytes: c
                .polygons
                .iter()
                .map(|(pts, o)| flat_size::polygon_bytes(pts.len()).saturating_mul(o.len()))
                .chain(c.texts.iter().map(|t| flat_size::text_bytes(text(t).len())))
                .fold(0, usize::saturating_add),
            children: placed
                .iter()
                .zip(&c.placements)
                .map(|(&i, p)| (i, p.offsets.len()))
                .collect(),
        })
        .collect();
    flat_size::flattened_bytes(&sizes, top).map_err(|e| match e {
        FlatSizeError::TooDeep => OasisError::TooDeep,
        FlatSizeError::TooLarge => OasisError::ExpandsTooLarge {
            max_mib: flat_size::MAX_FLAT_BYTES >> 20,
        },
    })?;
    let scale = 1.0 / s.unit_per_um;
    let mut flat = Flat {
        polygons_um: Vec::new(),
        texts: Vec::new(),
    };
    let mut stack = vec![(top, Affine::IDENTITY)];
    while let Some((at, tf)) = stack.pop() {
        let cell = cells[at];
        for (pts, offsets) in &cell.polygons {
            for o in offsets {
                flat.polygons_um.push(
                    pts.iter()
                        .map(|p| tf.apply([p[0] as f64 + o[0] as f64, p[1] as f64 + o[1] as f64]))
                        .map(|p| [p[0] * scale, p[1] * scale])
                        .collect(),
                );
            }
        }
        flat.texts.extend(cell.texts.iter().map(text));
        for (p, &child) in cell.placements.iter().zip(&placed[at]) {
            for o in &p.offsets {
                let at = [p.at[0] as f64 + o[0] as f64, p.at[1] as f64 + o[1] as f64];
                stack.push((child, tf.then(p.flip, p.mag, p.angle_deg, at)));
            }
        }
    }
    Ok(flat)
}
