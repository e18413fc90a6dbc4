//! The plate as GDSII, one layer per height level.

use super::*;

use super::pieces::{level_height_um, level_runs, pieces};

/// Writes a multi-level GDSII: layer k holds the rectangles where the height is k·step (k ≥ 1;
/// height 0 is bare substrate and is not drawn), each spanning `length_um` along y. Mask writers
/// and grayscale processes assign one dose or one etch per layer. Coordinates are whole
/// nanometres (database unit 1 nm, user unit 1 µm); the length is rounded to 2 nm so the plate
/// stays centred. Equal neighbouring levels are one rectangle, also across lenslet edges. The
/// top cell [`GDS_TOP_CELL`] carries ASCII notes (units, layer table, design) on
/// [`GDS_NOTE_LAYER`].
///
/// # Errors
/// A message naming `height_step_um` when the design has no step (GDSII needs discrete levels)
/// or too many levels, naming `length_um` when out of range; [`IoError::Mask`] when encoding
/// fails.
pub fn write_height_gds(
    design: &PhaseDesign,
    path: &Path,
    length_um: f64,
    min_feature_um: f64,
) -> Result<ExportSummary, IoError> {
    write_height_gds_with(design, path, length_um, false, min_feature_um)
}

/// The layer map of a written plate: `level_k k/0` per level layer, then `notes`.
pub(super) fn layer_map(summary: &ExportSummary) -> crate::fab::LayerMap {
    use crate::fab::LayerEntry;
    let mut entries: Vec<LayerEntry> = summary
        .layers
        .iter()
        .map(|l| LayerEntry {
            name: format!("level_{}", l.layer),
            layer: l.layer,
            datatype: 0,
        })
        .collect();
    entries.push(LayerEntry {
        name: "notes".into(),
        layer: GDS_NOTE_LAYER,
        datatype: 0,
    });
    crate::fab::LayerMap { entries }
}

/// [`write_height_gds`], with fixed timestamps (2000-01-01) when `deterministic`.
///
/// # Errors
/// As [`write_height_gds`].
pub fn write_height_gds_with(
    design: &PhaseDesign,
    path: &Path,
    length_um: f64,
    deterministic: bool,
    min_feature_um: f64,
) -> Result<ExportSummary, IoError> {
    let lenslets = lenslets_of(design)?;
    check_length(length_um)?;
    let Some(step) = design.height_step_um else {
        return Err(invalid(
            "GDSII export needs a fabrication step: set height_step_um (e.g. 0.2 µm) so every \
             height is one of a few levels, one layer each"
                .into(),
        ));
    };
    let pieces = pieces(design, &lenslets, min_feature_um)?;
    let runs = level_runs(&pieces);
    let top_level = runs.iter().map(|r| r.2).max().unwrap_or(0);
    if top_level > MAX_GDS_LEVEL {
        return Err(invalid(format!(
            "height_step_um = {step}: {top_level} levels above 0 need more than the \
             {MAX_GDS_LEVEL} level layers (layer {GDS_NOTE_LAYER} holds the notes); use a \
             coarser step"
        )));
    }
    let half_nm = (length_um / DB_UNIT_UM / 2.0).round().max(1.0) as i64;
    let to_i32 = |v: i64| {
        i32::try_from(v)
            .map_err(|_| invalid(format!("coordinate {v} nm is outside GDSII's 32-bit range")))
    };
    let (y0, y1) = (to_i32(-half_nm)?, to_i32(half_nm)?);
    let mut layers: Vec<GdsLayer> = (1..=top_level)
        .map(|k| GdsLayer {
            layer: k as i16,
            height_um: level_height_um(k, step),
            rectangles: 0,
            width_um: 0.0,
        })
        .collect();
    let hash = crate::fab::sha256_hex(crate::phase::design::phase_design_json(design).as_bytes());
    let mut cell = GdsStruct::new(format!("{GDS_TOP_CELL}_{}", hash[..8].to_uppercase()));
    let mut width_nm = vec![0i64; layers.len()];
    for &(x0, x1, level) in &runs {
        if level == 0 {
            continue;
        }
        let (a, b) = (to_i32(x0)?, to_i32(x1)?);
        let k = level as usize - 1;
        layers[k].rectangles += 1;
        width_nm[k] += x1 - x0;
        cell.elems.push(GdsElement::GdsBoundary(GdsBoundary {
            layer: level as i16,
            datatype: 0,
            xy: vec![
                GdsPoint::new(a, y0),
                GdsPoint::new(b, y0),
                GdsPoint::new(b, y1),
                GdsPoint::new(a, y1),
                GdsPoint::new(a, y0),
            ],
            ..Default::default()
        }));
    }
    for (layer, w) in layers.iter_mut().zip(&width_nm) {
        layer.width_um = *w as f64 * DB_UNIT_UM;
    }
    let length_written = 2.0 * half_nm as f64 * DB_UNIT_UM;
    let mut notes = vec![
        format!(
            "UDC STUDIO PHASE PLATE: layer k = height k x {step} um (k = 1..{top_level}); \
             height 0 = bare substrate, not drawn; layer {GDS_NOTE_LAYER} = these notes"
        ),
        format!(
            "units: user unit 1 um, database unit 1 nm; x across lenslets (x = 0 on the axis), \
             plate uniform along y over {length_written} um"
        ),
    ];
    notes.extend(header_lines(design, &lenslets).into_iter().skip(2));
    let x_note = to_i32(-(lenslets.span_um() / 2.0 / DB_UNIT_UM).round() as i64)?;
    for (k, note) in notes.iter().enumerate() {
        // One line per note, 10 µm apart, above the plate's top-left corner.
        let y = half_nm + 10_000 * (notes.len() - k) as i64;
        cell.elems.push(GdsElement::GdsTextElem(GdsTextElem {
            string: note.clone(),
            layer: GDS_NOTE_LAYER,
            texttype: 0,
            xy: GdsPoint::new(x_note, to_i32(y)?),
            ..Default::default()
        }));
    }
    let mut lib = GdsLibrary::new(GDS_LIBRARY);
    // Database unit 1 nm = 1e-3 user units (1 µm), 1e-9 m.
    lib.units = GdsUnits::new(1e-3, 1e-9);
    lib.structs.push(cell);
    lib.set_all_dates(crate::fab::gds_date(deterministic));
    let mut bytes = Vec::new();
    lib.write(&mut bytes).map_err(|e| IoError::Mask {
        path: path.to_path_buf(),
        message: format!("cannot encode the GDSII library: {e}"),
    })?;
    write_atomic(path, &bytes)?;
    let mut summary = ExportSummary::new(
        path,
        HeightFormat::Gds,
        lenslets.span_um(),
        level_height_um(top_level, step),
    );
    summary.levels = Some(top_level as usize + 1);
    summary.um_per_level = Some(step);
    summary.rectangles = Some(layers.iter().map(|l| l.rectangles).sum());
    summary.layers = layers;
    summary.length_um = Some(length_written);
    summary.grid_um = Some(DB_UNIT_UM);
    Ok(summary)
}
