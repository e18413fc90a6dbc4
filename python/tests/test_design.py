"""Designs: presets, fields, copies with changes, files the CLI reads."""

import json

import numpy as np
import pytest

import udc_studio as udc
from conftest import run_cli


def test_presets_are_the_clis(cli):
    listed = run_cli(cli, "presets").stdout
    names = [line.split()[0] for line in listed.splitlines() if line.startswith("  ")]
    assert [name for name, _, _ in udc.presets()] == names
    assert all(group and description for _, group, description in udc.presets())


def test_the_toled_preset_is_a_five_of_twenty_one_slit():
    d = udc.Design.from_preset("toled-150dpi")
    assert d.pitch_um == 168.0
    assert d.dpi == pytest.approx(151.19, abs=0.01)
    opening = d.opening
    assert opening.dtype == np.bool_ and opening.shape == (21, 21)
    # A full-height slit: columns 8..12 open in every row, nothing else.
    assert opening[:, 8:13].all() and not opening[:, :8].any() and not opening[:, 13:].any()
    assert d.cells.dtype == np.float64
    assert d.tiling == "repeat" and d.channels == ["R", "G", "B"]
    assert d.optics["recipe"] == "iccp21"


def test_with_changes_a_copy_and_validates():
    d = udc.Design.from_preset("toled-150dpi")
    e = d.with_(tiling="random-d4", seed=7, pitch_um=84.0, optics={"window_px": 128})
    assert (e.tiling, e.seed, e.pitch_um, e.optics["window_px"]) == ("random-d4", 7, 84.0, 128)
    assert (d.tiling, d.seed, d.pitch_um) == ("repeat", 0, 168.0)
    # Optics edited away from the thesis recipe are the design's own (the crop warns).
    assert e.optics["recipe"] == "custom" and d.optics["recipe"] == "iccp21"
    assert d.with_(optics={"recipe": "iccp21", "window_px": 294}).optics["recipe"] == "iccp21"
    closed = np.zeros((21, 21), dtype=bool)
    closed[10, :] = True
    f = d.with_(opening=closed)
    assert np.array_equal(f.opening, closed)
    with pytest.raises(ValueError, match="opening.pitch_um"):
        d.with_(pitch_um=float("nan"))
    with pytest.raises(ValueError, match="tiling"):
        d.with_(tiling="spiral")
    with pytest.raises(ValueError, match="opening"):
        d.with_(opening=np.full((21, 21), 2.0))
    with pytest.raises(ValueError, match="N×N"):
        d.with_(opening=np.ones(21))
    for seed in (-1, 2**64, 1.5, "3"):
        with pytest.raises(ValueError, match="seed"):
            d.with_(seed=seed)
    with pytest.raises(ValueError, match="pitch_um"):
        d.with_(pitch_um="wide")


def test_a_saved_design_reads_back_and_the_cli_analyses_it_the_same(tmp_path, cli):
    d = udc.Design.from_preset("l2inv-random").with_(seed=11)
    path = tmp_path / "mine.json"
    d.save(path)
    assert udc.Design.load(path) == d
    ours = json.loads(udc.analyze(d, quality="preview").to_json())
    theirs = json.loads(
        run_cli(cli, "analyze", str(path), "--preview", "--json").stdout
    )
    for report in (ours, theirs):
        report.pop("elapsed_ms")
        report.pop("tool_version", None)
    assert ours == theirs


def test_bad_designs_and_files_raise():
    with pytest.raises(ValueError, match="unknown preset"):
        udc.Design.from_preset("no-such-preset")
    with pytest.raises(ValueError):
        udc.Design("{ not json")
    with pytest.raises(OSError, match="cannot read the design"):
        udc.Design.load("/no/such/design.json")


def test_a_malformed_design_file_names_the_file(tmp_path):
    path = tmp_path / "broken.json"
    path.write_text('{"format": "udc-studio-design", "version": 1, "opening": 3}')
    with pytest.raises(OSError, match="broken.json"):
        udc.Design.load(path)
