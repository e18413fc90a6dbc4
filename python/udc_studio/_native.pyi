"""Type stubs of the compiled module ``udc_studio._native`` (see ``python/src/``).

The public API is ``udc_studio`` itself; these are the plain functions it wraps. A test
(``tests/test_stubs.py``) checks every name and parameter here against the module.
"""

from typing import Any, Dict, List, Optional, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str

def presets() -> List[Tuple[str, str, str]]: ...
def preset_json(name: str) -> str: ...
def load_design_json(path: str) -> str: ...
def save_design_json(path: str, text: str) -> None: ...
def check_design_json(text: str) -> str: ...
def cells(text: str) -> npt.NDArray[np.float64]: ...
def with_cells(text: str, cells: npt.NDArray[np.float64]) -> str: ...
def with_fields(
    text: str,
    *,
    name: Optional[str] = None,
    pitch_um: Optional[float] = None,
    tiling: Optional[str] = None,
    seed: Optional[int] = None,
) -> str: ...
def analyze(
    design_json: str, quality_name: str = "full", advice: str = "warnings"
) -> Dict[str, Any]: ...
def theory(design_json: str, channel: int = 0, quality_name: str = "full") -> Dict[str, Any]: ...
def denoise(image: npt.NDArray[np.float64], sigma2: float) -> npt.NDArray[np.float64]: ...
def load_photo(path: str, max_side_px: Optional[int] = None) -> npt.NDArray[np.float64]: ...
def restore(
    design_json: str,
    image: npt.NDArray[np.float64],
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
) -> Dict[str, Any]: ...
def run_json(words: List[str]) -> str: ...
def sweep(spec: str, out: str, threads: Optional[int] = None) -> Dict[str, Any]: ...
