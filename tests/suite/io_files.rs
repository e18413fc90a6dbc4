//! File formats against real files: the thesis authors' pixel patterns, the spectral tables,
//! exported PSF images and MTF tables read back with the `image` crate, the presets, and the
//! errors malformed design files produce.

// The helpers below are test code too: a panic in them is a failing test, which is what we want.
#![allow(clippy::unwrap_used)]

use std::path::{Path, PathBuf};

use ndarray::{Array2, array};
use udc_studio::core::design::TilingMode::{self, Random4, Repeat};
use udc_studio::core::design::{Channel, Design, Opening, Optics};
use udc_studio::core::psf::sampling::fft_size;
use udc_studio::core::{Analysis, Progress, analyze};
use udc_studio::io::IoError;
use udc_studio::io::design::file::{load_design, parse_design, to_json};
use udc_studio::io::design::pattern::{load_pattern_png, save_pattern_png};
use udc_studio::io::design::presets::{PRESETS, PresetGroup, load_preset};
use udc_studio::io::design::spectral::{channels_from_response, load_response_csv};
use udc_studio::io::display::export::{
    LOG_PSF_FLOOR_DECADES, write_analysis_outputs, write_log_psf_png, write_mtf_csv, write_psf_exr,
    write_psf_png16,
};
use udc_studio::io::error::{PatternError, TableError};

fn asset(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("assets")
        .join(rel)
}

/// The error's message names `path` (where it went wrong).
fn assert_names(err: &IoError, path: &Path) {
    let msg = err.to_string();
    assert!(msg.contains(&path.display().to_string()), "{msg}");
}

fn open_cells(cells: &[Vec<f64>]) -> usize {
    cells.iter().flatten().filter(|v| **v == 1.0).count()
}

// ---------------------------------------------------------------- pixel patterns

/// `(file, cells per side, open cells)`: the table of /work/shared/reference/README.md, as counts.
const PATTERNS: &[(&str, usize, usize)] = &[
    ("TOLED_Rect.png", 21, 105),      // 5/21
    ("TOLED_Rect_5.png", 21, 105),    // 5/21
    ("TOLED_Rect_7.png", 21, 147),    // 7/21 = 0.333
    ("TOLED_Rect_9.png", 21, 189),    // 9/21 = 0.429
    ("TOLED_Rect_11.png", 21, 231),   // 11/21 = 0.524
    ("TOLED_Rect_5_42.png", 42, 210), // 5/42 = 0.119
    ("POLED.png", 42, 419),           // 0.2375
    ("POLED_Circ.png", 29, 194),      // 0.231
    ("POLED_Circ_9.png", 29, 370),    // 0.440
    ("OpenAperture.png", 21, 441),    // 1
    ("L2_Repeat.png", 21, 101),       // ≈ 0.23
    ("L2Inv_Repeat.png", 21, 100),
    ("L2_Random.png", 21, 101),
    ("L2Inv_Random.png", 21, 100),
];

#[test]
fn every_reference_pattern_loads_with_its_published_open_fraction() {
    let mut on_disk: Vec<String> = std::fs::read_dir(asset("pixel-patterns"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".png"))
        .collect();
    on_disk.sort();
    let mut listed: Vec<String> = PATTERNS.iter().map(|p| p.0.to_string()).collect();
    listed.sort();
    assert_eq!(
        on_disk, listed,
        "every PNG in assets/pixel-patterns has an expected open fraction"
    );
    for &(file, n, open) in PATTERNS {
        let cells = load_pattern_png(&asset(&format!("pixel-patterns/{file}"))).unwrap();
        assert_eq!(cells.len(), n, "{file}");
        assert!(cells.iter().all(|r| r.len() == n), "{file}");
        assert!(
            cells.iter().flatten().all(|v| *v == 0.0 || *v == 1.0),
            "{file}"
        );
        assert_eq!(
            open_cells(&cells),
            open,
            "{file}: open fraction {open}/{}",
            n * n
        );
    }
    let toled = load_pattern_png(&asset("pixel-patterns/TOLED_Rect.png")).unwrap();
    assert_eq!(open_cells(&toled) as f64 / 441.0, 5.0 / 21.0);
    // Not just the count: it is the centred 5-cell slit, columns 8..13 of every row.
    assert_eq!(toled, Opening::slit(21, 5, 168.0).cells);
}

#[test]
fn a_non_square_image_is_refused_with_its_size_and_path() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("wide.png");
    image::GrayImage::from_pixel(5, 3, image::Luma([255]))
        .save(&path)
        .unwrap();
    let err = load_pattern_png(&path).unwrap_err();
    assert!(
        matches!(
            err,
            IoError::Pattern {
                error: PatternError::NotSquare {
                    width: 5,
                    height: 3
                },
                ..
            }
        ),
        "{err:?}"
    );
    let msg = err.to_string();
    assert!(msg.contains("5×3") && msg.contains("square"), "{msg}");
    assert!(msg.contains(&path.display().to_string()), "{msg}");
}

#[test]
fn a_corrupt_image_is_refused_with_its_path() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("broken.png");
    // A PNG signature followed by garbage: sniffed as PNG, fails to decode.
    let mut bytes = b"\x89PNG\r\n\x1a\n".to_vec();
    bytes.extend_from_slice(b"this is not a PNG chunk stream at all");
    std::fs::write(&path, bytes).unwrap();
    let err = load_pattern_png(&path).unwrap_err();
    assert!(
        matches!(
            err,
            IoError::Pattern {
                error: PatternError::Unreadable(_),
                ..
            }
        ),
        "{err:?}"
    );
    assert_names(&err, &path);
    let text = dir.path().join("notes.png");
    std::fs::write(&text, "just some text").unwrap();
    let err = load_pattern_png(&text).unwrap_err();
    assert_names(&err, &text);
}

#[test]
fn a_missing_image_is_a_file_error_with_its_path() {
    let path = Path::new("/nonexistent/udc/pattern.png");
    let err = load_pattern_png(path).unwrap_err();
    assert!(matches!(err, IoError::File { .. }), "{err:?}");
    assert_names(&err, Path::new("/nonexistent/udc/pattern.png"));
}

#[test]
fn a_saved_pattern_loads_back_cell_for_cell() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("poled.png");
    let cells = load_pattern_png(&asset("pixel-patterns/POLED.png")).unwrap();
    save_pattern_png(&path, &cells).unwrap();
    assert_eq!(load_pattern_png(&path).unwrap(), cells);
    let grey = image::open(&path).unwrap();
    assert_eq!(grey.color(), image::ColorType::L8);
}

// ---------------------------------------------------------------- spectral tables

/// The r, g, b values of one row of the thesis table, read straight from the text.
fn thesis_row(wavelength: &str) -> [f64; 3] {
    let text = std::fs::read_to_string(asset("spectral/thesis_sensor_response.csv")).unwrap();
    let line = text
        .lines()
        .find(|l| l.split(',').next() == Some(wavelength))
        .unwrap();
    let v: Vec<f64> = line
        .split(',')
        .skip(1)
        .map(|f| f.parse().unwrap())
        .collect();
    [v[0], v[1], v[2]]
}

#[test]
fn the_spectral_tables_load() {
    let r = load_response_csv(&asset("spectral/thesis_sensor_response.csv")).unwrap();
    assert_eq!(r.wavelengths_nm.len(), 300);
    assert_eq!((r.wavelengths_nm[0], r.wavelengths_nm[299]), (401.0, 700.0));
    // The table is normalised per channel (README).
    for c in [&r.r, &r.g, &r.b] {
        assert!((c.iter().sum::<f64>() - 1.0).abs() < 1e-5);
    }
    assert_eq!([r.r[129], r.g[129], r.b[129]], thesis_row("530"));
    // Other headers (`wavelength,R,G,B`), integers and exponents.
    for (file, rows) in [
        ("nikon_d5100_npl.csv", 81),
        ("canon_eos_5d_mark_ii_rawtoaces.csv", 81),
    ] {
        let r = load_response_csv(&asset(&format!("spectral/{file}"))).unwrap();
        assert_eq!(r.wavelengths_nm.len(), rows, "{file}");
        assert_eq!(
            (r.wavelengths_nm[0], r.wavelengths_nm[rows - 1]),
            (380.0, 780.0),
            "{file}"
        );
    }
    let nikon = load_response_csv(&asset("spectral/nikon_d5100_npl.csv")).unwrap();
    assert_eq!(nikon.r[78], 8.56e-05); // "770,8.56e-05,…"
}

#[test]
fn channels_interpolate_the_table_linearly_and_sum_to_one() {
    let resp = load_response_csv(&asset("spectral/thesis_sensor_response.csv")).unwrap();
    let v530 = thesis_row("530");
    let v531 = thesis_row("531");
    let v610 = thesis_row("610");
    let samples = [530.0, 530.25, 610.0];
    let ch = channels_from_response(&resp, &samples).unwrap();
    assert_eq!(
        ch.iter().map(|c| c.name.as_str()).collect::<Vec<_>>(),
        ["R", "G", "B"]
    );
    for (k, c) in ch.iter().enumerate() {
        assert_eq!(c.wavelengths_nm, samples);
        assert!(
            (c.weights.iter().sum::<f64>() - 1.0).abs() < 1e-12,
            "{}",
            c.name
        );
        let raw = [v530[k], 0.75 * v530[k] + 0.25 * v531[k], v610[k]];
        let sum: f64 = raw.iter().sum();
        for (w, r) in c.weights.iter().zip(raw) {
            assert!(
                (w - r / sum).abs() < 1e-14,
                "{}: {w} vs {}",
                c.name,
                r / sum
            );
        }
    }
    // B changes between 530 and 531 nm, so the mix is really between the rows.
    assert!(ch[2].weights[1] > ch[2].weights[0]);
    // The channels validate as part of a design.
    let mut d = Design::default_toled();
    d.channels = ch;
    d.validate().unwrap();
    assert!(
        channels_from_response(&resp, &[400.0])
            .unwrap_err()
            .to_string()
            .contains("400")
    );
}

fn bad_table(text: &str) -> String {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.csv");
    std::fs::write(&path, text).unwrap();
    let err = load_response_csv(&path).unwrap_err();
    assert!(
        matches!(
            err,
            IoError::Table {
                error: TableError::Spectral(_),
                ..
            }
        ),
        "{err:?}"
    );
    let msg = err.to_string();
    assert!(msg.ends_with(&format!("(in {})", path.display())), "{msg}");
    msg
}

#[test]
fn bad_spectral_tables_name_the_line() {
    let msg = bad_table("wavelength_nm,r,g,b\n500,0.1,0.2,0.3\n510,abc,0.2,0.3\n");
    assert!(
        msg.starts_with("line 3, column 2: `abc` is not a number"),
        "{msg}"
    );
    let msg = bad_table("wavelength_nm,r,g,b\n500,0.1,0.2,0.3\n510,0.1,0.2,0.3\n505,0.1,0.2,0.3\n");
    assert!(
        msg.starts_with("line 4, column 1") && msg.contains("increase"),
        "{msg}"
    );
    let msg = bad_table("wavelength_nm,r,g,b\n500,0.1,0.2,0.3\n510,0.1,-0.2,0.3\n");
    assert!(msg.starts_with("line 3, column 3"), "{msg}");
    let msg = bad_table("wavelength_nm,r,g,b\n500,0.1,0.2,0.3\n510,0.1,0.2,NaN\n");
    assert!(msg.starts_with("line 3, column 4"), "{msg}");
    let msg = bad_table("wavelength_nm,r,g,b\n500,0.1,0.2,0.3\n");
    assert!(msg.contains("at least 2"), "{msg}");
    let err = load_response_csv(Path::new("/nonexistent/response.csv")).unwrap_err();
    assert_names(&err, Path::new("/nonexistent/response.csv"));
}

// ---------------------------------------------------------------- exports

/// A real analysis of the T-OLED with a small window (fast, still a valid design).
fn small_analysis() -> Analysis {
    let mut d = Design::default_toled();
    d.optics.window_px = 32;
    d.validate().unwrap();
    analyze(&d, &Progress::new()).unwrap()
}

#[test]
fn exr_round_trips_to_f32_precision_with_rows_as_rows() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("psf.exr");
    // Non-square and asymmetric, so a transpose or flip would show.
    let psf = array![[0.0, 1e-9, 0.25], [0.125, 3.5, 1.0 / 3.0]];
    write_psf_exr(&path, &psf).unwrap();
    let img = image::open(&path).unwrap().into_rgb32f();
    assert_eq!(img.dimensions(), (3, 2));
    for ((row, col), v) in psf.indexed_iter() {
        let p = img.get_pixel(col as u32, row as u32).0;
        assert_eq!(p, [*v as f32; 3], "[{row}, {col}]");
    }
}

#[test]
fn png16_puts_the_peak_at_65535_and_keeps_zero() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("psf.png");
    // Scaled values avoid exact halves, so the rounding is unambiguous.
    let psf = array![[0.0, 4.0], [1.0, 0.5]];
    write_psf_png16(&path, &psf).unwrap();
    let img = image::open(&path).unwrap();
    assert_eq!(img.color(), image::ColorType::L16);
    let img = img.into_luma16();
    assert_eq!(img.get_pixel(1, 0).0, [65535]);
    assert_eq!(img.get_pixel(0, 0).0, [0]);
    assert_eq!(img.get_pixel(0, 1).0, [16384]); // 65535 / 4 = 16383.75
    assert_eq!(img.get_pixel(1, 1).0, [8192]); // 65535 / 8 = 8191.875
}

#[test]
fn log_psf_maps_decades_onto_the_documented_floor() {
    assert_eq!(LOG_PSF_FLOOR_DECADES, 6.0);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("log.png");
    let psf = array![[1.0, 1e-3, 1e-6], [1e-9, 0.0, 1e-2]];
    write_log_psf_png(&path, &psf).unwrap();
    let img = image::open(&path).unwrap();
    assert_eq!(img.color(), image::ColorType::L8);
    let img = img.into_luma8();
    let at = |row: u32, col: u32| img.get_pixel(col, row).0[0];
    assert_eq!(at(0, 0), 255);
    assert_eq!(at(0, 1), (255.0f64 * (1.0 - 3.0 / 6.0)).round() as u8);
    assert_eq!(at(0, 2), 0, "exactly at the floor");
    assert_eq!(at(1, 0), 0, "below the floor clips to it");
    assert_eq!(at(1, 1), 0, "zero (log −∞) clips to the floor");
    assert_eq!(at(1, 2), 170, "two decades down: 255 · 4/6");
}

#[test]
fn the_mtf_table_holds_every_ring_of_every_channel() {
    let a = small_analysis();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("mtf.csv");
    write_mtf_csv(&path, &a).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next().unwrap(),
        "freq_cyc_per_px,R_horizontal,R_vertical,R_radial_min,R_radial_mean,\
         G_horizontal,G_vertical,G_radial_min,G_radial_mean,\
         B_horizontal,B_vertical,B_radial_min,B_radial_mean"
    );
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|f| f.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 16, "rings d = 0 … N/2 − 1 of a 32-pixel window");
    for (d, row) in rows.iter().enumerate() {
        assert_eq!(row.len(), 13);
        assert_eq!(row[0], d as f64 / 32.0);
        for (k, ch) in a.channels.iter().enumerate() {
            let m = &ch.mtf;
            let want = [
                m.horizontal[d],
                m.vertical[d],
                m.radial_min[d],
                m.radial_mean[d],
            ];
            assert_eq!(
                row[1 + 4 * k..5 + 4 * k],
                want,
                "ring {d}, channel {}",
                ch.name
            );
        }
    }
    assert_eq!(rows[0][3], 1.0, "MTF(0) = 1");
}

#[test]
fn analysis_outputs_are_all_written_and_read_back() {
    let a = small_analysis();
    let base = tempfile::tempdir().unwrap();
    let dir = base.path().join("nested/out");
    let written = write_analysis_outputs(&dir, &a).unwrap();
    let names: Vec<String> = written
        .iter()
        .map(|p| p.strip_prefix(&dir).unwrap().to_string_lossy().into_owned())
        .collect();
    let mut want: Vec<String> = Vec::new();
    for c in ["R", "G", "B"] {
        want.extend([
            format!("psf_{c}.exr"),
            format!("psf_{c}.png"),
            format!("log_psf_{c}.png"),
        ]);
    }
    want.extend(["psf_rgb.exr".to_string(), "mtf.csv".to_string()]);
    assert_eq!(names, want);
    for p in &written {
        assert!(std::fs::metadata(p).unwrap().len() > 0, "{}", p.display());
    }
    // The RGB EXR carries each channel's unscaled PSF in its own colour.
    let rgb = image::open(dir.join("psf_rgb.exr")).unwrap().into_rgb32f();
    assert_eq!(rgb.dimensions(), (32, 32));
    for (k, ch) in a.channels.iter().enumerate() {
        for ((row, col), v) in ch.psf.indexed_iter() {
            assert_eq!(rgb.get_pixel(col as u32, row as u32).0[k], *v as f32);
        }
        let g = image::open(dir.join(format!("psf_{}.exr", ch.name)))
            .unwrap()
            .into_rgb32f();
        let sum: f64 = g.pixels().map(|p| f64::from(p.0[0])).sum();
        assert!(
            (sum - 1.0).abs() < 1e-5,
            "the sensor PSF sums to 1 unscaled"
        );
    }
    // The R and B PSFs differ, so channel order matters in the check above.
    assert_ne!(a.channels[0].psf, a.channels[2].psf);
}

#[test]
fn writing_into_a_path_that_is_a_file_names_the_folder() {
    let a = small_analysis();
    let base = tempfile::tempdir().unwrap();
    let file = base.path().join("occupied");
    std::fs::write(&file, "x").unwrap();
    let err = write_analysis_outputs(&file, &a).unwrap_err();
    assert!(matches!(err, IoError::File { .. }), "{err:?}");
    assert_names(&err, &file);
    let empty = Array2::<f64>::zeros((0, 0));
    let err = write_psf_exr(&base.path().join("e.exr"), &empty).unwrap_err();
    assert!(err.to_string().contains("e.exr"), "{err}");
}

// ---------------------------------------------------------------- presets

/// `(preset, pattern, pitch µm, tiling, origin offset in cells)`.
const PRESET_SOURCES: &[(&str, &str, f64, TilingMode, f64)] = &[
    ("toled-150dpi", "TOLED_Rect.png", 168.0, Repeat, 6.0),
    ("toled-300dpi", "TOLED_Rect.png", 84.0, Repeat, 6.0),
    ("toled-600dpi", "TOLED_Rect.png", 42.0, Repeat, 6.0),
    ("poled-336um", "POLED.png", 336.0, Repeat, 6.0),
    ("disc-lattice", "POLED_Circ.png", 232.0, Repeat, 8.0),
    ("open-aperture", "OpenAperture.png", 168.0, Repeat, 6.0),
    ("l2-repeat", "L2_Repeat.png", 168.0, Repeat, 6.0),
    ("l2inv-repeat", "L2Inv_Repeat.png", 168.0, Repeat, 6.0),
    ("l2-random", "L2_Random.png", 168.0, Random4, 6.0),
    ("l2inv-random", "L2Inv_Random.png", 168.0, Random4, 6.0),
    (
        "l2inv-random-wiring8",
        "L2Inv_Random.png",
        168.0,
        Random4,
        6.0,
    ),
];

#[test]
fn every_preset_is_its_reference_pattern_and_round_trips() {
    let mut names: Vec<&str> = PRESETS
        .iter()
        .filter(|p| p.group == PresetGroup::Thesis)
        .map(|p| p.name)
        .collect();
    names.sort_unstable();
    let mut sources: Vec<&str> = PRESET_SOURCES.iter().map(|p| p.0).collect();
    sources.sort_unstable();
    assert_eq!(names, sources);
    for &(name, png, pitch_um, mode, offset) in PRESET_SOURCES {
        let d = load_preset(name).unwrap();
        let cells = load_pattern_png(&asset(&format!("pixel-patterns/{png}"))).unwrap();
        assert_eq!(d.opening.cells, cells, "{name} is {png}");
        assert!(d.opening.polygons.is_empty(), "{name}");
        assert_eq!(d.opening.pitch_um, pitch_um, "{name}");
        assert_eq!(d.tiling.mode, mode, "{name}");
        assert_eq!(d.tiling.seed, 0, "{name}");
        assert_eq!(d.tiling.origin_offset_cells, [offset, offset], "{name}");
        let gap_um = if name.ends_with("-wiring8") { 8.0 } else { 0.0 };
        assert_eq!(d.tiling.wiring_gap_um, gap_um, "{name}");
        assert_eq!(d.channels, Channel::rgb_peaks(), "{name}");
        assert!(!d.name.is_empty(), "{name}");
        assert!(
            d.description.contains("thesis §3"),
            "{name}: {}",
            d.description
        );
        assert!(
            d.description.contains(png),
            "{name} names its source pattern"
        );
        let again = parse_design(&to_json(&d)).unwrap();
        assert_eq!(again, d, "{name}: to_json → parse_design");
        // The file is exactly what the studio would write.
        let text = PRESETS.iter().find(|p| p.name == name).unwrap().text;
        assert_eq!(text, to_json(&d), "{name} is in the design_file format");
    }
}

#[test]
fn presets_use_the_thesis_optics_unless_their_cells_need_a_finer_pupil_grid() {
    for &(name, ..) in PRESET_SOURCES {
        let d = load_preset(name).unwrap();
        let cell_um = d.opening.cell_um();
        if cell_um >= 8.0 {
            assert_eq!(d.optics, Optics::iccp21(), "{name}");
            continue;
        }
        // 300 / 600 DPI: the pupil grid resolves the cells, everything else stays iccp21.
        let op = &d.optics;
        assert_eq!(
            op.recipe,
            udc_studio::core::design::OpticsRecipe::Custom,
            "{name}"
        );
        assert_eq!(op.pupil_sample_um, cell_um, "{name}");
        assert_eq!((op.sensor_pixel_um, op.window_px), (2.0, 294), "{name}");
        let iccp = Optics::iccp21();
        assert_eq!(
            (op.focal_length_mm, op.f_number, op.axis_in_pixel_um),
            (iccp.focal_length_mm, iccp.f_number, iccp.axis_in_pixel_um),
            "{name}"
        );
        let m = fft_size(
            610.0,
            op.focal_length_mm,
            op.pupil_sample_um,
            op.fine_sample_um,
        );
        assert!(m <= 8192, "{name}: FFT {m}");
        // At least 2× zero-padding of the pupil, so the PSF is not under-sampled.
        assert!(
            m as f64 >= 2.0 * op.pupil_diameter_um() / op.pupil_sample_um,
            "{name}: FFT {m}"
        );
        assert!(
            d.description.contains("pupil_sample_um"),
            "{name} says what changed"
        );
    }
}

// ---------------------------------------------------------------- malformed design files

fn base_json() -> serde_json::Value {
    serde_json::from_str(&to_json(&Design::default_toled())).unwrap()
}

fn parse_err(v: &serde_json::Value) -> String {
    parse_design(&v.to_string()).unwrap_err().to_string()
}

#[test]
fn malformed_designs_name_the_field() {
    let mut v = base_json();
    v["optics"]["bogus"] = 1.into();
    let e = parse_err(&v);
    assert!(
        e.contains("`optics.bogus`") && e.contains("unknown field"),
        "{e}"
    );

    let mut v = base_json();
    v["opening"]["pitch_um"] = (-168.0).into();
    let e = parse_err(&v);
    assert!(e.contains("opening.pitch_um") && e.contains("-168"), "{e}");

    let mut v = base_json();
    let mut row = vec![0.0; 21];
    row[3] = 1.5;
    v["opening"]["cells"][2] = serde_json::json!(row);
    let e = parse_err(&v);
    assert!(
        e.contains("opening.cells[2][3]") && e.contains("1.5"),
        "{e}"
    );

    let mut v = base_json();
    v["version"] = 7.into();
    let e = parse_err(&v);
    assert!(e.contains("`version`") && e.contains('7'), "{e}");

    let mut v = base_json();
    v["opening"]["cells"][4] = "........##x##........".into();
    let e = parse_err(&v);
    assert!(
        e.contains("opening.cells") && e.contains("row 4") && e.contains("'x'"),
        "{e}"
    );

    let text = to_json(&Design::default_toled());
    let e = parse_design(&text[..text.len() / 2])
        .unwrap_err()
        .to_string();
    assert!(e.contains("EOF") && e.contains("line"), "{e}");

    // The unmodified base parses, so each error above comes from its one change.
    assert_eq!(
        parse_design(&base_json().to_string()).unwrap(),
        Design::default_toled()
    );
}

#[test]
fn a_malformed_design_file_names_field_and_path() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.udc.json");
    let text = to_json(&Design::default_toled()).replace("\"f_number\": 2.5", "\"f_number\": -2.5");
    std::fs::write(&path, text).unwrap();
    let err = load_design(&path).unwrap_err();
    assert!(matches!(err, IoError::Design { .. }), "{err:?}");
    let msg = err.to_string();
    assert!(msg.contains("optics.f_number"), "{msg}");
    assert!(msg.ends_with(&format!("(in {})", path.display())), "{msg}");
}

/// The built-in photo fitted to a narrow sensor: the longer side shrinks to the limit, the
/// aspect ratio and the mean brightness stay; a photo that fits is returned as it is.
#[test]
fn fit_max_side_shrinks_to_the_limit_and_keeps_what_fits() {
    use udc_studio::io::photo::{built_in_photo, fit_max_side};
    let full = built_in_photo().unwrap();
    let (h, w) = full[0].dim();
    let small = fit_max_side(full.clone(), 64);
    assert_eq!(small.len(), 3);
    let (sh, sw) = small[0].dim();
    assert_eq!(sh.max(sw), 64);
    assert!(((sw as f64 / sh as f64) - (w as f64 / h as f64)).abs() < 0.05);
    for (a, b) in full.iter().zip(&small) {
        let (ma, mb) = (a.mean().unwrap(), b.mean().unwrap());
        assert!((ma - mb).abs() < 0.02, "mean {ma} vs {mb}");
    }
    assert_eq!(fit_max_side(full.clone(), w.max(h)), full);
}

#[test]
fn a_truncated_jpeg_is_refused_and_the_whole_one_loads() {
    use udc_studio::io::photo::load_photo;
    let dir = tempfile::tempdir().expect("temp dir");
    let img = image::RgbImage::from_fn(64, 48, |x, y| {
        image::Rgb([(x * 4) as u8, (y * 5) as u8, 90])
    });
    let mut bytes = Vec::new();
    image::DynamicImage::ImageRgb8(img)
        .write_to(
            &mut std::io::Cursor::new(&mut bytes),
            image::ImageFormat::Jpeg,
        )
        .expect("encode");
    let whole = dir.path().join("whole.jpg");
    std::fs::write(&whole, &bytes).expect("write");
    let planes = load_photo::<f64>(&whole, None).expect("a complete JPEG loads");
    assert_eq!(planes[0].dim(), (48, 64));
    // Cut before the last rows: decoders would fill them with grey and report success.
    let cut = dir.path().join("cut.jpg");
    std::fs::write(&cut, &bytes[..bytes.len() * 2 / 3]).expect("write");
    let err = load_photo::<f64>(&cut, None).expect_err("a truncated JPEG is refused");
    let text = err.to_string();
    assert!(text.contains("truncated"), "{text}");
    assert_names(&err, &cut);
}
