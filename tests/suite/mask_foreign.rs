//! Masks from other tools, without our notes: a 3×3 array of a 100-µm pixel (a 30×60-µm
//! opening) written by gdstk as an array reference or as flat polygons, at the origin or far
//! from it, reads back as the pixel at the layout's middle with its open fraction; a pitch that
//! misses the array is refused in one line, with the layout's extent.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::Path;

use crate::common::run_cli as run;

fn gdstk(dir: &Path, name: &str, origin: (f64, f64), aref: bool) {
    let code = format!(
        "import gdstk\n\
         lib = gdstk.Library(unit=1e-6, precision=1e-9)\n\
         top = lib.new_cell('TOP')\n\
         if {aref}:\n\
         \x20   unit = lib.new_cell('UNIT')\n\
         \x20   unit.add(gdstk.rectangle((20, 10), (50, 70), layer=1, datatype=0))\n\
         \x20   top.add(gdstk.Reference(unit, {origin:?}, columns=3, rows=3, spacing=(100, 100)))\n\
         else:\n\
         \x20   for i in range(3):\n\
         \x20       for j in range(3):\n\
         \x20           x, y = {ox} + 100 * i, {oy} + 100 * j\n\
         \x20           top.add(gdstk.rectangle((x + 20, y + 10), (x + 50, y + 70), layer=1, datatype=0))\n\
         lib.write_gds('{name}')\n",
        aref = if aref { "True" } else { "False" },
        ox = origin.0,
        oy = origin.1,
    );
    crate::common::python(dir, &code, "gdstk");
}

/// `udc-studio import MASK [--layer LAYER] --pitch-um PITCH --cells 20 --out OUT`.
fn import(mask: &Path, layer: Option<&str>, pitch_um: &str, out: &Path) -> (bool, String, String) {
    let mut args = vec!["import", mask.to_str().unwrap()];
    if let Some(l) = layer {
        args.extend(["--layer", l]);
    }
    args.extend([
        "--pitch-um",
        pitch_um,
        "--cells",
        "20",
        "--out",
        out.to_str().unwrap(),
    ]);
    run(&args)
}

fn open_fraction(design: &Path) -> f64 {
    let d = udc_studio::io::design::file::load_design(design).unwrap();
    let n = d.opening.n();
    d.opening.cells.iter().flatten().sum::<f64>() / (n * n) as f64
}

#[test]
fn an_array_from_another_tool_reads_as_its_middle_pixel_wherever_it_is() {
    let dir = tempfile::tempdir().unwrap();
    for (name, origin, aref) in [
        ("origin.gds", (0.0, 0.0), true),
        ("far.gds", (1000.0, -333.0), true),
        ("flat.gds", (1000.0, -333.0), false),
    ] {
        gdstk(dir.path(), name, origin, aref);
        let gds = dir.path().join(name);
        let out = dir.path().join(format!("{name}.json"));
        let (ok, stdout, stderr) = import(&gds, None, "100", &out);
        assert!(ok, "{name}: {stderr}");
        assert!(
            stdout.contains("open fraction 0.180000"),
            "{name}: {stdout}"
        );
        assert!((open_fraction(&out) - 0.18).abs() < 1e-12, "{name}");
        // An array reference registers the pixel: read where the array puts it, the opening
        // 20 µm from its left and 30 µm from its top (cells of 5 µm); flat polygons have no
        // registration: the pixel at the layout's middle, on the layout's grid.
        if aref {
            assert!(
                stderr.contains("3×3 array of cell `UNIT`"),
                "{name}: {stderr}"
            );
            let d = udc_studio::io::design::file::load_design(&out).unwrap();
            let c = &d.opening.cells;
            assert_eq!(
                (c[6][4], c[5][4], c[6][3], c[17][9], c[18][9]),
                (1.0, 0.0, 0.0, 1.0, 0.0),
                "{name}"
            );
        } else {
            assert!(
                stderr.contains("middle of its drawn layout"),
                "{name}: {stderr}"
            );
        }
        assert!(!stderr.contains("warning"), "{name}: {stderr}");
    }
    // Without --pitch-um, an array reference's spacing is the pitch.
    let out = dir.path().join("inferred.json");
    let (ok, stdout, stderr) = run(&[
        "import",
        dir.path().join("far.gds").to_str().unwrap(),
        "--cells",
        "20",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    assert!(
        stderr.contains("pitch 100 µm, the spacing of its array reference"),
        "{stderr}"
    );
    assert!(
        stdout.contains("pitch 100 µm, open fraction 0.180000"),
        "{stdout}"
    );
    // A pitch ten times the array's: the pixel misses it, said in one line with the extent.
    let out = dir.path().join("wrong.json");
    let (ok, _, stderr) = import(&dir.path().join("far.gds"), None, "1000", &out);
    assert!(!ok && !out.exists(), "{stderr}");
    assert!(stderr.contains("not wholly inside"), "{stderr}");
    let error = stderr.lines().find(|l| l.starts_with("error")).unwrap();
    assert!(
        error.contains("holds no opening") && error.contains("1020.000"),
        "{error}"
    );
}

#[test]
fn the_foreign_window_sits_inside_the_layout_on_its_grid() {
    use udc_studio::io::mask::foreign_window;
    // Three pixels of 100 µm from x = 20 (an opening inset 20 µm): the middle one.
    let (w, warning) = foreign_window([20.0, -290.0, 250.0, -40.0], 100.0, 20);
    assert_eq!(
        (w.left_um, w.top_um, w.cols, w.rows),
        (120.0, -140.0, 20, 20)
    );
    assert!(warning.is_none());
    // A layout smaller than one pixel: centred on it, and said.
    let (w, warning) = foreign_window([0.0, 0.0, 50.0, 50.0], 100.0, 10);
    assert_eq!((w.left_um, w.top_um), (-25.0, 75.0));
    assert!(warning.unwrap().contains("not wholly inside"));
}

/// Writes, with ezdxf, a 3×3 array of the pixel as one arrayed block insert on layer `OPEN`
/// (the block's polyline on layer `0`, which takes the insert's layer), plus a text on it.
/// `half`: the block drawn at half size, inserted scaled ×2 and turned 90°.
fn ezdxf(dir: &Path, name: &str, half: bool) {
    let code = format!(
        "import ezdxf\n\
         doc = ezdxf.new('R2000')\n\
         doc.layers.add('OPEN')\n\
         blk = doc.blocks.new(name='PIX')\n\
         if {half}:\n\
         \x20   blk.add_lwpolyline([(10, 5), (25, 5), (25, 35), (10, 35)], close=True, dxfattribs={{'layer': '0'}})\n\
         \x20   attribs = {{'layer': 'OPEN', 'xscale': 2, 'yscale': 2, 'rotation': 90}}\n\
         else:\n\
         \x20   blk.add_lwpolyline([(20, 10), (50, 10), (50, 70), (20, 70)], close=True, dxfattribs={{'layer': '0'}})\n\
         \x20   attribs = {{'layer': 'OPEN'}}\n\
         attribs.update(column_count=3, row_count=3, column_spacing=100, row_spacing=100)\n\
         msp = doc.modelspace()\n\
         msp.add_blockref('PIX', (1000, -333), dxfattribs=attribs)\n\
         msp.add_text('made elsewhere', dxfattribs={{'layer': 'OPEN'}})\n\
         doc.saveas('{name}')\n",
        half = if half { "True" } else { "False" },
    );
    crate::common::python(dir, &code, "ezdxf");
}

#[test]
fn a_dxf_layer_is_chosen_by_name_and_its_block_inserts_are_expanded() {
    let dir = tempfile::tempdir().unwrap();
    for (name, half) in [("blocks.dxf", false), ("turned.dxf", true)] {
        ezdxf(dir.path(), name, half);
        let dxf = dir.path().join(name);
        let out = dir.path().join(format!("{name}.json"));
        let (ok, stdout, stderr) = import(&dxf, Some("OPEN"), "100", &out);
        assert!(ok, "{name}: {stderr}");
        assert!(
            stdout.contains("open fraction 0.180000"),
            "{name}: {stdout}"
        );
        // Turned 90°, the 30×60 opening reads 60 wide and 30 tall.
        let d = udc_studio::io::design::file::load_design(&out).unwrap();
        let (rows, cols): (Vec<usize>, Vec<usize>) = d
            .opening
            .cells
            .iter()
            .enumerate()
            .flat_map(|(r, row)| row.iter().enumerate().map(move |(c, v)| (r, c, *v)))
            .filter(|(_, _, v)| *v > 0.5)
            .map(|(r, c, _)| (r, c))
            .unzip();
        let span = |v: &[usize]| v.iter().max().unwrap() - v.iter().min().unwrap() + 1;
        let (tall, wide) = (span(&rows), span(&cols));
        if half {
            assert_eq!((tall, wide), (6, 12), "{name}");
        } else {
            assert_eq!((tall, wide), (12, 6), "{name}");
        }
    }
    // A layer name on a GDSII file, and a DXF layer with nothing on it: one line each.
    gdstk(dir.path(), "a.gds", (0.0, 0.0), true);
    let out = dir.path().join("x.json");
    for (file, layer, want) in [
        ("a.gds", "OPEN", "layers are numbers"),
        ("blocks.dxf", "METAL", "nothing is drawn on layer METAL"),
    ] {
        let (ok, _, stderr) = import(&dir.path().join(file), Some(layer), "100", &out);
        assert!(!ok && stderr.contains(want), "{file} {layer}: {stderr}");
        assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
        assert!(!out.exists());
    }
}

/// Files written by KLayout: the 100-µm pixel's 30×60-µm opening drawn as a box, a path and a
/// polygon (and a text) on layer 1/0, arrayed 3×3 turned by 90° (`rot.gds`), as a half-size
/// cell magnified twice (`mag.gds`), and beside a second top cell (`two.gds`).
fn klayout(dir: &Path) {
    let code = "import klayout.db as db\n\
        def pixel(ly, name, s):\n\
        \x20   c = ly.create_cell(name)\n\
        \x20   l = ly.layer(1, 0)\n\
        \x20   c.shapes(l).insert(db.DBox(20 * s, 10 * s, 50 * s, 30 * s))\n\
        \x20   c.shapes(l).insert(db.DPath([db.DPoint(20 * s, 35 * s), db.DPoint(50 * s, 35 * s)], 10 * s))\n\
        \x20   c.shapes(l).insert(db.DPolygon(db.DBox(20 * s, 40 * s, 50 * s, 70 * s)))\n\
        \x20   c.shapes(l).insert(db.DText('OPENING', 25 * s, 25 * s))\n\
        \x20   return c\n\
        def write(name, s, trans, second):\n\
        \x20   ly = db.Layout()\n\
        \x20   ly.dbu = 0.001\n\
        \x20   top = ly.create_cell('TOP_A')\n\
        \x20   pix = pixel(ly, 'PIX', s)\n\
        \x20   top.insert(db.CellInstArray(pix.cell_index(), trans, db.Vector(100000, 0), db.Vector(0, 100000), 3, 3))\n\
        \x20   if second:\n\
        \x20       mark = ly.create_cell('TOP_B')\n\
        \x20       mark.shapes(ly.layer(1, 0)).insert(db.DBox(5000, 5000, 5010, 5010))\n\
        \x20   ly.write(name)\n\
        write('rot.gds', 1.0, db.ICplxTrans(1.0, 90.0, False, 0, 0), False)\n\
        write('mag.gds', 0.5, db.ICplxTrans(2.0, 0.0, False, 0, 0), False)\n\
        write('two.gds', 1.0, db.ICplxTrans(1.0, 0.0, False, 0, 0), True)\n";
    crate::common::python(dir, code, "klayout");
}

#[test]
fn klayout_files_with_turned_and_magnified_arrays_paths_boxes_and_two_top_cells() {
    let dir = tempfile::tempdir().unwrap();
    klayout(dir.path());
    let p = |n: &str| dir.path().join(n);
    // Turned and magnified arrays: the box, the path and the polygon make the one opening.
    for name in ["rot.gds", "mag.gds"] {
        let out = p(&format!("{name}.json"));
        let (ok, stdout, stderr) = import(&p(name), None, "100", &out);
        assert!(ok, "{name}: {stderr}");
        assert!(
            stdout.contains("open fraction 0.180000"),
            "{name}: {stdout}"
        );
        assert!(!stderr.contains("warning"), "{name}: {stderr}");
    }
    // The turned opening is 60 wide and 30 tall (cells of 5 µm: 12 × 6).
    let d = udc_studio::io::design::file::load_design(&p("rot.gds.json")).unwrap();
    let rows: Vec<usize> = d
        .opening
        .cells
        .iter()
        .map(|r| r.iter().filter(|v| **v == 1.0).count())
        .filter(|n| *n > 0)
        .collect();
    assert_eq!(rows, vec![12; 6], "{rows:?}");
    // Two top cells: which one is asked for, by name.
    let out = p("two.json");
    let (ok, _, stderr) = import(&p("two.gds"), None, "100", &out);
    assert!(!ok && !out.exists());
    assert!(
        stderr.contains("found 2 (")
            && stderr.contains("TOP_A")
            && stderr.contains("TOP_B")
            && stderr.contains("--cell"),
        "{stderr}"
    );
    let args = |cell: &str| {
        vec![
            "import".to_owned(),
            p("two.gds").to_str().unwrap().to_owned(),
            "--cell".to_owned(),
            cell.to_owned(),
            "--pitch-um".to_owned(),
            "100".to_owned(),
            "--cells".to_owned(),
            "20".to_owned(),
            "--out".to_owned(),
            out.to_str().unwrap().to_owned(),
        ]
    };
    let run_args = |a: Vec<String>| run(&a.iter().map(String::as_str).collect::<Vec<_>>());
    let (ok, stdout, stderr) = run_args(args("TOP_A"));
    assert!(ok, "{stderr}");
    assert!(stdout.contains("open fraction 0.180000"), "{stdout}");
    assert!(stderr.contains("3×3 array of cell `PIX`"), "{stderr}");
    // A DXF has no cells to choose.
    ezdxf(dir.path(), "a.dxf", false);
    let (ok, _, stderr) = run(&[
        "import",
        p("a.dxf").to_str().unwrap(),
        "--cell",
        "PIX",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!ok && stderr.contains("only GDSII"), "{stderr}");
    let (ok, _, stderr) = run_args(args("NOPE"));
    assert!(
        !ok && stderr.contains("no cell `NOPE`") && stderr.contains("TOP_B"),
        "{stderr}"
    );
}
