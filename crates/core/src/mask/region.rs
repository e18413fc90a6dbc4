//! Which pixels of the display a mask covers: one pixel, a block, or the lens pupil.

use crate::ValueError;

/// Which pixels a mask covers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MaskRegion {
    /// A block of `cols × rows` pixels centred on the pixel that holds the optical axis
    /// (tiles `−⌊cols/2⌋ …` in x, likewise in y). `1 × 1` is that one pixel; a whole display is
    /// its `W × H` pixels.
    Block {
        /// Pixels across (x).
        cols: u32,
        /// Pixels down (y).
        rows: u32,
    },
    /// Every pixel that overlaps the lens pupil (diameter f / F#), plus the pupil outline.
    Pupil,
}

impl MaskRegion {
    /// The single pixel that holds the optical axis.
    pub const PIXEL: MaskRegion = MaskRegion::Block { cols: 1, rows: 1 };

    /// `pixel`, `pupil` or `WxH`.
    pub fn label(self) -> String {
        match self {
            MaskRegion::PIXEL => "pixel".into(),
            MaskRegion::Block { cols, rows } => format!("{cols}x{rows}"),
            MaskRegion::Pupil => "pupil".into(),
        }
    }
}

impl std::str::FromStr for MaskRegion {
    type Err = ValueError;
    fn from_str(s: &str) -> Result<Self, ValueError> {
        match s {
            "pixel" => return Ok(MaskRegion::PIXEL),
            "pupil" => return Ok(MaskRegion::Pupil),
            _ => {}
        }
        let bad = || ValueError::UnknownName {
            what: "region",
            value: s.to_string(),
            expected: "pixel, pupil or WxH, e.g. 1080x2400",
        };
        let (w, h) = s.split_once(['x', 'X']).ok_or_else(bad)?;
        let cols: u32 = w.trim().parse().map_err(|_| bad())?;
        let rows: u32 = h.trim().parse().map_err(|_| bad())?;
        if cols == 0 || rows == 0 {
            return Err(ValueError::Unusable {
                value: s.to_string(),
                problem: "an empty region: W and H must be at least 1".into(),
            });
        }
        Ok(MaskRegion::Block { cols, rows })
    }
}
