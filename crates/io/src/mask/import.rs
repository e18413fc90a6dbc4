//! Reading a GDSII or DXF mask back into a cell grid, so an exported (or foreign) mask can be
//! simulated again.
//!
//! The drawn polygons (references expanded) are sampled at the centre of every cell of a window:
//! a cell is drawn when its centre lies inside a polygon (even-odd rule per polygon, so keyhole
//! bridges cancel out). With the chrome tone the grid is inverted, so the result is always
//! transmittance: 1 = open (clear), 0 = chrome.

use std::path::Path;

use super::{Drawn, MaskFormat, dxf, gds, oasis, tone_of_notes};
use crate::IoError;
use crate::error::MaskImportError;
use udc_core::ValueError;
use udc_core::mask::Tone;

/// The cells to sample: `cols × rows` cells of `cell_um`, the top-left corner at
/// (`left_um`, `top_um`) in the mask frame (y up).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImportWindow {
    /// x of the window's left edge in the mask frame, in µm.
    pub left_um: f64,
    /// y of the window's top edge in the mask frame (y up), in µm.
    pub top_um: f64,
    /// Cells across (along x).
    pub cols: usize,
    /// Cells down (along −y).
    pub rows: usize,
}

/// How to read a mask back.
#[derive(Debug, Clone, PartialEq)]
pub struct ImportOptions {
    /// Side of a square cell, in µm.
    pub cell_um: f64,
    /// GDSII layer and datatype of the drawn polygons (DXF: the layer `L<layer>_…`).
    pub layer: i16,
    /// GDSII datatype of the drawn polygons (DXF: the `D<datatype>` of the layer name).
    pub datatype: i16,
    /// A DXF layer by its name (another tool's, such as `OPEN`), instead of `L<layer>D<datatype>`.
    pub layer_name: Option<String>,
    /// The GDSII cell to read (another tool's file with several top cells), instead of the
    /// one top cell.
    pub cell: Option<String>,
    /// Cells to sample; by default the drawn polygons' bounding box, rounded out to whole cells.
    pub window: Option<ImportWindow>,
    /// The tone; by default the one the file's notes state, else open.
    pub tone: Option<Tone>,
    /// Whether the file is checked against the checksum its export wrote beside it.
    pub checksum: ChecksumCheck,
}

/// Whether an import checks a mask against the checksum its export wrote beside it
/// (`<file>.sha256`, or the `sha256` of `<file>.manifest.json`) when there is one.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ChecksumCheck {
    /// Refuse a file whose SHA-256 is not the one stated (the default).
    #[default]
    Verify,
    /// Read the file whatever its sidecar says (`--ignore-checksum`).
    Ignore,
}

impl Default for ImportOptions {
    fn default() -> Self {
        ImportOptions {
            cell_um: 1.0,
            layer: 1,
            datatype: 0,
            layer_name: None,
            cell: None,
            window: None,
            tone: None,
            checksum: ChecksumCheck::Verify,
        }
    }
}

/// A mask read back: transmittance per cell (1 open, 0 chrome), row 0 at the top.
#[derive(Debug, Clone, PartialEq)]
pub struct ImportedMask {
    /// Transmittance per cell, `[row][col]`: 1 open, 0 chrome.
    pub cells: Vec<Vec<f64>>,
    /// The cells sampled (given, or the polygons' bounding box).
    pub window: ImportWindow,
    /// The tone the polygons were read with (given, from the notes, or open).
    pub tone: Tone,
    /// Polygons read from the layer, references expanded.
    pub polygons: usize,
}

/// Largest grid an import produces (cells).
pub const MAX_IMPORT_CELLS: usize = 64 << 20;

/// Most cell and edge visits the sampling of one import makes: every cell of the largest grid
/// drawn 16 times over.
const MAX_SAMPLING_WORK: usize = 16 * MAX_IMPORT_CELLS;

/// Reads the mask at `path` (GDSII or DXF, by extension) into cells.
///
/// # Errors
/// [`IoError::File`] when unreadable; [`IoError::Mask`] or [`IoError::Oasis`] when it is not a
/// mask this reader understands; [`IoError::MaskImport`] when the extension names no mask
/// format, the cell size is not positive, nothing is on the layer, or the window is empty or
/// too large.
pub fn import_mask(path: &Path, options: &ImportOptions) -> Result<ImportedMask, IoError> {
    let err = |error: MaskImportError| IoError::MaskImport {
        path: path.to_path_buf(),
        error,
    };
    vector_format(path)?;
    let s = options.cell_um;
    if !(s.is_finite() && s > 0.0) {
        return Err(err(MaskImportError::CellSize { cell_um: s }));
    }
    if options.checksum == ChecksumCheck::Verify {
        super::integrity::verify_checksum(path)?;
    }
    let (polygons, texts) = read_drawn(
        path,
        options.layer,
        options.datatype,
        options.layer_name.as_deref(),
        options.cell.as_deref(),
    )?;
    if polygons.is_empty() {
        return Err(err(MaskImportError::NoPolygon {
            layer: options.layer,
            datatype: options.datatype,
        }));
    }
    let tone = options
        .tone
        .or_else(|| tone_of_notes(texts.iter().map(String::as_str)))
        .unwrap_or(Tone::Open);
    let window = match options.window {
        Some(w) => w,
        None => bounding_window(&polygons, s),
    };
    // A vertex far out or at ±∞ (DXF reads `inf`) sizes the bounding window at up to
    // usize::MAX cells a side: the product must not overflow.
    let cells = window.cols.checked_mul(window.rows);
    if window.cols == 0 || window.rows == 0 || cells.is_none_or(|n| n > MAX_IMPORT_CELLS) {
        return Err(err(MaskImportError::Window {
            cols: window.cols,
            rows: window.rows,
            max_cells: MAX_IMPORT_CELLS,
        }));
    }
    // Sampling visits, for each polygon, its rows times its edges and the cells across it:
    // a few hundred polygons piled on one wide window would take hours.
    let work = polygons
        .iter()
        .map(|poly| sampling_work(poly, &window, s))
        .fold(0usize, usize::saturating_add);
    if work > MAX_SAMPLING_WORK {
        return Err(IoError::Mask {
            path: path.to_path_buf(),
            message: format!(
                "the {} polygons overlap too much to sample on {}×{} cells (more than \
                 {MAX_SAMPLING_WORK} cell and edge visits); import a smaller window",
                polygons.len(),
                window.cols,
                window.rows
            ),
        });
    }
    let mut drawn = vec![vec![false; window.cols]; window.rows];
    for poly in &polygons {
        sample_polygon(poly, &window, s, &mut drawn);
    }
    let cells = drawn
        .into_iter()
        .map(|row| {
            row.into_iter()
                .map(|d| f64::from(u8::from(d != (tone == Tone::Chrome))))
                .collect()
        })
        .collect();
    Ok(ImportedMask {
        cells,
        window,
        tone,
        polygons: polygons.len(),
    })
}

/// The bounding box `[x0, y0, x1, y1]` (µm, y up) of what is drawn on `layer`/`datatype`,
/// references expanded; `None` when nothing is.
///
/// # Errors
/// As [`import_mask`] when the file cannot be read.
pub fn drawn_bounds_um(
    path: &Path,
    layer: i16,
    datatype: i16,
    layer_name: Option<&str>,
    cell: Option<&str>,
) -> Result<Option<[f64; 4]>, IoError> {
    let (polygons, _) = read_drawn(path, layer, datatype, layer_name, cell)?;
    let mut b = [
        f64::INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NEG_INFINITY,
    ];
    for p in polygons
        .iter()
        .flatten()
        .filter(|p| p[0].is_finite() && p[1].is_finite())
    {
        b = [
            b[0].min(p[0]),
            b[1].min(p[1]),
            b[2].max(p[0]),
            b[3].max(p[1]),
        ];
    }
    Ok(b[0].is_finite().then_some(b))
}

/// The window of one pixel (`period_um` a side, `n × n` cells) that a mask from another tool
/// is read at: the pixel at the middle of its drawn layout `bounds` (`[x0, y0, x1, y1]`, µm),
/// on the grid of `period_um` from the layout's top-left corner, so that it lies inside the
/// array wherever the array is placed. The second value says, in one line, when the window
/// is not wholly inside the layout (a layout smaller than a pixel, or a grid whose corner is
/// not the layout's).
pub fn foreign_window(
    bounds: [f64; 4],
    period_um: f64,
    n: usize,
) -> (ImportWindow, Option<String>) {
    let [x0, y0, x1, y1] = bounds;
    let (w, h) = (x1 - x0, y1 - y0);
    let steps = |span: f64| ((span / 2.0) / period_um).floor().max(0.0);
    let left_um = if w >= period_um {
        x0 + steps(w) * period_um
    } else {
        (x0 + x1 - period_um) / 2.0
    };
    let top_um = if h >= period_um {
        y1 - steps(h) * period_um
    } else {
        (y0 + y1 + period_um) / 2.0
    };
    let window = ImportWindow {
        left_um,
        top_um,
        cols: n,
        rows: n,
    };
    // A hundredth of a cell of slack: coordinates on a database grid round.
    let slack = period_um / n.max(1) as f64 / 100.0;
    let inside = left_um >= x0 - slack
        && left_um + period_um <= x1 + slack
        && top_um <= y1 + slack
        && top_um - period_um >= y0 - slack;
    let warning = (!inside).then(|| {
        format!(
            "the {period_um} µm pixel read at ({left_um:.3}, {top_um:.3}) µm is not wholly inside the drawn layout ({x0:.3} … {x1:.3}, {y0:.3} … {y1:.3}) µm: check --pitch-um, or that the file holds an array of pixels"
        )
    });
    (window, warning)
}

/// The vector format (GDSII, OASIS or DXF) `path`'s extension names.
///
/// # Errors
/// [`MaskImportError::UnknownExtension`] for any other.
pub(super) fn vector_format(path: &Path) -> Result<MaskFormat, IoError> {
    match MaskFormat::of_path(path) {
        Some(f @ (MaskFormat::Gds | MaskFormat::Oas | MaskFormat::Dxf)) => Ok(f),
        _ => Err(IoError::MaskImport {
            path: path.to_path_buf(),
            error: MaskImportError::UnknownExtension {
                extension: path
                    .extension()
                    .map(|e| e.to_string_lossy().to_lowercase())
                    .unwrap_or_default(),
            },
        }),
    }
}

/// The polygons on `layer`/`datatype` (µm, references expanded) and every text of a GDSII,
/// OASIS or DXF file.
///
/// # Errors
/// As [`vector_format`], and the readers' errors.
pub(super) fn read_drawn(
    path: &Path,
    layer: i16,
    datatype: i16,
    layer_name: Option<&str>,
    cell: Option<&str>,
) -> Result<Drawn, IoError> {
    let format = vector_format(path)?;
    if let Some(name) = cell.filter(|_| format != MaskFormat::Gds) {
        return Err(IoError::Mask {
            path: path.to_path_buf(),
            message: format!("cell `{name}`: only a GDSII file's cells are chosen by name"),
        });
    }
    if let Some(name) = layer_name.filter(|_| format != MaskFormat::Dxf) {
        return Err(IoError::Mask {
            path: path.to_path_buf(),
            message: format!(
                "layer `{name}`: GDSII and OASIS layers are numbers, L/D (for example 1/0)"
            ),
        });
    }
    Ok(match format {
        MaskFormat::Dxf => dxf::read(path, layer, datatype, layer_name)?,
        MaskFormat::Oas => {
            let flat = oasis::read(path, layer, datatype)?;
            (flat.polygons_um, flat.texts)
        }
        _ => {
            let flat = gds::read(path, layer, datatype, cell)?;
            (flat.polygons_um, flat.texts)
        }
    })
}

/// The polygons' bounding box rounded out to whole cells from its top-left corner.
fn bounding_window(polygons: &[Vec<[f64; 2]>], cell_um: f64) -> ImportWindow {
    let mut b = [
        f64::INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NEG_INFINITY,
    ];
    for p in polygons.iter().flatten() {
        b = [
            b[0].min(p[0]),
            b[1].min(p[1]),
            b[2].max(p[0]),
            b[3].max(p[1]),
        ];
    }
    // A hair of slack so that a box of exactly k cells does not round up to k + 1.
    let count = |span: f64| ((span / cell_um) - 1e-6).ceil().max(1.0) as usize;
    ImportWindow {
        left_um: b[0],
        top_um: b[3],
        cols: count(b[2] - b[0]),
        rows: count(b[3] - b[1]),
    }
}

/// The rows whose centre y = top − (r + ½)s lies within the polygon's span, `r0..r1`.
fn row_range(poly: &[[f64; 2]], w: &ImportWindow, s: f64) -> (usize, usize) {
    let (mut y_lo, mut y_hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for p in poly {
        y_lo = y_lo.min(p[1]);
        y_hi = y_hi.max(p[1]);
    }
    let r0 = ((w.top_um - y_hi) / s - 0.5).floor().max(0.0) as usize;
    let r1 = (((w.top_um - y_lo) / s - 0.5).ceil().max(0.0) as usize).min(w.rows);
    (r0, r1)
}

/// What [`sample_polygon`] visits for `poly`: its rows, times its edges and the cells across
/// its x-span.
fn sampling_work(poly: &[[f64; 2]], w: &ImportWindow, s: f64) -> usize {
    if poly.len() < 3 {
        return 0;
    }
    let (r0, r1) = row_range(poly, w, s);
    let (mut x_lo, mut x_hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for p in poly {
        x_lo = x_lo.min(p[0]);
        x_hi = x_hi.max(p[0]);
    }
    let c0 = ((x_lo - w.left_um) / s - 0.5).ceil().max(0.0) as usize;
    let c1 = (((x_hi - w.left_um) / s - 0.5).ceil().max(0.0) as usize).min(w.cols);
    r1.saturating_sub(r0)
        .saturating_mul(poly.len().saturating_add(c1.saturating_sub(c0)))
}

/// Marks the cells whose centres lie inside `poly` (even-odd rule).
fn sample_polygon(poly: &[[f64; 2]], w: &ImportWindow, s: f64, drawn: &mut [Vec<bool>]) {
    let n = poly.len();
    if n < 3 {
        return;
    }
    let (r0, r1) = row_range(poly, w, s);
    let mut xs = Vec::new();
    for (r, row) in drawn.iter_mut().enumerate().take(r1).skip(r0) {
        let y = w.top_um - (r as f64 + 0.5) * s;
        xs.clear();
        for i in 0..n {
            let [x0, y0] = poly[i];
            let [x1, y1] = poly[(i + 1) % n];
            if (y0 <= y) != (y1 <= y) {
                xs.push(x0 + (y - y0) * (x1 - x0) / (y1 - y0));
            }
        }
        xs.sort_by(f64::total_cmp);
        for pair in xs.chunks_exact(2) {
            // Cells whose centre x = left + (c + ½)s lies in [pair[0], pair[1]).
            let c0 = ((pair[0] - w.left_um) / s - 0.5).ceil().max(0.0) as usize;
            let c1 = (((pair[1] - w.left_um) / s - 0.5).ceil().max(0.0) as usize).min(w.cols);
            for cell in row.iter_mut().take(c1).skip(c0) {
                *cell = true;
            }
        }
    }
}

/// Reads the pixel that holds the optical axis of a GDSII or DXF mask back into `design`'s cell
/// grid (its cell size and tile registration), undoing that pixel's orientation when the design
/// tiles randomly, so an exported mask can be simulated again as the design's opening. The
/// mask's tone is read from its notes; layer 1, datatype 0 (the export defaults).
///
/// # Errors
/// As [`import_mask`], and [`IoError::MaskLayout`] when the design cannot be laid out.
pub fn import_opening(path: &Path, design: &udc_core::Design) -> Result<Vec<Vec<f64>>, IoError> {
    import_opening_on(path, design, 1, 0, ChecksumCheck::Verify)
}

/// As [`import_opening`], reading the polygons of GDSII `layer`/`datatype` (DXF: the layer
/// `L<layer>D<datatype>…`), or a PNG mask written by the export (`.png`: its `REGION=` and
/// `GRID_NM=` notes place the region, `pHYs` gives the pixel size; a cell is open when the
/// image pixel under its centre is at least half drawn, so the cells come back exactly when the
/// image pixel is at most half a cell).
///
/// # Errors
/// As [`import_mask`]; for a PNG, [`IoError::MaskImport`] for a missing pixel size or region, or
/// a region that does not fit the image.
pub fn import_opening_on(
    path: &Path,
    design: &udc_core::Design,
    layer: i16,
    datatype: i16,
    checksum: ChecksumCheck,
) -> Result<Vec<Vec<f64>>, IoError> {
    use udc_core::display::tiling::{D4, tile_orientation};
    use udc_core::mask::{MaskLayout, MaskRegion, MaskSpec};
    let png = is_png(path);
    let notes = if png {
        Some(super::png_read::read(path)?)
    } else {
        None
    };
    let err = |error: MaskImportError| IoError::MaskImport {
        path: path.to_path_buf(),
        error,
    };
    let mut spec = MaskSpec {
        region: MaskRegion::PIXEL,
        // The registration only: no border to work out.
        border: udc_core::mask::BorderPolicy::Cut,
        ..MaskSpec::default()
    };
    if let Some(m) = &notes {
        let lines = m.notes.iter().map(String::as_str);
        spec.region = note_field(lines.clone(), "REGION")
            .ok_or_else(|| err(MaskImportError::NoRegionNote))?
            .parse()
            .map_err(|e: ValueError| err(MaskImportError::Region(e)))?;
        if let Some(g) = note_field(lines, "GRID_NM").and_then(|g| g.parse().ok()) {
            spec.grid_nm = g;
        }
    }
    // Only the registration matters here, not the cells (which may all be closed right now).
    let n = design.opening.n();
    let mut frame = design.clone();
    frame.opening.cells = vec![vec![1.0; n]; n];
    frame.opening.polygons.clear();
    // Emitters would sit on the all-open frame's cells; they play no part in the registration.
    frame.subpixels = None;
    let layout = MaskLayout::new(&frame, &spec)?;
    let [x_nm, y_nm] = layout.tile_corner_nm(0, 0);
    let cells = match notes {
        Some(m) => png_axis_pixel(&m, &layout).map_err(err)?,
        None => {
            import_mask(
                path,
                &ImportOptions {
                    cell_um: design.opening.cell_um(),
                    layer,
                    datatype,
                    window: Some(ImportWindow {
                        left_um: x_nm as f64 * 1e-3,
                        top_um: y_nm as f64 * 1e-3,
                        cols: n,
                        rows: n,
                    }),
                    checksum,
                    ..ImportOptions::default()
                },
            )?
            .cells
        }
    };
    // The axis pixel shows g·P; find h with h·(g·P) = P for every pattern (h = g⁻¹).
    let g = tile_orientation(design.tiling.mode, design.tiling.seed, 0, 0);
    let probe: Vec<Vec<usize>> = (0..3)
        .map(|r| (0..3).map(|c| 3 * r + c).collect())
        .collect();
    let inverse = D4::all()
        .into_iter()
        .find(|h| h.apply(&g.apply(&probe)) == probe)
        .unwrap_or(D4::IDENTITY);
    Ok(inverse.apply(&cells))
}

fn is_png(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.to_string_lossy().eq_ignore_ascii_case("png"))
}

/// The axis pixel's cells of a PNG mask: each cell's centre looked up in the image.
fn png_axis_pixel(
    m: &super::png_read::PngMask,
    layout: &udc_core::mask::MaskLayout,
) -> Result<Vec<Vec<f64>>, MaskImportError> {
    let d_nm = m.um_per_px.ok_or(MaskImportError::NoPixelSize)? * 1e3;
    let tone = tone_of_notes(m.notes.iter().map(String::as_str)).unwrap_or(Tone::Open);
    let corner = note_field(m.notes.iter().map(String::as_str), "IMAGE_TOP_LEFT_NM")
        .and_then(|v| v.split_once(','))
        .and_then(|(x, y)| Some([x.parse::<i64>().ok()?, y.parse::<i64>().ok()?]));
    // Files from before the note: the image starts at the region's corner.
    let bbox = match corner {
        Some([x, y]) => [x, 0, 0, y],
        None => super::region_bbox_nm(layout),
    };
    let [cx, cy] = layout.tile_corner_nm(0, 0);
    let b = &layout.bounds_nm;
    let mut cells = vec![vec![0.0; layout.n]; layout.n];
    for (r, row) in cells.iter_mut().enumerate() {
        for (c, cell) in row.iter_mut().enumerate() {
            // Cell centre in the mask frame (nm), then in image pixels (y down).
            let x = cx as f64 + (b[c] + b[c + 1]) as f64 / 2.0;
            let y = cy as f64 - (b[r] + b[r + 1]) as f64 / 2.0;
            let px = ((x - bbox[0] as f64) / d_nm).floor();
            let py = ((bbox[3] as f64 - y) / d_nm).floor();
            if !(px >= 0.0 && py >= 0.0 && (px as usize) < m.width && (py as usize) < m.height) {
                return Err(MaskImportError::AxisPixelOutside {
                    width: m.width,
                    height: m.height,
                    // From `d_nm`, not `m.um_per_px`: the message shows the size as used.
                    um_per_px: d_nm / 1e3,
                });
            }
            let drawn = m.grey[py as usize * m.width + px as usize] >= 128;
            *cell = f64::from(u8::from(drawn != (tone == Tone::Chrome)));
        }
    }
    Ok(cells)
}

/// The value of `KEY=VALUE` in the notes (values end at a space), e.g. `CELLS` → `"21"`.
pub fn note_field<'a>(notes: impl IntoIterator<Item = &'a str>, key: &str) -> Option<&'a str> {
    notes.into_iter().find_map(|line| {
        line.split([' ', ':'])
            .find_map(|token| token.strip_prefix(key)?.strip_prefix('='))
    })
}

/// The text notes of a mask (GDSII and DXF TEXTs, PNG `Description` lines), as the export
/// writes them: `TONE=…`, `PITCH_NM=… PERIOD_NM=… CELLS=… REGION=… TILING=… SEED=…`.
///
/// # Errors
/// As [`import_mask`] when the file cannot be read.
pub fn mask_notes(
    path: &Path,
    layer: i16,
    datatype: i16,
    cell: Option<&str>,
) -> Result<Vec<String>, IoError> {
    if is_png(path) {
        return Ok(super::png_read::read(path)?.notes);
    }
    match path
        .extension()
        .map(|e| e.to_string_lossy().to_lowercase())
        .as_deref()
    {
        Some("dxf") => Ok(dxf::read(path, layer, datatype, None)?.1),
        Some("oas" | "oasis") => Ok(oasis::read(path, layer, datatype)?.texts),
        _ => Ok(gds::read(path, layer, datatype, cell)?.texts),
    }
}
