//! The emitter layer: which opaque cells of a pixel hold its red, green and blue OLED subpixels
//! (thesis §3.7, Fig. 3.26). Emitters are opaque, so they may only sit where the opening is
//! closed; the camera sees through the rest.

use serde::{Deserialize, Serialize};

/// The colour of one subpixel.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Subpixel {
    /// The red emitter.
    Red,
    /// The green emitter.
    Green,
    /// The blue emitter.
    Blue,
}

impl Subpixel {
    /// Every colour, in channel order (R, G, B).
    pub const ALL: [Subpixel; 3] = [Subpixel::Red, Subpixel::Green, Subpixel::Blue];

    /// The letter used in design files (`R`, `G`, `B`).
    pub fn letter(self) -> char {
        match self {
            Subpixel::Red => 'R',
            Subpixel::Green => 'G',
            Subpixel::Blue => 'B',
        }
    }

    /// The colour's name for messages.
    pub fn name(self) -> &'static str {
        match self {
            Subpixel::Red => "red",
            Subpixel::Green => "green",
            Subpixel::Blue => "blue",
        }
    }

    /// Index of the colour channel it emits (0 = R, 1 = G, 2 = B).
    pub fn index(self) -> usize {
        match self {
            Subpixel::Red => 0,
            Subpixel::Green => 1,
            Subpixel::Blue => 2,
        }
    }

    /// The colour a letter names (`R`, `G`, `B`, either case).
    pub fn from_letter(c: char) -> Option<Subpixel> {
        match c.to_ascii_uppercase() {
            'R' => Some(Subpixel::Red),
            'G' => Some(Subpixel::Green),
            'B' => Some(Subpixel::Blue),
            _ => None,
        }
    }
}

/// The emitter grid of one pixel: the same `N×N` cells as the opening, each holding a colour
/// or nothing. In design files each row is text: `R`, `G`, `B` or `.` per cell.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Subpixels {
    /// Rows of cells, row 0 at the top, `None` where no emitter sits.
    #[serde(with = "label_rows")]
    pub cells: Vec<Vec<Option<Subpixel>>>,
}

impl Subpixels {
    /// An empty `n×n` emitter grid.
    pub fn empty(n: usize) -> Self {
        Subpixels {
            cells: vec![vec![None; n]; n],
        }
    }

    /// Removes the emitters that sit on open cells of `cells` (after an edit opened them).
    pub fn clear_open(&mut self, cells: &[Vec<f64>]) {
        for (row, open_row) in self.cells.iter_mut().zip(cells) {
            for (s, &v) in row.iter_mut().zip(open_row) {
                if v > 0.0 {
                    *s = None;
                }
            }
        }
    }

    /// Cells of each colour (R, G, B).
    pub fn counts(&self) -> [usize; 3] {
        let mut out = [0; 3];
        for s in self.cells.iter().flatten().flatten() {
            out[s.index()] += 1;
        }
        out
    }
}

/// The per-colour footprint of an emitter grid, as the editor and the CLI report it (checks,
/// not errors: a designer may want unequal subpixels).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SubpixelChecks {
    /// Area of the R, G and B emitters, µm².
    pub area_um2: [f64; 3],
    /// Largest deviation of one colour's area from the mean of the three, in % of the mean
    /// (0 = equal areas; 100 when no emitter is placed).
    pub equal_area_deviation_pct: f64,
}

impl SubpixelChecks {
    /// The footprint of `subpixels` on cells of `cell_um`.
    pub fn of(subpixels: &Subpixels, cell_um: f64) -> Self {
        let counts = subpixels.counts();
        let area_um2 = counts.map(|c| c as f64 * cell_um * cell_um);
        let mean = area_um2.iter().sum::<f64>() / 3.0;
        let equal_area_deviation_pct = if mean > 0.0 {
            area_um2
                .iter()
                .map(|a| (a - mean).abs() / mean * 100.0)
                .fold(0.0, f64::max)
        } else {
            100.0
        };
        SubpixelChecks {
            area_um2,
            equal_area_deviation_pct,
        }
    }
}

mod label_rows {
    use serde::de::Error as _;
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    use super::Subpixel;

    pub fn serialize<S: Serializer>(
        cells: &[Vec<Option<Subpixel>>],
        s: S,
    ) -> Result<S::Ok, S::Error> {
        let rows: Vec<String> = cells
            .iter()
            .map(|r| r.iter().map(|v| v.map_or('.', Subpixel::letter)).collect())
            .collect();
        rows.serialize(s)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(
        d: D,
    ) -> Result<Vec<Vec<Option<Subpixel>>>, D::Error> {
        let rows = Vec::<String>::deserialize(d)?;
        rows.iter()
            .enumerate()
            .map(|(i, t)| {
                t.chars()
                    .map(|c| match c {
                        '.' => Ok(None),
                        other => Subpixel::from_letter(other).map(Some).ok_or_else(|| {
                            D::Error::custom(format!(
                                "row {i}: unexpected character {other:?} (use R, G, B or '.')"
                            ))
                        }),
                    })
                    .collect()
            })
            .collect()
    }
}
