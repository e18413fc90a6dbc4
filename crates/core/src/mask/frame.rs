//! The die frame, alignment marks and label around a mask's active area: pure geometry in the
//! mask frame (nm, y up), snapped to the layout's grid, for the writers in `io::mask`.
//!
//! Placement, from the region's bounding box `B` (snapped outward to the grid):
//! - **frame**: a ring `frame_width_um` wide whose inner edge lies `margin_um` outside `B`,
//!   written as four non-overlapping rectangles (bottom and top the full width, left and right
//!   between them), so no reader has to handle a polygon with a hole;
//! - **marks**: four crosses (`mark_size_um` square, arms `mark_arm_width_um` wide), one beyond
//!   each corner of the frame (of `B` grown by the margin when there is no frame), `margin_um`
//!   away from it in x and y;
//! - **label**: one line of text, `label_height_um` high, its lower-left corner `margin_um`
//!   below everything else and level with the frame's left edge.
//!
//! Every polygon and the label lie strictly outside `B`: the margin is at least one grid step.

use super::{MaskError, Polygon};

/// The largest length a frame setting accepts, in µm (10 mm: more than any die).
pub const MAX_FRAME_LENGTH_UM: f64 = 10_000.0;

/// Which part of the frame a polygon belongs to (each goes to its own layer).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FramePart {
    /// The die frame around the active area.
    Frame,
    /// The alignment crosses at the corners.
    Marks,
}

/// Which of the frame, marks and label an export draws, and their sizes.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameSpec {
    /// Draw the die frame.
    pub frame: bool,
    /// Draw the four alignment crosses.
    pub marks: bool,
    /// Write the label (design name, date, scale).
    pub label: bool,
    /// Distance from the region's bounding box to the frame, from the frame to the marks and
    /// from the marks to the label, µm (default 50).
    pub margin_um: f64,
    /// Width of the frame's ring, µm (default 10).
    pub frame_width_um: f64,
    /// Side of the square each alignment cross fills, µm (default 100).
    pub mark_size_um: f64,
    /// Width of a cross's arms, µm (default 10).
    pub mark_arm_width_um: f64,
    /// Height of the label's letters, µm (default 20; DXF and SVG use it, GDSII texts have none).
    pub label_height_um: f64,
}

impl Default for FrameSpec {
    fn default() -> Self {
        FrameSpec {
            frame: false,
            marks: false,
            label: false,
            margin_um: 50.0,
            frame_width_um: 10.0,
            mark_size_um: 100.0,
            mark_arm_width_um: 10.0,
            label_height_um: 20.0,
        }
    }
}

impl FrameSpec {
    /// Whether anything is drawn.
    pub fn any(&self) -> bool {
        self.frame || self.marks || self.label
    }

    /// Checks every size (enabled or not, so a bad value never waits for its checkbox).
    ///
    /// # Errors
    /// A [`FrameError`] naming the bad size.
    pub fn validate(&self) -> Result<(), FrameError> {
        for (what, value) in [
            ("frame margin (µm)", self.margin_um),
            ("frame width (µm)", self.frame_width_um),
            ("mark size (µm)", self.mark_size_um),
            ("mark arm width (µm)", self.mark_arm_width_um),
            ("label height (µm)", self.label_height_um),
        ] {
            if !(value.is_finite() && value > 0.0 && value <= MAX_FRAME_LENGTH_UM) {
                return Err(FrameError::OutOfRange { what, value });
            }
        }
        if self.mark_arm_width_um >= self.mark_size_um {
            return Err(FrameError::ArmNotThinner {
                arm_um: self.mark_arm_width_um,
                size_um: self.mark_size_um,
            });
        }
        Ok(())
    }
}

/// Why a die frame cannot be drawn.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FrameError {
    /// A size that is not a number above 0 and at most [`MAX_FRAME_LENGTH_UM`].
    #[error("{what} must be a number above 0 and at most {MAX_FRAME_LENGTH_UM} (got {})", short(*.value))]
    OutOfRange {
        /// The size as the dialog labels it, with its unit ("frame width (µm)").
        what: &'static str,
        /// The value given, µm.
        value: f64,
    },
    /// A mark whose arms are as wide as the mark: no cross is left.
    #[error(
        "mark arm width (µm) must be smaller than the mark size ({} >= {})",
        short(*.arm_um),
        short(*.size_um)
    )]
    ArmNotThinner {
        /// The arm width, µm.
        arm_um: f64,
        /// The mark size, µm.
        size_um: f64,
    },
}

/// A value as a user typed it, short even for 1e308.
fn short(v: f64) -> String {
    if v.is_finite() && v.abs() < 1e9 {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// The label's text and place.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameLabel {
    /// One line of ASCII.
    pub text: String,
    /// Lower-left corner of the text, nm.
    pub at_nm: [i64; 2],
    /// Letter height, nm.
    pub height_nm: i64,
}

/// What [`frame_geometry`] lays out.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct FrameGeometry {
    /// Manhattan polygons (nm, counter-clockwise), each with its part.
    pub polygons: Vec<(FramePart, Polygon)>,
    /// The label, when asked for.
    pub label: Option<FrameLabel>,
    /// `[min x, min y, max x, max y]` of the polygons and the label's anchor, nm; the region's
    /// box when nothing is drawn.
    pub extent_nm: [i64; 4],
}

/// The label's text: `UDC STUDIO <name> <date> SCALE 1 UM = 1000 DBU GRID <g> NM`, ASCII
/// (anything else becomes `?`), the name cut to 60 characters.
pub fn label_text(design_name: &str, date: &str, grid_nm: i64) -> String {
    let name: String = design_name
        .chars()
        .map(|c| {
            if c.is_ascii_graphic() || c == ' ' {
                c
            } else {
                '?'
            }
        })
        .take(60)
        .collect();
    format!("UDC STUDIO {name} {date} SCALE 1 UM = 1000 DBU GRID {grid_nm} NM")
}

fn rect(x0: i64, y0: i64, x1: i64, y1: i64) -> Polygon {
    Polygon {
        points_nm: vec![[x0, y0], [x1, y0], [x1, y1], [x0, y1]],
    }
}

/// A cross filling the square of side `2a + w` at lower-left `(x, y)`, arms `w` wide.
fn cross(x: i64, y: i64, a: i64, w: i64) -> Polygon {
    let (b, s) = (a + w, 2 * a + w);
    Polygon {
        points_nm: vec![
            [x + a, y],
            [x + b, y],
            [x + b, y + a],
            [x + s, y + a],
            [x + s, y + b],
            [x + b, y + b],
            [x + b, y + s],
            [x + a, y + s],
            [x + a, y + b],
            [x, y + b],
            [x, y + a],
            [x + a, y + a],
        ],
    }
}

/// The frame, marks and label of `spec` around `region_bbox_nm` (`[min x, min y, max x,
/// max y]`), every coordinate a multiple of `grid_nm`. `label` is the label's text.
///
/// # Errors
/// [`MaskError::Frame`] for a bad spec, [`MaskError::Invalid`] for a bad grid, [`MaskError::TooLarge`] when a coordinate
/// leaves GDSII's 32-bit range.
pub fn frame_geometry(
    spec: &FrameSpec,
    region_bbox_nm: [i64; 4],
    grid_nm: i64,
    label: &str,
) -> Result<FrameGeometry, MaskError> {
    spec.validate()?;
    if grid_nm <= 0 {
        return Err(MaskError::Invalid(format!(
            "the grid must be positive (got {grid_nm} nm)"
        )));
    }
    let g = grid_nm;
    // Lengths round up to the grid, so a positive margin stays at least one step.
    let len = |um: f64| (((um * 1000.0).ceil() as i64 + g - 1) / g).max(1) * g;
    let [b0, b1, b2, b3] = region_bbox_nm;
    let b = [
        b0.div_euclid(g) * g,
        b1.div_euclid(g) * g,
        -((-b2).div_euclid(g) * g),
        -((-b3).div_euclid(g) * g),
    ];
    let m = len(spec.margin_um);
    let mut out = FrameGeometry {
        extent_nm: region_bbox_nm,
        ..FrameGeometry::default()
    };
    let inner = [b[0] - m, b[1] - m, b[2] + m, b[3] + m];
    let mut outer = inner;
    if spec.frame {
        let w = len(spec.frame_width_um);
        outer = [inner[0] - w, inner[1] - w, inner[2] + w, inner[3] + w];
        let [o0, o1, o2, o3] = outer;
        let [i0, i1, i2, i3] = inner;
        for r in [
            rect(o0, o1, o2, i1),
            rect(o0, i3, o2, o3),
            rect(o0, i1, i0, i3),
            rect(i2, i1, o2, i3),
        ] {
            out.polygons.push((FramePart::Frame, r));
        }
    }
    let mut ext = outer;
    if spec.marks {
        let s = len(spec.mark_size_um);
        let w = len(spec.mark_arm_width_um);
        let a = ((s - w) / 2).div_euclid(g).max(1) * g;
        let s = 2 * a + w;
        let (left, right) = (outer[0] - m - s, outer[2] + m);
        let (low, high) = (outer[1] - m - s, outer[3] + m);
        for (x, y) in [(left, low), (right, low), (right, high), (left, high)] {
            out.polygons.push((FramePart::Marks, cross(x, y, a, w)));
        }
        ext = [left, low, right + s, high + s];
    }
    if spec.label {
        let h = len(spec.label_height_um);
        let at = [outer[0], ext[1] - m - h];
        ext[1] = at[1];
        out.label = Some(FrameLabel {
            text: label.to_string(),
            at_nm: at,
            height_nm: h,
        });
    }
    if spec.any() {
        let limit = i64::from(i32::MAX);
        if ext.iter().any(|v| v.abs() > limit) {
            return Err(MaskError::TooLarge(format!(
                "the frame reaches {} µm from the axis, beyond GDSII's 32-bit coordinates",
                ext.iter().map(|v| v.abs()).max().unwrap_or(0) / 1000
            )));
        }
        out.extent_nm = ext;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn all() -> FrameSpec {
        FrameSpec {
            frame: true,
            marks: true,
            label: true,
            ..FrameSpec::default()
        }
    }

    /// Whether the bounding box of `p` is disjoint from the closed box `b`.
    fn outside(p: &Polygon, b: [i64; 4]) -> bool {
        let xs = p.points_nm.iter().map(|q| q[0]);
        let ys = p.points_nm.iter().map(|q| q[1]);
        let (x0, x1) = (xs.clone().min().unwrap_or(0), xs.max().unwrap_or(0));
        let (y0, y1) = (ys.clone().min().unwrap_or(0), ys.max().unwrap_or(0));
        x1 < b[0] || x0 > b[2] || y1 < b[1] || y0 > b[3]
    }

    #[test]
    fn everything_lies_outside_the_active_area_on_the_grid() {
        for (bbox, grid) in [
            ([-32_000, -32_000, 32_000, 32_000], 1),
            ([-96_017, -64_003, 96_011, 64_005], 5),
            ([0, 0, 1, 1], 1000),
        ] {
            let f = frame_geometry(&all(), bbox, grid, "L").unwrap();
            assert_eq!(f.polygons.len(), 8);
            for (part, p) in &f.polygons {
                assert!(outside(p, bbox), "{part:?} {p:?} touches {bbox:?}");
                assert!(p.points_nm.iter().flatten().all(|v| v % grid == 0), "{p:?}");
            }
            let l = f.label.unwrap();
            assert!(l.at_nm[1] + l.height_nm < bbox[1], "{l:?}");
            assert!(l.at_nm.iter().all(|v| v % grid == 0));
        }
    }

    #[test]
    fn frame_and_marks_have_their_documented_sizes() {
        let bbox = [-32_000, -32_000, 32_000, 32_000];
        let f = frame_geometry(&all(), bbox, 1, "L").unwrap();
        let area = |part| {
            f.polygons
                .iter()
                .filter(|(p, _)| *p == part)
                .map(|(_, q)| q.area_um2())
                .sum::<f64>()
        };
        // 64 µm region + 2 × 50 µm margin = 164 µm inside, 184 µm outside.
        assert!((area(FramePart::Frame) - (184.0f64.powi(2) - 164.0f64.powi(2))).abs() < 1e-9);
        // Four crosses of 2 × 100 × 10 − 10².
        assert!((area(FramePart::Marks) - 4.0 * 1900.0).abs() < 1e-9);
        assert_eq!(f.extent_nm[2], 92_000 + 50_000 + 100_000);
    }

    #[test]
    fn nothing_is_drawn_by_default() {
        let bbox = [-5, -5, 5, 5];
        let f = frame_geometry(&FrameSpec::default(), bbox, 1, "L").unwrap();
        assert!(f.polygons.is_empty() && f.label.is_none());
        assert_eq!(f.extent_nm, bbox);
    }

    #[test]
    fn bad_sizes_name_their_field() {
        for (spec, needle) in [
            (
                FrameSpec {
                    margin_um: f64::NAN,
                    ..all()
                },
                "frame margin",
            ),
            (
                FrameSpec {
                    frame_width_um: -1.0,
                    ..all()
                },
                "frame width",
            ),
            (
                FrameSpec {
                    mark_size_um: 1e308,
                    ..all()
                },
                "mark size",
            ),
            (
                FrameSpec {
                    mark_arm_width_um: 100.0,
                    ..all()
                },
                "mark arm width",
            ),
            (
                FrameSpec {
                    label_height_um: 0.0,
                    ..all()
                },
                "label height",
            ),
        ] {
            let e = spec.validate().unwrap_err().to_string();
            assert!(e.contains(needle), "{e}");
            assert!(e.len() < 120, "{e}");
        }
    }

    #[test]
    fn labels_are_ascii() {
        let t = label_text("Déjà vu", "2000-01-01", 5);
        assert!(t.is_ascii(), "{t}");
        assert_eq!(
            t,
            "UDC STUDIO D?j? vu 2000-01-01 SCALE 1 UM = 1000 DBU GRID 5 NM"
        );
    }
}
