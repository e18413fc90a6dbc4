//! The "What am I seeing?" paragraphs of the result views, in plain words (teaching overlays).

pub const PSF: &str = "The point-spread function (PSF) is the picture a single distant point of \
light makes on the sensor. Behind a display it is |Fourier transform of the aperture|²: the lens \
pupil multiplied by the display's transparent openings. The openings repeat every T (pitch + \
wiring gap), and a repeating grating throws light into diffraction orders: the bright spots spaced \
λf/T apart on the sensor (the cyan circles). The central spot is the light that goes straight \
through; its core is about the size of the Airy disc, radius 1.22 λ F# (the white ring). Light \
sent into the other orders shows up as ghosts and haze around bright objects. Axes are µm on the \
sensor, one square per sensor pixel, and the values of a channel sum to 1.";

pub const LOG_PSF: &str = "The same PSF on a logarithmic scale, so the faint orders and the halo \
become visible: every step on the colour bar is a factor of ten. Values below the floor (peak × \
10^−floor) take the floor colour, because the logarithm of zero is −∞. A random tiling (each \
pixel rotated or flipped at random) breaks the strict repetition: the sharp spots at λf/T spread \
into a smoother, dimmer halo. Same total light, but less structured ghosting.";

pub const RGB: &str = "The three colour channels together, each scaled to its own peak on the \
same log scale. Diffraction grows with wavelength (the order spacing λf/T is proportional to λ), \
so red's orders sit farther out than blue's: the rainbow fringes you would see around a street \
lamp photographed through this display.";

pub const MTF_2D: &str = "The modulation transfer function (MTF) says how much contrast a sine \
pattern keeps after the blur, for every frequency and direction. The centre is a uniform field \
(always 1); the edges are the sensor's limit, 0.5 cycles per pixel. It is |Fourier transform of \
the PSF|, the autocorrelation of the aperture, so the display's period shows up as a repeating \
structure. Dark spots are frequencies whose contrast nearly vanishes: detail there cannot be \
recovered by any deblurring, because noise swamps it.";

pub const MTF_PLOTS: &str = "Cuts through the MTF. Horizontal and vertical slices follow the two \
frequency axes; the radial mean averages every direction at each frequency, and the radial \
minimum keeps the worst direction. A radial minimum near 0 means some pattern of that fineness is \
lost and cannot be restored. The area under the radial minimum (AUC; 0.5 is perfect, and \
'normalised' divides by 0.5) sums up how invertible the blur is: bigger is better. The dotted \
lines mark multiples of ν = T·p/(λf) cycles/pixel, where the display's structure repeats in the \
MTF.";

pub const EXPECTED: &str = "First: the PSF of this one random tiling, one roll of the dice fixed by \
the seed. Second (beside it, or below it in a tall window): the expected PSF, the average over all \
random tilings, computed in closed form. Both use the same colour scale and open on where the \
light is; double-click returns there. The realisation shows speckle (fine random fluctuations) on top of \
the expected halo; re-rolling the seed changes the speckle but not the expectation.";

pub const COMPARE: &str = "A is the pinned design, B the current one, each with its own optics. \
The difference B − A is green where B is better (a larger AUC, light transmittance or energy in \
the window; a lower, more negative invertibility loss) and red where it is worse. Light \
transmittance (LTR) is the share of the lens's light that passes the display; AUC measures how \
well the blur can be undone. More open area lets more light through, but it is the shape of the \
openings that decides where the MTF dips.";

pub const RESTORE: &str = "A photo seen through the display: blurred by each channel's PSF, \
exposed with photon and read noise at the chosen light level (the brighter the display's LTR, the \
more electrons it collects), then restored by Wiener deconvolution or least squares. PSNR and SSIM \
compare the restoration with the original. A blur whose MTF has deep dips (a periodic T-OLED) \
loses those frequencies to the noise for good; random tiling and optimized openings keep them.";

pub const THEORY: &str = "Theory beside simulation. The Fourier-optics presets (Presets > Fourier \
optics) are apertures with a textbook answer: a slit gives sinc², two slits give Young's fringes \
under that envelope, a circle gives the Airy pattern, a grating puts light into orders whose \
strengths are the tile's Fourier coefficients. The top plot is the simulated PSF (solid) over \
the formula (dashed), sampled on the same sensor pixels; the bottom plot does the same for the \
MTF, the aperture's autocorrelation. Hover the formula for its numbers. Then draw in the pixel \
editor: the formula stays, the simulation follows your opening, and the gap between them is the \
diffraction of what you changed. Designs that name no aperture are compared with their own \
diffraction orders.";

pub const FIELD_DEPTH: &str = "The blur is not the same everywhere. Field: the display sits a \
little in front of the lens, so light from an angle crosses another part of the display (shifted \
by distance × tan(angle)). A periodic display looks the same from everywhere; a random one shows \
other tile orientations, so the PSF changes. Depth: focused on a near object the PSF is the \
infinity PSF scaled by z2/f from the lens law (a few per cent at 10 cm); focused at infinity, a \
near object is out of focus. Each PSF is shown with what is left after deblurring it with the \
reference PSF: a clean dot means the restoration's kernel still fits.";
/// The Appearance view.
pub const APPEARANCE: &str = "The built-in photo shown on this layout as a display would show it: \
every pixel's R, G and B emitters (the editor's Emitters layer, or an automatic placement) light \
with the photo's channel values, the layout scaled to the chosen DPI, then blurred by the eye \
(a Gaussian of 1 arcminute FWHM at the viewing distance). Left periodic, right random: random \
tilings trade a little display uniformity for a more invertible camera blur. Nonuniformity is \
the spread of a flat white field's luminance; aliasing the error energy of a slanted edge \
against an ideal full-fill display. Scatter presets places every thesis layout on camera AUC \
against display nonuniformity.";
