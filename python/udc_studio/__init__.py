"""UDC Studio's simulation core from Python.

The same core as the ``udc-studio`` command line and the studio: display designs for
under-display cameras, their PSFs and MTFs, captures restored with the thesis's pipeline
(BM3D, then Wiener), and the BM3D denoiser on its own.

>>> import udc_studio as udc
>>> design = udc.Design.from_preset("toled-150dpi")
>>> result = udc.analyze(design, quality="preview")
>>> result.psf.shape[0]                        # one PSF per colour channel
3

Every computation releases the GIL (call it from several threads at once) and stops on
Ctrl-C with ``KeyboardInterrupt``. Bad parameters raise ``ValueError`` and unreadable files
``OSError``, with the one-line messages of the command line.

Units are in the names: ``pitch_um`` is micrometres, ``light_e`` electrons, ``psnr_db``
decibels, frequencies are cycles per sensor pixel.
"""

from __future__ import annotations

import json
import os
import warnings
from dataclasses import dataclass, field
from typing import Any, Dict, List, Optional, Tuple, Union

import numpy as np

from . import _native, measured, phase, sensor

__version__: str = _native.__version__

PathLike = Union[str, "os.PathLike[str]"]

__all__ = [
    "Analysis",
    "Design",
    "Restoration",
    "analyze",
    "denoise",
    "load_photo",
    "presets",
    "restore",
    "measured",
    "phase",
    "sensor",
    "sweep",
    "sweep_figures",
    "view_figures",
    "save_figure",
    "theory",
    "MtfComparison",
    "TheoryComparison",
]


def presets() -> List[Tuple[str, str, str]]:
    """The built-in designs: ``(name, group, one-line description)``, as ``udc-studio presets``."""
    return list(_native.presets())


class Design:
    """A display design: one pixel's opening, its tiling, the camera optics and the channels.

    A ``Design`` is immutable: :meth:`with_` returns a modified copy. It holds the design file's
    JSON document, so :meth:`save` writes exactly what the studio and the CLI read.
    """

    __slots__ = ("_json", "_doc")

    def __init__(self, text: str) -> None:
        """A design from design-file JSON text (validated; ``ValueError`` names a bad field)."""
        self._json: str = _native.check_design_json(text)
        self._doc: Dict[str, Any] = json.loads(self._json)

    @classmethod
    def from_preset(cls, name: str) -> "Design":
        """A built-in design by name (see :func:`presets`)."""
        return cls(_native.preset_json(name))

    @classmethod
    def load(cls, path: PathLike) -> "Design":
        """A design file (``.json``) as the studio saves it."""
        return cls(_native.load_design_json(os.fspath(path)))

    def save(self, path: PathLike) -> None:
        """Writes the design file (atomically: a crash never leaves half a file)."""
        _native.save_design_json(os.fspath(path), self._json)

    def to_json(self) -> str:
        """The design file's text."""
        return self._json

    # The fields, read-only.
    @property
    def name(self) -> str:
        """The design's short name."""
        return str(self._doc.get("name", ""))

    @property
    def description(self) -> str:
        """Free text: what the design is and where it comes from."""
        return str(self._doc.get("description", ""))

    @property
    def pitch_um(self) -> float:
        """The display pixel pitch, µm."""
        return float(self._doc["opening"]["pitch_um"])

    @property
    def dpi(self) -> float:
        """Display pixels per inch (25 400 / ``pitch_um``)."""
        return 25400.0 / self.pitch_um

    @property
    def cells(self) -> np.ndarray:
        """The opening as an N × N float array of amplitude transmittance in [0, 1]."""
        return _native.cells(self._json)

    @property
    def opening(self) -> np.ndarray:
        """The opening as an N × N bool array: ``True`` where a cell lets light through."""
        return self.cells > 0.0

    @property
    def tiling(self) -> str:
        """``"repeat"``, ``"random-d4"`` or ``"random-4"``."""
        return str(self._doc["tiling"]["mode"])

    @property
    def seed(self) -> int:
        """The seed of the random orientations (ignored by ``"repeat"``)."""
        return int(self._doc["tiling"].get("seed", 0))

    @property
    def optics(self) -> Dict[str, Any]:
        """The camera optics and sampling, as the design file's ``optics`` object (a copy)."""
        return json.loads(json.dumps(self._doc["optics"]))

    @property
    def channels(self) -> List[str]:
        """The colour channels' names, in order."""
        return [str(c.get("name", "")) for c in self._doc.get("channels", [])]

    def with_(
        self,
        *,
        name: Optional[str] = None,
        pitch_um: Optional[float] = None,
        opening: Optional[np.ndarray] = None,
        tiling: Optional[str] = None,
        seed: Optional[int] = None,
        optics: Optional[Dict[str, Any]] = None,
    ) -> "Design":
        """A copy with the given fields changed (``optics`` merges into the current optics).

        ``opening`` is an N × N bool array (open cells) or float array (amplitude in [0, 1]);
        it replaces any polygons; emitters on cells that are now open are removed (all of them
        when N changes). Edited ``optics`` leave their named recipe (``"custom"``) unless
        ``recipe`` is among them.
        The result is validated as a design file is: ``ValueError`` names the bad field.
        """
        if seed is not None and (
            isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or not 0 <= seed < 2**64
        ):
            raise ValueError(f"seed: expected a whole number from 0 to 2^64 − 1 (got {seed!r})")
        text = _native.with_fields(
            self._json,
            name=name,
            pitch_um=None if pitch_um is None else _number(pitch_um, "pitch_um"),
            tiling=tiling,
            seed=None if seed is None else int(seed),
        )
        if optics is not None:
            doc = json.loads(text)
            changed = {k: v for k, v in optics.items() if doc["optics"].get(k) != v}
            doc["optics"].update(optics)
            # Values edited away from a named recipe are the design's own (as in the studio):
            # the thesis recipe's crop is then a warning with a fix, not a note.
            if changed and "recipe" not in optics:
                doc["optics"]["recipe"] = "custom"
            try:
                text = json.dumps(doc, allow_nan=False)
            except ValueError:
                raise ValueError(
                    f"optics: every value must be a finite number or text (got {optics!r})"
                ) from None
        if opening is not None:
            cells = np.asarray(opening)
            if cells.ndim != 2:
                raise ValueError(f"opening: expected an N×N array, got shape {cells.shape}")
            text = _native.with_cells(text, np.ascontiguousarray(cells, dtype=np.float64))
        return Design(text)

    def __repr__(self) -> str:
        return (
            f"Design({self.name!r}, pitch {self.pitch_um:g} µm ({self.dpi:.0f} DPI), "
            f"{self.cells.shape[0]}×{self.cells.shape[1]} cells, tiling {self.tiling})"
        )

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Design) and other._json == self._json

    def __hash__(self) -> int:
        return hash(self._json)


def _number(value: Any, what: str) -> float:
    try:
        return float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{what}: expected a number (got {value!r})") from None


def _design(design: Union[Design, str]) -> Design:
    """A design or a preset name."""
    return design if isinstance(design, Design) else Design.from_preset(design)


@dataclass(frozen=True, eq=False)
class Analysis:
    """What ``udc-studio analyze`` computes for a design, with its arrays.

    Arrays are per channel along their first axis, in :attr:`channels` order.
    """

    channels: List[str]
    wavelength_nm: np.ndarray
    """The channels' peak wavelengths, nm."""
    psf: np.ndarray
    """Channels × H × W over the sensor window, each summing to 1 (see :attr:`energy_in_window`)."""
    mtf: np.ndarray
    """Channels × H × W, the 2-D MTF with zero frequency at the centre."""
    freq_cyc_per_px: np.ndarray
    """The radial frequencies of :attr:`radial_min`, cycles per sensor pixel."""
    radial_min: np.ndarray
    """Channels × n: the radially-minimum MTF (the thesis's eq. 3.8)."""
    radial_mean: np.ndarray
    """Channels × n: the radially-averaged MTF."""
    auc: np.ndarray
    """Per channel, the area under :attr:`radial_min` (the thesis's AUC)."""
    invertibility: np.ndarray
    """Per channel, the invertibility score."""
    energy_in_window: np.ndarray
    """Per channel, the share of the light inside the sensor window."""
    ltr: float
    """Light transmittance ratio over the pupil."""
    open_fraction: float
    """Open area fraction of one tile."""
    invertibility_loss: float
    """L_inv pooled over the channels (the thesis's eq. 3.9)."""
    warnings: List[str]
    """Sampling and energy warnings, as the CLI prints them."""
    window_px: int
    """Side of the square sensor window, sensor pixels."""
    sensor_pixel_um: float
    """Sensor pixel pitch, µm."""
    elapsed_ms: float
    """Wall-clock time of the analysis, ms (as ``udc-studio analyze --json`` reports it)."""
    call_ms: float
    """Wall-clock time of the whole call inside Rust (the analysis and, unless skipped, the
    advice on its warnings), ms."""
    adapter: Optional[str]
    """The GPU adapter the PSFs were computed on (``backend="gpu"`` or ``"auto"``), or None
    where they were computed on the CPU."""
    _json: str = field(repr=False)

    def to_json(self) -> str:
        """The object ``udc-studio analyze --json`` prints for the same design and quality."""
        return self._json


def analyze(
    design: Union[Design, str],
    quality: str = "full",
    advice: str = "warnings",
    backend: str = "cpu",
) -> Analysis:
    """Analyses a design (or a preset name): PSF, MTF, AUC, LTR, invertibility, warnings.

    ``quality="preview"`` doubles the fine sampling where the f-number oversamples the PSF
    enough for the AUC to stay within 3 % of full quality's (about 4× faster), as the studio
    does while you draw; elsewhere (every preset at f/2.5) it is full quality.

    ``advice`` says which warnings get a fix, each checked by a further analysis:
    ``"warnings"`` (the default, as ``udc-studio analyze``), ``"all"`` (notes too, as
    ``--advice``) or ``"none"``. :meth:`Analysis.to_json` equals the CLI's for the same choice.

    ``backend`` says where the PSFs are computed, as ``udc-studio analyze --backend``:
    ``"cpu"`` (f64, the reference), ``"gpu"`` (f32 on a GPU through wgpu; a software driver
    counts; a ``ValueError`` where there is none) or ``"auto"`` (a hardware GPU when there is
    one, else the CPU with a ``RuntimeWarning`` saying why). :attr:`Analysis.adapter` names
    the GPU used.
    """
    raw = _native.analyze(_design(design).to_json(), quality, advice, backend)
    raw["_json"] = raw.pop("json")
    note = raw.pop("backend_note")
    if note is not None:
        warnings.warn(note, RuntimeWarning, stacklevel=2)
    return Analysis(**raw)


@dataclass(frozen=True, eq=False)
class MtfComparison:
    """The simulated MTF along x beside the aperture's closed-form MTF times the pixel's."""

    freq_cyc_per_px: np.ndarray
    """Frequencies, cycles per sensor pixel (0 … 0.5)."""
    simulated: np.ndarray
    predicted: np.ndarray
    deviation: float
    """Largest |simulated − predicted| (MTF(0) = 1)."""


@dataclass(frozen=True, eq=False)
class TheoryComparison:
    """The Theory view: one channel's simulated pattern beside the textbook's formula.

    Slits and rectangles compare the PSF summed over rows (light per column), a circle the
    PSF's axis row (Airy), a tiling the light in each diffraction order.
    """

    theory: str
    """``"single slit"``, ``"double slit"``, ``"rectangle"``, ``"circle"`` or the grating."""
    formula: str
    """The formula with this channel's numbers, as the Theory view prints it."""
    kind: str
    """What the values are (the plot's y axis)."""
    x_um: np.ndarray
    """Positions on the sensor, µm from the optical axis."""
    simulated: np.ndarray
    predicted: np.ndarray
    deviation: float
    """Largest |simulated − predicted| relative to the largest predicted value."""
    note: Optional[str]
    mtf: Optional[MtfComparison]


def theory(design: Union[Design, str], channel: int = 0, quality: str = "full") -> TheoryComparison:
    """Channel ``channel`` of the design beside its closed-form Fraunhofer pattern.

    The teaching presets (``fourier-slit``, ``fourier-circle``, …) name their shape; any other
    design is compared with the diffraction orders of its tiling.
    """
    raw = _native.theory(_design(design).to_json(), _whole(channel, "channel"), quality)
    mtf = raw.pop("mtf")
    return TheoryComparison(mtf=None if mtf is None else MtfComparison(**mtf), **raw)


def load_photo(path: PathLike, max_side_px: Optional[int] = None) -> np.ndarray:
    """A photo as ``udc-studio restore --image`` reads it: H × W × 3 (R, G, B) in [0, 1].

    With ``max_side_px`` the photo is scaled down so its longer side is at most that many
    pixels (``--max-side-px``). PNG, JPEG, TIFF, Radiance HDR and OpenEXR.
    """
    return _native.load_photo(os.fspath(path), _whole(max_side_px, "max_side_px", least=1))


def denoise(image: np.ndarray, sigma2: float) -> np.ndarray:
    """BM3D (CBM3D for an H × W × 3 colour image) with noise variance ``sigma2``.

    ``image`` is H × W (grey) or H × W × C, values on a [0, 1] scale; the result has its shape.
    """
    return _native.denoise(_float_image(image), float(sigma2))


@dataclass(frozen=True, eq=False)
class Restoration:
    """One capture through a design and its restoration (``udc-studio restore``'s run)."""

    captured: np.ndarray
    """The simulated capture, on the photo's scale and in its layout."""
    denoised: Optional[np.ndarray]
    """The denoised capture the deblurring started from; ``None`` with ``denoise="none"``."""
    restored: np.ndarray
    """The restored image."""
    psnr_db: float
    """PSNR of the restored image against the photo, dB (MSE pooled over channels)."""
    ssim: float
    """Mean SSIM over the channels."""
    captured_psnr_db: float
    denoised_psnr_db: Optional[float]
    denoise_sigma2: Optional[float]
    """The σ² BM3D got, on the capture's scale."""
    light_e: float
    """Electrons at a white pixel behind the reference display."""
    snr_db: float
    """The SNR at that pixel, dB."""
    adapter: Optional[str]
    """The GPU adapter the design's PSFs were computed on (``backend="gpu"`` or ``"auto"``),
    or None where they were computed on the CPU."""
    _json: str = field(repr=False)

    def to_json(self) -> str:
        """The run's object in ``udc-studio restore --json``."""
        return self._json


def restore(
    design: Union[Design, str],
    image: np.ndarray,
    *,
    light_e: Optional[float] = None,
    snr_db: Optional[float] = None,
    denoise: str = "bm3d",
    denoise_sigma2: Union[float, str, None] = None,
    method: str = "wiener",
    nsr: Optional[float] = None,
    lambda_: Optional[float] = None,
    iterations: Optional[int] = None,
    adc_bits: Optional[int] = None,
    noise_seed: int = 0,
    backend: str = "cpu",
) -> Restoration:
    """Captures ``image`` through the design at one light level and restores it.

    Give the light as ``light_e`` (electrons at a white pixel behind the reference T-OLED) or
    ``snr_db``. ``denoise="bm3d"`` runs the thesis's denoiser first, told the capture's own
    noise variance at white, ``1/e + 4.87²/e² + q²/12`` for the ``e`` electrons a white pixel
    collects and the ADC step ``q`` (``denoise_sigma2="matched"``, the default);
    ``denoise_sigma2="table"`` gives it the authors' chapter-3 table for the light level instead,
    and a number a variance of your own on the capture's scale. ``"none"`` deblurs the capture
    as it is.
    ``method`` is ``"wiener"`` (``nsr``) or ``"cg"`` (``lambda_``, ``iterations``). Defaults
    are the CLI's. ``backend`` says where the design's PSFs are computed, as in :func:`analyze`.
    """
    raw = _native.restore(
        _design(design).to_json(),
        _float_image(image),
        light_e=light_e,
        snr_db=snr_db,
        denoise=denoise,
        denoise_sigma2=denoise_sigma2,
        method=method,
        nsr=nsr,
        lambda_=lambda_,
        iterations=_whole(iterations, "iterations", least=1),
        adc_bits=_whole(adc_bits, "adc_bits", least=1),
        noise_seed=_whole(noise_seed, "noise_seed"),
        backend=backend,
    )
    raw["_json"] = raw.pop("json")
    raw.setdefault("denoised", None)
    note = raw.pop("backend_note")
    if note is not None:
        warnings.warn(note, RuntimeWarning, stacklevel=2)
    return Restoration(**raw)


def _float_image(image: Any) -> np.ndarray:
    """An image on the [0, 1] scale: floats as they are, unsigned integers (8- or 16-bit
    pixels) divided by their largest value, as the CLI reads PNG and TIFF files."""
    a = np.asarray(image)
    if a.dtype.kind == "u":
        return np.ascontiguousarray(a, dtype=np.float64) / float(np.iinfo(a.dtype).max)
    if a.dtype.kind == "b":
        return np.ascontiguousarray(a, dtype=np.float64)
    if a.dtype.kind != "f":
        raise ValueError(
            f"image: expected floats on a [0, 1] scale or unsigned integer pixels "
            f"(got dtype {a.dtype})"
        )
    return np.ascontiguousarray(a, dtype=np.float64)


def _whole(value: Any, what: str, least: int = 0) -> Optional[int]:
    """A whole-number parameter, or ``None``; ``ValueError`` naming it otherwise."""
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < least:
        raise ValueError(f"{what}: expected a whole number ≥ {least} (got {value!r})")
    return int(value)


def sweep(spec: PathLike, out: PathLike, threads: Optional[int] = None) -> Any:
    """Runs a sweep spec (TOML, as ``udc-studio sweep SPEC --out OUT``) and returns its table.

    A folder that already holds part of the sweep is resumed; Ctrl-C stops after the points in
    flight and keeps them. The table is ``OUT/results.csv``: a pandas ``DataFrame`` when pandas
    is installed, otherwise a dict of column name → numpy array (numbers) or list (text).
    """
    _native.sweep(os.fspath(spec), os.fspath(out), _whole(threads, "threads", least=1))
    return _read_table(os.path.join(os.fspath(out), "results.csv"))


def sweep_figures(out: PathLike) -> List[Dict[str, Any]]:
    """The figures of a sweep's results folder, as ``udc-studio sweep`` draws them into
    ``OUT/plots/`` and the studio on screen: one dict per plot with its ``title``, ``x`` and
    ``y`` axes (``label``, ``unit``, ``title``, ``categories``), ``series`` (``name``,
    ``colour`` as ``#rrggbb``, ``mark``, ``points`` as an N×2 array, ``band`` as an N×3 array
    of ``[x, low, high]`` or ``None``) and ``annotations``.
    """
    return list(_native.sweep_figures(os.fspath(out)))


def view_figures(
    design: Union[Design, str],
    quality: str = "preview",
    floor_decades: float = 6.0,
    airy: bool = True,
    orders: bool = False,
    backend: str = "cpu",
) -> List[Dict[str, Any]]:
    """The display workspace's figures of a design (or a preset name), as the studio draws its
    views: for each channel its PSF, log-PSF (down to ``floor_decades`` below the peak) and
    2-D MTF, then the RGB composite and the MTF curves. Each is a dict as
    :func:`sweep_figures` gives, plus ``images``: ``name``, ``unit``, ``values`` (rows ×
    columns, row 0 at the top), ``extent`` ``[left, right, bottom, top]`` for matplotlib's
    ``imshow``, ``scale`` (``kind`` ``"linear"`` with ``max`` or ``"log"`` with ``reference``
    and ``floor_decades``), ``colormap`` (matplotlib's name) and ``rgb`` (rows × columns × 3,
    ``uint8``: the colours drawn). ``airy`` and ``orders`` add the Airy ring and the
    diffraction orders to the PSFs' ``annotations``. ``backend`` says where the PSFs are
    computed, as in :func:`analyze`.
    """
    return list(
        _native.view_figures(
            _design(design).to_json(),
            quality,
            _number(floor_decades, "floor_decades"),
            bool(airy),
            bool(orders),
            backend,
        )
    )


def save_figure(
    design: Union[Design, str],
    out: Union[str, "os.PathLike[str]"],
    view: str = "log-psf",
    **params: Any,
) -> Dict[str, Any]:
    """Save one of the display views of a design (or a preset name) as a figure file, as
    ``udc-studio figure`` and the studio's Save figure write it: ``out`` ending in ``.svg`` or
    ``.png``; ``view`` one of ``psf``, ``log-psf``, ``rgb``, ``mtf-2d``, ``mtf``, ``theory``;
    further keywords as the command's flags (``channel="G"``, ``width_px=1600``, ``height_px=1000``,
    ``floor_decades=5``, ``caption="..."``, ``no_caption=True``, ``preview=True``, and for a
    comparison with view ``mtf`` ``against_preset="toled-150dpi"`` or ``against_design=PATH``).
    Returns what ``--json`` prints: ``file``, ``format``, ``view``, ``title``, ``caption``,
    ``against`` (design A's name, or None) and the size.
    A bad value raises ``ValueError`` naming it; nothing is written then.
    """
    from ._jobs import _plain  # noqa: PLC0415 - one helper for every job's keywords

    args: Dict[str, Any] = {k: _plain(v) for k, v in params.items()}
    args["out"] = os.fspath(out)
    args["view"] = view
    return dict(_native.save_figure(_design(design).to_json(), args))


def _read_table(path: str) -> Any:
    try:
        import pandas  # noqa: PLC0415 - optional
    except ImportError:
        pandas = None
    if pandas is not None:
        return pandas.read_csv(path)
    import csv  # noqa: PLC0415

    with open(path, newline="", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    columns: Dict[str, Any] = {}
    for name in rows[0].keys() if rows else []:
        values = [row[name] for row in rows]
        try:
            columns[name] = np.array([float(v) if v != "" else np.nan for v in values])
        except ValueError:
            columns[name] = values
    return columns
