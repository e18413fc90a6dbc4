#!/usr/bin/env python3
"""Independent reader for the mask tests (tests/mask_export.rs): measures what a mask file
really holds, with gdstk (GDSII) and ezdxf (DXF), and prints one JSON object.

    mask_check.py gds FILE LAYER DATATYPE [POINTS.json]
    mask_check.py dxf FILE LAYER_NAME_PREFIX
    mask_check.py dxf-audit FILE
    mask_check.py gds-layers FILE
    mask_check.py dxf-layers FILE

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


def main(argv):
    if len(argv) >= 5 and argv[1] == "gds":
        out = check_gds(argv[2], int(argv[3]), int(argv[4]), argv[5] if len(argv) > 5 else None)
    elif len(argv) == 3 and argv[1] == "gds-layers":
        out = layers_gds(argv[2])
    elif len(argv) == 3 and argv[1] == "dxf-layers":
        out = layers_dxf(argv[2])
    elif len(argv) == 3 and argv[1] == "dxf-audit":
        out = audit_dxf(argv[2])
    elif len(argv) == 4 and argv[1] == "dxf":
        out = check_dxf(argv[2], argv[3])
    else:
        raise SystemExit(__doc__)
    print(json.dumps(out))


if __name__ == "__main__":
    main(sys.argv)
