"""Figures from Python: a display view saved as the command line and the studio save it."""

import xml.dom.minidom

import pytest

import udc_studio


def test_a_view_saves_as_svg_and_png_with_its_caption(tmp_path):
    design = udc_studio.Design.from_preset("toled-150dpi")
    svg = udc_studio.save_figure(design, tmp_path / "mtf.svg", view="mtf", preview=True)
    assert svg["format"] == "svg" and svg["view"] == "mtf"
    doc = xml.dom.minidom.parse(str(tmp_path / "mtf.svg"))
    texts = " ".join(
        n.data for n in doc.getElementsByTagName("text")[0].parentNode.getElementsByTagName("*")
        for n in n.childNodes
        if n.nodeType == n.TEXT_NODE
    )
    assert "cycles/pixel" in texts and "pitch 168.0" in texts
    png = udc_studio.save_figure(
        "toled-150dpi",
        tmp_path / "psf.png",
        view="log-psf",
        channel="G",
        width_px=640,
        height_px=400,
        caption="slide 3",
        preview=True,
    )
    assert png["caption"] == "slide 3" and "G log-PSF" in png["title"]
    with open(tmp_path / "psf.png", "rb") as f:
        header = f.read(24)
    assert header[:8] == b"\x89PNG\r\n\x1a\n"
    assert int.from_bytes(header[16:20], "big") == 640
    assert int.from_bytes(header[20:24], "big") == 400


def test_bad_figure_values_raise_naming_them(tmp_path):
    with pytest.raises(ValueError, match="svg or .png"):
        udc_studio.save_figure("toled-150dpi", tmp_path / "a.jpg", preview=True)
    with pytest.raises(ValueError, match="--width-px"):
        udc_studio.save_figure("toled-150dpi", tmp_path / "a.svg", width_px=5, preview=True)
    assert not list(tmp_path.iterdir())


def test_a_comparison_figure_names_both_designs(tmp_path):
    out = udc_studio.save_figure(
        "l2inv-random",
        tmp_path / "compare.svg",
        view="mtf",
        against_preset="toled-150dpi",
        preview=True,
    )
    assert out["against"] == "T-OLED 150 DPI"
    assert out["caption"].startswith("B: Top-10 L2 + inv, random") and "A: T-OLED" in out["caption"]
    with pytest.raises(ValueError, match="only the mtf view compares"):
        udc_studio.save_figure(
            "l2inv-random", tmp_path / "x.svg", view="psf", against_preset="toled-150dpi"
        )
