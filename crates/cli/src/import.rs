//! `udc-studio import`: a mask (GDSII, OASIS, DXF or PNG) read back into a design file.

use std::path::{Path, PathBuf};

use anyhow::{Result, anyhow, bail};
use clap::Args;

use udc_core::ValueError;
use udc_core::design::{Design, MAX_CELLS, TilingMode};
use udc_io::design::file::{load_design, save_design};
use udc_io::mask::{ChecksumCheck, import_opening_on, mask_notes, note_field, sidecar_path};

/// Arguments of `udc-studio import`.
#[derive(Debug, Args)]
pub struct ImportArgs {
    /// The mask: `.gds`, `.oas`, `.dxf` or `.png` (as `udc-studio export` writes them).
    pub mask: PathBuf,
    /// GDSII layer/datatype of the drawn polygons, e.g. `1/0` (DXF: the layer `L1D0…`); or, for
    /// a DXF drawn by another tool, its layer's name (`OPEN`).
    #[arg(long, default_value = "1/0", value_parser = parse_layer)]
    pub layer: LayerArg,
    /// The GDSII cell to read, by name: the pixel array of a file with several top cells (or
    /// any cell of it); by default its one top cell.
    #[arg(long, value_name = "NAME")]
    pub cell: Option<String>,
    /// Pixel pitch in µm; by default the mask's `PITCH_NM=` note (or its sidecar design).
    #[arg(long)]
    pub pitch_um: Option<f64>,
    /// Cells across a pixel; by default the mask's `CELLS=` note (or its sidecar design).
    #[arg(long)]
    pub cells: Option<usize>,
    /// The design file to write.
    #[arg(long)]
    pub out: PathBuf,
    /// Read the mask even when it does not match the checksum its export wrote beside it
    /// (`<mask>.sha256` or `<mask>.manifest.json`): by default such a file is refused.
    #[arg(long)]
    pub ignore_checksum: bool,
}

/// The drawn layer: numbers, or a DXF layer's name.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum LayerArg {
    /// A GDSII layer and datatype (DXF: the layer `L<layer>D<datatype>`).
    Numbers(i16, i16),
    /// A DXF layer by its name.
    Name(String),
}

/// `L/D` as a GDSII layer and datatype, each 0–255; a word without `/` as a DXF layer's name.
fn parse_layer(s: &str) -> Result<LayerArg, ValueError> {
    let t = s.trim();
    if !t.contains('/') && !t.is_empty() && !t.starts_with(|c: char| c.is_ascii_digit()) {
        return Ok(LayerArg::Name(t.to_owned()));
    }
    parse_numbers(s).map(|(l, d)| LayerArg::Numbers(l, d))
}

/// `L/D` as a GDSII layer and datatype, each 0–255.
fn parse_numbers(s: &str) -> Result<(i16, i16), ValueError> {
    let bad = || ValueError::Malformed {
        value: s.to_string(),
        expected: "a layer L/D, e.g. 1/0, each 0–255 (or a DXF layer's name)",
    };
    let (l, d) = s.split_once('/').ok_or_else(bad)?;
    let l: i16 = l.trim().parse().map_err(|_| bad())?;
    let d: i16 = d.trim().parse().map_err(|_| bad())?;
    if !(0..=255).contains(&l) || !(0..=255).contains(&d) {
        return Err(bad());
    }
    Ok((l, d))
}

/// Runs `udc-studio import`: the mask's pixel on the optical axis becomes the opening of a
/// design (the sidecar `<MASK>.design.json` when there is one, else the default design with
/// the pitch, cells, wiring gap and tiling the mask's notes state), written to `--out`.
///
/// # Errors
/// An unknown extension, an unreadable mask, a pitch or cell count neither stated nor given,
/// an invalid design, an unwritable output.
pub fn import_cmd(args: &ImportArgs) -> Result<()> {
    let path = &args.mask;
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_lowercase())
        .unwrap_or_default();
    if !matches!(
        ext.as_str(),
        "gds" | "gdsii" | "gds2" | "oas" | "oasis" | "dxf" | "png"
    ) {
        let what = if ext.is_empty() {
            "a file without an extension".to_string()
        } else {
            format!("`.{ext}` masks")
        };
        bail!(
            "{}: cannot import {what} (expected .gds, .oas, .dxf or .png)",
            path.display()
        );
    }
    udc_io::safe_file::check_not_an_input(&args.out, &[path.as_path()])?;
    let (layer, datatype, layer_name) = match &args.layer {
        LayerArg::Numbers(l, d) => (*l, *d, None),
        LayerArg::Name(n) => {
            if ext != "dxf" {
                bail!(
                    "--layer {n}: {} layers are numbers L/D (for example 1/0); a name picks a \
                     DXF layer",
                    if ext == "png" {
                        "PNG masks have no"
                    } else {
                        "GDSII and OASIS"
                    }
                );
            }
            (1, 0, Some(n.as_str()))
        }
    };
    let cell = args.cell.as_deref();
    if let Some(name) = cell
        && !is_gds(path)
    {
        bail!("--cell {name}: only GDSII files' cells are chosen by name");
    }
    // First: the notes below are read from the file, and a damaged one could misstate them.
    if !args.ignore_checksum && ext != "png" {
        udc_io::mask::verify_checksum(path)?;
    }
    let design = template(path, layer, datatype, args)?;
    // A mask another tool drew states none of our notes: where its pixels are is read from
    // the drawing itself (the pixel at the layout's middle, on its own grid), not from our
    // export's registration.
    let foreign = layer_name.is_some()
        || cell.is_some()
        || (ext != "png"
            && !sidecar_path(path).is_file()
            && note_field(
                mask_notes(path, layer, datatype, cell)?
                    .iter()
                    .map(String::as_str),
                "PITCH_NM",
            )
            .is_none());
    let cells = if foreign {
        foreign_pixel(path, &design, layer, datatype, layer_name, cell)?
    } else {
        // Checked above (or waived): the import need not hash the file a second time.
        import_opening_on(path, &design, layer, datatype, ChecksumCheck::Ignore)?
    };
    let mut design = design;
    design.opening.cells = cells;
    design.reconcile_subpixels();
    design
        .validate()
        .map_err(|e| anyhow!("{}: {e}", path.display()))?;
    save_design(&args.out, &design)?;
    let n = design.opening.n();
    let open = design.opening.cells.iter().flatten().sum::<f64>() / (n * n) as f64;
    println!(
        "imported {n}×{n} cells of {:.4} µm (pitch {} µm, open fraction {open:.6}) from {} into {}",
        design.opening.cell_um(),
        design.opening.pitch_um,
        path.display(),
        args.out.display()
    );
    Ok(())
}

/// The cells of the pixel at the middle of a foreign mask's drawn layout, with a line saying
/// where it was read (and a warning when it is not wholly inside the layout).
///
/// # Errors
/// Nothing drawn on the layer, or a pixel that holds no opening.
fn foreign_pixel(
    path: &Path,
    design: &Design,
    layer: i16,
    datatype: i16,
    layer_name: Option<&str>,
    cell: Option<&str>,
) -> Result<Vec<Vec<f64>>> {
    let shown = layer_name.map_or(format!("{layer}/{datatype}"), str::to_owned);
    let bounds = udc_io::mask::drawn_bounds_um(path, layer, datatype, layer_name, cell)?
        .ok_or_else(|| {
            anyhow!(
                "{}: nothing is drawn on layer {shown} (give --layer L/D, or a DXF layer's name)",
                path.display()
            )
        })?;
    let period = design.opening.pitch_um + design.tiling.wiring_gap_um;
    let n = design.opening.n();
    let (window, warning) = match array_window(path, layer, datatype, layer_name, cell, period, n)?
    {
        Some((window, said)) => {
            eprintln!("note: {}: {said}", path.display());
            (window, None)
        }
        None => {
            let (window, warning) = udc_io::mask::foreign_window(bounds, period, n);
            eprintln!(
                "note: {} states no pitch of ours: reading the {period} µm pixel at ({:.3}, {:.3}) µm, the middle of its drawn layout on the layout's own grid",
                path.display(),
                window.left_um,
                window.top_um
            );
            (window, warning)
        }
    };
    if let Some(w) = warning {
        eprintln!("warning: {w}");
    }
    let imported = udc_io::mask::import_mask(
        path,
        &udc_io::mask::ImportOptions {
            cell_um: design.opening.cell_um(),
            layer,
            datatype,
            layer_name: layer_name.map(str::to_owned),
            cell: cell.map(str::to_owned),
            window: Some(window),
            checksum: ChecksumCheck::Ignore,
            ..udc_io::mask::ImportOptions::default()
        },
    )?;
    if imported.cells.iter().flatten().all(|c| *c == 0.0) {
        bail!(
            "{}: the pixel read at ({:.3}, {:.3}) µm holds no opening; the drawn layout spans {:.3} … {:.3} × {:.3} … {:.3} µm (check --pitch-um and --layer)",
            path.display(),
            window.left_um,
            window.top_um,
            bounds[0],
            bounds[2],
            bounds[1],
            bounds[3]
        );
    }
    Ok(imported.cells)
}

/// The window of the middle copy of a GDSII file's one array reference, when its spacing is
/// the pixel (`period_um` both ways, within 0.5 %) and its cell draws within one pixel from its
/// origin (the cell's corner, or its centre): the pixel exactly as the file registers it,
/// with a line saying so.
fn array_window(
    path: &Path,
    layer: i16,
    datatype: i16,
    layer_name: Option<&str>,
    cell: Option<&str>,
    period_um: f64,
    n: usize,
) -> Result<Option<(udc_io::mask::ImportWindow, String)>> {
    if !is_gds(path) || layer_name.is_some() {
        return Ok(None);
    }
    let Some(g) = udc_io::mask::array_grid(path, layer, datatype, cell)? else {
        return Ok(None);
    };
    let close = |a: f64, b: f64| (a - b).abs() <= 0.005 * b.abs().max(1e-9);
    // Columns to the right and rows upward, one pixel apart each way.
    let square = g.col_step_um[1].abs() < 1e-9
        && g.row_step_um[0].abs() < 1e-9
        && close(g.col_step_um[0], period_um)
        && close(g.row_step_um[1], period_um);
    let Some(b) = g.cell_bounds_um.filter(|_| square) else {
        return Ok(None);
    };
    let slack = period_um / n.max(1) as f64 / 100.0;
    let within = |lo: f64| {
        b[0] >= lo - slack
            && b[1] >= lo - slack
            && b[2] <= lo + period_um + slack
            && b[3] <= lo + period_um + slack
    };
    // The pixel's lower-left corner in the cell's own coordinates.
    let corner = if within(0.0) {
        0.0
    } else if within(-period_um / 2.0) {
        -period_um / 2.0
    } else {
        return Ok(None);
    };
    let (col, row) = (g.cols / 2, g.rows / 2);
    let x = g.origin_um[0] + f64::from(col) * g.col_step_um[0] + corner;
    let y = g.origin_um[1] + f64::from(row) * g.row_step_um[1] + corner;
    let window = udc_io::mask::ImportWindow {
        left_um: x,
        top_um: y + period_um,
        cols: n,
        rows: n,
    };
    let said = format!(
        "reading copy ({col}, {row}) of the {}×{} array of cell `{}` ({period_um} µm apart), \
         the pixel at ({x:.3}, {:.3}) µm as the array registers it",
        g.cols,
        g.rows,
        g.cell,
        y + period_um
    );
    Ok(Some((window, said)))
}

/// Whether `path` names a GDSII file.
fn is_gds(path: &Path) -> bool {
    matches!(
        path.extension()
            .map(|e| e.to_string_lossy().to_lowercase())
            .as_deref(),
        Some("gds" | "gdsii" | "gds2")
    )
}

/// The design the opening goes into: the sidecar, or the default design set from the notes;
/// `--pitch-um` and `--cells` override either.
fn template(path: &Path, layer: i16, datatype: i16, args: &ImportArgs) -> Result<Design> {
    let cell = args.cell.as_deref();
    let sidecar = sidecar_path(path);
    let mut design = if sidecar.is_file() {
        load_design(&sidecar)?
    } else {
        let notes = mask_notes(path, layer, datatype, cell)?;
        let lines = || notes.iter().map(String::as_str);
        let number = |key: &str| -> Option<f64> { note_field(lines(), key)?.parse().ok() };
        let mut d = Design {
            name: path
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default(),
            ..Design::default()
        };
        d.opening.polygons.clear();
        if let Some(cells) = number("CELLS") {
            d.opening.cells = square(cells_in_range(cells, "the CELLS= note")?);
        }
        if let Some(pitch_nm) = number("PITCH_NM") {
            d.opening.pitch_um = pitch_nm / 1e3;
            let period_nm = number("PERIOD_NM").unwrap_or(pitch_nm);
            d.tiling.wiring_gap_um = (period_nm - pitch_nm).max(0.0) / 1e3;
        } else if args.pitch_um.is_none() {
            // Another tool's array of one pixel cell: its spacing is the pitch.
            let spacing = udc_io::mask::array_grid(path, layer, datatype, cell)
                .ok()
                .flatten()
                .filter(|g| {
                    g.col_step_um[1] == 0.0
                        && g.row_step_um[0] == 0.0
                        && g.col_step_um[0] > 0.0
                        && (g.col_step_um[0] - g.row_step_um[1]).abs() <= 1e-9 * g.col_step_um[0]
                })
                .map(|g| g.col_step_um[0]);
            let Some(pitch_um) = spacing.filter(|_| is_gds(path)) else {
                bail!(
                    "{}: the mask states no PITCH_NM= note and has no sidecar design; give --pitch-um",
                    path.display()
                );
            };
            eprintln!(
                "note: {}: pitch {pitch_um} µm, the spacing of its array reference",
                path.display()
            );
            d.opening.pitch_um = pitch_um;
        }
        if number("CELLS").is_none() && args.cells.is_none() {
            bail!(
                "{}: the mask states no CELLS= note and has no sidecar design; give --cells",
                path.display()
            );
        }
        if let Some(mode) = note_field(lines(), "TILING") {
            d.tiling.mode = mode
                .parse::<TilingMode>()
                .map_err(|e| anyhow!("{}: {e}", path.display()))?;
        }
        d.tiling.seed = note_field(lines(), "SEED")
            .and_then(|s| s.parse().ok())
            .unwrap_or(0);
        if let Some((x, y)) = note_field(lines(), "AXIS_CELL").and_then(|a| a.split_once(','))
            && let (Ok(x), Ok(y)) = (x.parse::<f64>(), y.parse::<f64>())
        {
            d.tiling.origin_offset_cells = [x, y];
        }
        d
    };
    if let Some(p) = args.pitch_um {
        if !(p.is_finite() && p > 0.0) {
            bail!("--pitch-um: must be a positive number of µm (got {p})");
        }
        design.opening.pitch_um = p;
    }
    if let Some(n) = args.cells {
        design.opening.cells = square(cells_in_range(n as f64, "--cells")?);
        design.reconcile_subpixels();
    }
    Ok(design)
}

/// A cell count from user data, checked before a grid of that size is allocated.
fn cells_in_range(n: f64, what: &str) -> Result<usize> {
    if !(n.fract() == 0.0 && (1.0..=MAX_CELLS as f64).contains(&n)) {
        bail!(
            "{what}: cells across a pixel must be a whole number from 1 to {MAX_CELLS} (got {n})"
        );
    }
    Ok(n as usize)
}

/// An `n × n` grid of closed cells (the import fills it).
fn square(n: usize) -> Vec<Vec<f64>> {
    vec![vec![0.0; n]; n]
}
