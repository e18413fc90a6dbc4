#!/usr/bin/env python3
"""Independent reader for the mask tests (tests/mask_export.rs): measures what a mask file
really holds, with gdstk (GDSII) and ezdxf (DXF), and prints one JSON object.

    mask_check.py gds FILE LAYER DATATYPE [POINTS.json]
    mask_check.py dxf FILE LAYER_NAME_PREFIX
    mask_check.py dxf-audit FILE
    mask_check.py klayout FILE LAYER DATATYPE [OTHER_FILE]
    mask_check.py klayout-convert IN OUT
    mask_check.py oas-validate FILE
    mask_check.py klayout-drc FILE DECK.lydrc
    mask_check.py klayout-drc-batch LIST.json   ([[FILE, DECK], ...]: a list of answers)
    mask_check.py gds-layers FILE
    mask_check.py dxf-layers FILE

`klayout-drc` runs the checks a `.lydrc` deck the export wrote names (its `input`, `width`
and `space` lines) with KLayout's own Region checks on the file, and reports each output's
edge pairs: their count and distances (µm), and for the corner check the distinct points where
features touch.

For GDSII the top cell is flattened by gdstk (references, arrays, reflections and rotations
applied by gdstk, not by the studio), and the optional POINTS.json ([[x_um, y_um], ...]) is
answered with whether each point lies inside the flattened polygons.

The `-layers` modes report every layer of the (flattened) top cell or drawing: its polygons'
count, area and bounding boxes, and its texts with their place (and DXF height).
"""
import json
import sys


def check_gds(path, layer, datatype, points_path=None):
    import gdstk

    lib = gdstk.read_gds(path)
    tops = lib.top_level()
    if len(tops) != 1:
        raise SystemExit(f"expected one top cell, found {[c.name for c in tops]}")
    top = tops[0]
    polys = top.get_polygons(layer=layer, datatype=datatype)
    singles = sum(1 for r in top.references if r.repetition.size <= 1)
    arrays = sum(1 for r in top.references if r.repetition.size > 1)
    out = {
        "user_unit_m": lib.unit,
        "db_unit_m": lib.precision,
        "top": top.name,
        "cells": len(lib.cells),
        "polygons": len(polys),
        "max_vertices": max((len(p.points) for p in polys), default=0),
        "area_um2": sum(abs(p.area()) for p in polys),
        "references": singles,
        "arrays": arrays,
        "texts": [t.text for t in top.labels],
    }
    if points_path:
        with open(points_path) as f:
            pts = [tuple(p) for p in json.load(f)]
        out["inside"] = [bool(v) for v in gdstk.inside(pts, polys)]
    return out


def check_dxf(path, prefix):
    import ezdxf
    from ezdxf.math import area

    doc = ezdxf.readfile(path)
    msp = doc.modelspace()
    polys = [
        e
        for e in msp.query("LWPOLYLINE")
        if e.dxf.layer == prefix or e.dxf.layer.startswith(prefix + "_")
    ]
    return {
        "version": doc.dxfversion,
        "insunits": doc.header.get("$INSUNITS", 0),
        "polygons": len(polys),
        "closed": all(p.closed for p in polys),
        "max_vertices": max((len(p) for p in polys), default=0),
        "area_um2": sum(abs(area([(x, y) for x, y, *_ in p.get_points()])) for p in polys),
        "texts": [t.dxf.text for t in msp.query("TEXT")],
    }


def audit_dxf(path):
    """What a strict reader repairs: ezdxf's recover mode counts errors and fixes; also the
    header extents and the bounding box of every LWPOLYLINE vertex."""
    from ezdxf import recover

    doc, auditor = recover.readfile(path)
    xs, ys = [], []
    for e in doc.modelspace().query("LWPOLYLINE"):
        for x, y, *_ in e.get_points():
            xs.append(x)
            ys.append(y)
    return {
        "errors": [str(e.message) for e in auditor.errors],
        "fixes": [str(f.message) for f in auditor.fixes],
        "extmin": list(doc.header.get("$EXTMIN", (0, 0, 0)))[:2],
        "extmax": list(doc.header.get("$EXTMAX", (0, 0, 0)))[:2],
        "bbox": [min(xs), min(ys), max(xs), max(ys)] if xs else None,
    }


def klayout_read(path):
    """Reads `path` with KLayout in this process; its warnings go to stderr, which the caller
    captures (the tests require none)."""
    import klayout.db as db

    layout = db.Layout()
    options = db.LoadLayoutOptions()
    options.warn_level = 3
    layout.read(path, options)
    return layout


def check_klayout(path, layer, datatype, other=None):
    """KLayout's view of a mask: top cells, cells, the flattened region's merged area, and,
    with a second file, the area of the XOR of the two (0 when they draw the same thing)."""
    import klayout.db as db

    def region(path):
        layout = klayout_read(path)
        tops = layout.top_cells()
        index = layout.find_layer(layer, datatype)
        r = db.Region()
        if index is not None and len(tops) == 1:
            r = db.Region(tops[0].begin_shapes_rec(index))
        return layout, tops, r

    layout, tops, r = region(path)
    out = {
        "dbu_um": layout.dbu,
        "tops": [c.name for c in tops],
        "cells": layout.cells(),
        "shapes": r.count(),
        "area_um2": r.merged().area() * layout.dbu**2,
        "texts": sorted(
            {
                it.shape().text_string
                for li in layout.layer_indexes()
                for it in (tops[0].begin_shapes_rec(li) if len(tops) == 1 else [])
                if it.shape().is_text()
            }
        ),
    }
    if other:
        layout2, _, r2 = region(other)
        out["xor_area_um2"] = (r ^ r2).area() * layout.dbu**2
    return out


def klayout_convert(src, dst):
    """KLayout rewrites a mask in the format of `dst` (for OASIS: CBLOCKs, its own modal
    compression and repetitions), to test that our reader takes what other tools write."""
    import klayout.db as db

    layout = klayout_read(src)
    options = db.SaveLayoutOptions()
    if not options.set_format_from_filename(dst):
        raise SystemExit(f"KLayout has no writer for {dst}")
    options.oasis_write_cblocks = True
    options.oasis_compression_level = 10
    layout.write(dst, options)
    return {"written": dst}


def oas_validate(path):
    """gdstk's check of an OASIS file's END-record validation (CRC-32 or checksum)."""
    import gdstk

    valid, signature = gdstk.oas_validate(path)
    return {"valid": bool(valid), "signature": signature}


def bbox(points):
    xs = [p[0] for p in points]
    ys = [p[1] for p in points]
    return [min(xs), min(ys), max(xs), max(ys)]


def layers_gds(path):
    import gdstk

    lib = gdstk.read_gds(path)
    top = lib.top_level()[0]
    layers = {}
    for p in top.get_polygons():
        key = f"{p.layer}/{p.datatype}"
        entry = layers.setdefault(key, {"polygons": 0, "area_um2": 0.0, "bboxes": []})
        entry["polygons"] += 1
        entry["area_um2"] += abs(p.area())
        entry["bboxes"].append(bbox(p.points.tolist()))
    texts = [
        {"layer": f"{t.layer}/{t.texttype}", "text": t.text, "at": list(t.origin)}
        for t in top.get_labels()
    ]
    return {"layers": layers, "texts": texts}


def layers_dxf(path):
    import ezdxf
    from ezdxf.math import area

    doc = ezdxf.readfile(path)
    msp = doc.modelspace()
    layers = {}
    for e in msp.query("LWPOLYLINE"):
        pts = [(x, y) for x, y, *_ in e.get_points()]
        entry = layers.setdefault(e.dxf.layer, {"polygons": 0, "area_um2": 0.0, "bboxes": []})
        entry["polygons"] += 1
        entry["area_um2"] += abs(area(pts))
        entry["bboxes"].append(bbox(pts))
    texts = [
        {
            "layer": t.dxf.layer,
            "text": t.dxf.text,
            "at": list(t.dxf.insert)[:2],
            "height": t.dxf.height,
        }
        for t in msp.query("TEXT")
    ]
    return {"layer_table": [l.dxf.name for l in doc.layers], "layers": layers, "texts": texts}


def klayout_drc(path, deck_path):
    import re
    import xml.etree.ElementTree as ET

    import klayout.db as db

    text = ET.parse(deck_path).getroot().find("text").text
    ly = db.Layout()
    ly.read(path)
    source = re.search(r"drawn = input\((\d+), (\d+)\)(\.merged)?", text)
    layer, datatype = int(source.group(1)), int(source.group(2))
    region = db.Region(ly.top_cell().begin_shapes_rec(ly.layer(layer, datatype)))
    if source.group(3):
        region = region.merged()
    dbu = ly.dbu
    out = {}
    check = re.compile(
        r'drawn\.(width|space)\(([0-9.e+-]+)\.um, (projection|euclidian)\)\.output\("(\w+)"'
    )
    for kind, value, metric, name in check.findall(text):
        d = int(round(float(value) / dbu))
        m = db.Metrics.Projection if metric == "projection" else db.Metrics.Euclidian
        pairs = (region.width_check if kind == "width" else region.space_check)(d, False, m)
        found = list(pairs.each())
        entry = {
            "count": len(found),
            "distances_um": sorted(round(ep.distance() * dbu, 6) for ep in found),
        }
        if name == "corner_contact":
            points = set()
            for ep in found:
                a, b = ep.first, ep.second
                for p in (a.p1, a.p2):
                    if p in (b.p1, b.p2):
                        points.add((p.x, p.y))
            entry["points"] = len(points)
        out[name] = entry
    return out


def main(argv):
    if len(argv) >= 5 and argv[1] == "gds":
        out = check_gds(argv[2], int(argv[3]), int(argv[4]), argv[5] if len(argv) > 5 else None)
    elif len(argv) == 3 and argv[1] == "gds-layers":
        out = layers_gds(argv[2])
    elif len(argv) == 3 and argv[1] == "dxf-layers":
        out = layers_dxf(argv[2])
    elif len(argv) == 3 and argv[1] == "dxf-audit":
        out = audit_dxf(argv[2])
    elif len(argv) in (5, 6) and argv[1] == "klayout":
        out = check_klayout(argv[2], int(argv[3]), int(argv[4]), argv[5] if len(argv) > 5 else None)
    elif len(argv) == 4 and argv[1] == "klayout-drc":
        out = klayout_drc(argv[2], argv[3])
    elif len(argv) == 3 and argv[1] == "klayout-drc-batch":
        with open(argv[2]) as f:
            out = [klayout_drc(path, deck) for path, deck in json.load(f)]
    elif len(argv) == 4 and argv[1] == "klayout-convert":
        out = klayout_convert(argv[2], argv[3])
    elif len(argv) == 3 and argv[1] == "oas-validate":
        out = oas_validate(argv[2])
    elif len(argv) == 4 and argv[1] == "dxf":
        out = check_dxf(argv[2], argv[3])
    else:
        raise SystemExit(__doc__)
    print(json.dumps(out))


if __name__ == "__main__":
    main(sys.argv)
