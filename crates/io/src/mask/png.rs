//! PNG: the region's bounding box at a chosen size per pixel. White = drawn, so with the open
//! tone white is clear glass (as in the opening PNGs) and with the chrome tone white is chrome.
//! 8-bit pixels hold the drawn fraction of their area; 1-bit pixels are drawn when at least half
//! is. The physical pixel size is in the `pHYs` chunk, the tone and notes in `tEXt` chunks.

use std::io::BufWriter;
use std::path::Path;

use png::{BitDepth, ColorType, Encoder, PixelDimensions, Unit};

use super::{ExportOptions, FileCounts, PngBits, region_bbox_nm};
use crate::IoError;
use udc_core::Progress;
use udc_core::display::tiling::D4;
use udc_core::mask::{MaskError, MaskLayout};

/// Largest image written (pixels); coverage is accumulated in 16 bits per pixel.
pub const MAX_PNG_PIXELS: u64 = 100_000_000;

/// Drawn rectangles `[x0, y0, x1, y1]` (nm, corner frame) of a tile in orientation `g`: the
/// runs of drawn cells in each row, plus the wiring gap.
fn tile_rects(layout: &MaskLayout, g: D4) -> Vec<[i64; 4]> {
    let grid = layout.drawn_grid(g);
    let b = &layout.bounds_nm;
    let mut rects = Vec::new();
    for r in 0..layout.n {
        let mut c = 0;
        while c < layout.n {
            if !grid.get(c, r) {
                c += 1;
                continue;
            }
            let start = c;
            while c < layout.n && grid.get(c, r) {
                c += 1;
            }
            rects.push([b[start], -b[r + 1], b[c], -b[r]]);
        }
    }
    if layout.gap_polygon.is_some() {
        let (p, q) = (layout.pitch_nm, layout.period_nm);
        rects.push([p, -q, q, 0]);
        rects.push([0, -q, p, -p]);
    }
    rects
}

/// Image size for the region at `um_per_px`.
fn size(layout: &MaskLayout, um_per_px: f64) -> (u64, u64, [i64; 4]) {
    let bbox = region_bbox_nm(layout);
    let d = um_per_px * 1e3;
    let w = ((bbox[2] - bbox[0]) as f64 / d).ceil().max(1.0) as u64;
    let h = ((bbox[3] - bbox[1]) as f64 / d).ceil().max(1.0) as u64;
    (w, h, bbox)
}

/// Adds the coverage of one rectangle (pixel units, y down) to the image.
fn add_rect(cov: &mut [u16], width: usize, height: usize, r: [f64; 4]) {
    let [fx0, fy0, fx1, fy1] = r;
    let (ix0, ix1) = (
        fx0.floor().max(0.0) as usize,
        (fx1.ceil() as usize).min(width),
    );
    let (iy0, iy1) = (
        fy0.floor().max(0.0) as usize,
        (fy1.ceil() as usize).min(height),
    );
    for iy in iy0..iy1 {
        let wy = fy1.min(iy as f64 + 1.0) - fy0.max(iy as f64);
        if wy <= 0.0 {
            continue;
        }
        let row = &mut cov[iy * width..(iy + 1) * width];
        for (ix, v) in row.iter_mut().enumerate().take(ix1).skip(ix0) {
            let wx = fx1.min(ix as f64 + 1.0) - fx0.max(ix as f64);
            if wx > 0.0 {
                let add = (wx * wy * 65535.0).round() as u16;
                *v = v.saturating_add(add);
            }
        }
    }
}

/// Writes the PNG file.
pub(super) fn write(
    layout: &MaskLayout,
    o: &ExportOptions,
    notes: &[String],
    path: &Path,
    progress: &Progress,
) -> Result<FileCounts, IoError> {
    let (w, h, bbox) = size(layout, o.um_per_px);
    if w * h > MAX_PNG_PIXELS {
        return Err(MaskError::TooLarge(format!(
            "{w}×{h} pixels at {} µm per pixel is more than {MAX_PNG_PIXELS}; \
             use coarser pixels or a smaller region",
            o.um_per_px
        ))
        .into());
    }
    let cov = coverage(
        layout,
        o.um_per_px,
        (w as usize, h as usize),
        bbox,
        progress,
    )?;
    let data = pixels(&cov, w as usize, o.png_bits);
    // Where the image sits: a border drawn past the region moves its corner off the region's.
    let mut notes = notes.to_vec();
    notes.push(format!("IMAGE_TOP_LEFT_NM={},{}", bbox[0], bbox[3]));
    encode(path, (w as u32, h as u32), o, &notes, &data)?;
    let bytes = std::fs::metadata(path).map(|m| m.len()).unwrap_or(0);
    let s = layout.stats();
    Ok(FileCounts {
        polygons: s.flat_polygons,
        vertices: s.flat_vertices,
        references: 0,
        arrays: 0,
        bytes,
    })
}

/// Drawn fraction of every pixel, in 1/65535 (row 0 at the top).
fn coverage(
    layout: &MaskLayout,
    um_per_px: f64,
    (width, height): (usize, usize),
    bbox: [i64; 4],
    progress: &Progress,
) -> Result<Vec<u16>, IoError> {
    let d = um_per_px * 1e3;
    let mut cov = vec![0u16; width * height];
    let mut cache: Vec<(D4, Vec<[i64; 4]>)> = Vec::new();
    let rows = layout.rows.len().max(1);
    for (k, r) in layout.rows.iter().enumerate() {
        progress.check().map_err(|_| MaskError::Cancelled)?;
        progress.set(0.9 * k as f32 / rows as f32);
        for tx in r.tx0..r.tx0 + i64::from(r.count) {
            let g = layout.orientation(tx, r.ty);
            let idx = match cache.iter().position(|(h, _)| *h == g) {
                Some(i) => i,
                None => {
                    cache.push((g, tile_rects(layout, g)));
                    cache.len() - 1
                }
            };
            let [cx, cy] = layout.tile_corner_nm(tx, r.ty);
            for rect in &cache[idx].1 {
                let px = [
                    (cx + rect[0] - bbox[0]) as f64 / d,
                    (bbox[3] - (cy + rect[3])) as f64 / d,
                    (cx + rect[2] - bbox[0]) as f64 / d,
                    (bbox[3] - (cy + rect[1])) as f64 / d,
                ];
                add_rect(&mut cov, width, height, px);
            }
        }
    }
    // What the border policy redrew, as the non-overlapping rectangles of its union.
    let border = layout.border.polygons().map(|p| p.points_nm.as_slice());
    for rect in udc_core::mask::geometry_drc::union_rectangles(border) {
        let px = [
            (rect[0] - bbox[0]) as f64 / d,
            (bbox[3] - rect[3]) as f64 / d,
            (rect[2] - bbox[0]) as f64 / d,
            (bbox[3] - rect[1]) as f64 / d,
        ];
        add_rect(&mut cov, width, height, px);
    }
    Ok(cov)
}

/// The image rows as PNG pixel bytes (1-bit rows are packed, most significant bit first).
fn pixels(cov: &[u16], width: usize, bits: PngBits) -> Vec<u8> {
    match bits {
        PngBits::Eight => cov
            .iter()
            .map(|v| ((f64::from(*v) / 65535.0) * 255.0).round() as u8)
            .collect(),
        PngBits::One => cov
            .chunks(width)
            .flat_map(|row| {
                row.chunks(8).map(|px| {
                    px.iter()
                        .enumerate()
                        .fold(0u8, |acc, (i, v)| acc | (u8::from(*v >= 32768) << (7 - i)))
                })
            })
            .collect(),
    }
}

fn encode(
    path: &Path,
    (w, h): (u32, u32),
    o: &ExportOptions,
    notes: &[String],
    data: &[u8],
) -> Result<(), IoError> {
    let encode_err = |e: png::EncodingError| IoError::Mask {
        path: path.to_path_buf(),
        message: format!("cannot encode the PNG: {e}"),
    };
    let file =
        crate::safe_file::open_reserved(path).map_err(|e| IoError::file("create", path, e))?;
    let mut enc = Encoder::new(BufWriter::new(file), w, h);
    enc.set_color(ColorType::Grayscale);
    enc.set_depth(match o.png_bits {
        PngBits::One => BitDepth::One,
        PngBits::Eight => BitDepth::Eight,
    });
    let ppm = (1e6 / o.um_per_px).round().clamp(1.0, f64::from(u32::MAX)) as u32;
    enc.set_pixel_dims(Some(PixelDimensions {
        xppu: ppm,
        yppu: ppm,
        unit: Unit::Meter,
    }));
    enc.add_text_chunk("Tone".into(), notes.get(1).cloned().unwrap_or_default())
        .map_err(encode_err)?;
    enc.add_text_chunk("Description".into(), notes.join("\n"))
        .map_err(encode_err)?;
    let mut writer = enc.write_header().map_err(encode_err)?;
    writer.write_image_data(data).map_err(encode_err)?;
    writer.finish().map_err(encode_err)
}

/// What [`write`] would produce (the size is the uncompressed bound).
pub(super) fn estimate(layout: &MaskLayout, o: &ExportOptions) -> FileCounts {
    let (w, h, _) = size(layout, o.um_per_px);
    let bits = match o.png_bits {
        PngBits::One => 1,
        PngBits::Eight => 8,
    };
    let s = layout.stats();
    FileCounts {
        polygons: s.flat_polygons,
        vertices: s.flat_vertices,
        references: 0,
        arrays: 0,
        bytes: 200 + h * (1 + (w * bits).div_ceil(8)),
    }
}
