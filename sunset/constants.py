"""Physical and historical constants, each named once.

Every number that the paper prints, or that physics fixes, lives here so that
the rest of the package (and the book) can cite it by name.
"""

from __future__ import annotations

import math

#: Standard acceleration of gravity g, in m s⁻² (deep-water dispersion ω² = g k).
GRAVITY = 9.80665
#: The gravity a scene may set, m s⁻²: from a small moon's (Enceladus 0.11) to beyond the Sun's surface
#: (274); 5e-324 or 1e308 were accepted, and gave waves whose cycle or whose ω t left float64.
MIN_GRAVITY = 0.1
MAX_GRAVITY = 300.0

#: Hour angle rate of the sun: 2π/24 radians per hour, i.e. 15° per hour
#: (the paper's garbled "2π/2μ", READING-NOTES.md).
RADIANS_PER_HOUR = 2.0 * math.pi / 24.0
#: The range of "hours before sunset" a user may ask for: half the sun's 24-hour circle either side.
MAX_HOURS_FROM_SUNSET = 12.0

#: The sun's true angular radius, about 0.267°, in radians.
SUN_TRUE_RADIUS = math.radians(0.2666)

#: The paper's enlarged sun radius δ ("about .75" degrees), in degrees: the default of a Sun.
SUN_PAPER_RADIUS_DEGREES = 0.75

#: Image size printed in the paper for Figures 6 and 7: width × height pixels.
PAPER_WIDTH = 1020
PAPER_HEIGHT = 1023

#: Cray-1 computation time for one Figure 6 frame, seconds.
CRAY1_SECONDS_FIGURE6 = 34.0

#: The paper's projected sample spacing σ (text: "σ = 1/4"), in pixels.
PAPER_SIGMA = 0.25

#: Number of codes on the tape: 8 bits per pixel.
N_CODES = 256

#: Highest deep-water Stokes wave, steepness H/λ (Williams 1981: 0.1410633; Schwartz 1974): no
#: steepness above it is a wave, and the Stokes API refuses one. STOKES_MAP_STEEPNESS is the
#: point the exact solver's auxiliary map is tuned to (a little above: its √ stays positive).
STOKES_MAX_STEEPNESS = 0.141063
STOKES_MAP_STEEPNESS = 0.1411

#: Surface classes in Frame.surface.
SKY = -1
SEA = 0
#: What a ray meets in a cloud layer (sunset/model/clouds.py), in Frame.surface and Frame.final_surface.
CLOUD = -2

#: Island parts in Frame.part.
PART_NONE = 0
PART_BEACH = 1
PART_CLIFF = 2
PART_HILL = 3

# ---------------------------------------------------------------------------
# Colour codes, colour tables and the film (sunset/tape/codes.py, sunset/recorder/dicomed.py,
# sunset/tape/tapefile.py, sunset/recorder/film.py). Appended by the colour-codes helper.

#: Codes per group of the 8-bit code map (sunset/tape/codes.py); they sum to N_CODES.
#: Islands: green hill, brown cliff, tan beach (each a full turn of the
#: sun-plane angle ψ, see codes.rho_hat); sky by the final ray's z component;
#: the sun's track (|W·R| < sin δ) and the band beside it (sin δ <= |W·R| < sin 3δ),
#: both by the reflected ray's elevation. Track and halo get the same number of
#: codes, so that both resolve elevation equally finely: the halo (rays beside
#: the sun, not above or below it) then lights the same band of elevations as
#: the track, and the still-water reflection is one patch (book, chapter 9).
CODES_HILL = 40
CODES_CLIFF = 40
CODES_BEACH = 24
CODES_SKY = 56
CODES_TRACK = 48
CODES_HALO = 48

#: The third code range spans sin δ <= |W·R| < sin(HALO_FACTOR·δ) (the paper: 3δ).
HALO_FACTOR = 3.0

#: Scale of the random number added to |W·R| before it is thresholded, as a
#: fraction of sin δ: |W·R| + (u − 1/2)·TRACK_DITHER·sin δ, u uniform in [0, 1).
TRACK_DITHER = 1.0

#: How far towards sun colour the third range's entries go (0: sky, 1: sun).
HALO_STRENGTH = 0.5

#: Mean radius of the Earth, metres (spherical single-scattering sky).
EARTH_RADIUS = 6.371e6

#: Top of the model atmosphere, metres.
ATMOSPHERE_TOP = 80.0e3

#: Scale height of the molecular (Rayleigh) atmosphere, metres.
RAYLEIGH_SCALE_HEIGHT = 8.0e3

#: Scale height of the maritime aerosol, metres.
AEROSOL_SCALE_HEIGHT = 1.2e3

#: Ångström turbidity β (aerosol optical depth at 1 µm) and exponent α:
#: τ_a(λ) = β (λ / 1 µm)^−α (Ångström 1929); β = 0.05 is a clear maritime sky.
AEROSOL_ANGSTROM_BETA = 0.05
AEROSOL_ANGSTROM_ALPHA = 1.3

#: Henyey–Greenstein asymmetry g and single-scattering albedo ω of the aerosol.
AEROSOL_ASYMMETRY = 0.76
AEROSOL_ALBEDO = 0.9

#: Total ozone column, Dobson units, and one Dobson unit in molecules m⁻².
OZONE_COLUMN_DU = 300.0
DOBSON_UNIT = 2.687e20

#: The ozone layer: density a tent peaking at OZONE_PEAK_ALTITUDE, falling to
#: zero OZONE_HALF_WIDTH below and above (10–40 km); and the single height of
#: a thin layer used for the direct sun's ozone air mass (Komhyr 1980), metres.
OZONE_PEAK_ALTITUDE = 25.0e3
OZONE_HALF_WIDTH = 15.0e3
OZONE_LAYER_ALTITUDE = 22.0e3

#: Ozone absorption cross-section, m² per molecule, 360–830 nm in 10 nm bins
#: (Serdyuchenko et al. 2014, 233 K, bin averages as tabulated by Bruneton 2017):
#: the Chappuis band that keeps the twilight zenith blue (Hulburt 1953).
OZONE_CROSS_SECTION_NM = tuple(range(360, 831, 10))
OZONE_CROSS_SECTION = (
    1.18e-27, 2.182e-28, 2.818e-28, 6.636e-28, 1.527e-27, 2.763e-27, 5.52e-27, 8.451e-27,
    1.582e-26, 2.316e-26, 3.669e-26, 4.924e-26, 7.752e-26, 9.016e-26, 1.48e-25, 1.602e-25,
    2.139e-25, 2.755e-25, 3.091e-25, 3.5e-25, 4.266e-25, 4.672e-25, 4.398e-25, 4.701e-25,
    5.019e-25, 4.305e-25, 3.74e-25, 3.215e-25, 2.662e-25, 2.238e-25, 1.852e-25, 1.473e-25,
    1.209e-25, 9.423e-26, 7.455e-26, 6.566e-26, 5.105e-26, 4.15e-26, 4.228e-26, 3.237e-26,
    2.451e-26, 2.801e-26, 2.534e-26, 1.624e-26, 1.465e-26, 2.078e-26, 1.383e-26, 7.105e-27,
)

#: Effective temperature of the sun's photosphere, kelvin (blackbody spectrum).
SUN_TEMPERATURE = 5778.0

#: Elevation of the sun (degrees) at which a white horizontal surface in full
#: sun is exposed to linear value 1 (the film's fixed exposure).
EXPOSURE_SUN_ELEVATION = 30.0

#: How far the exposure follows the light: the film is exposed for
#: (sky luminance)^EXPOSURE_FOLLOW (0: a fixed exposure; 1: full automatic).
EXPOSURE_FOLLOW = 0.75

#: The display's response to luminance x relative to the exposure:
#: y = xⁿ/(xⁿ + σⁿ) (Naka & Rushton 1966), exponent n and semi-saturation σ.
#: n below 1 compresses: the eye adapted to a sunset sky still sees the
#: islands in shadow, some 150 to 430 times darker (chapter 08 computes it) than the sky near the sun.
EYE_RESPONSE_EXPONENT = 0.6
EYE_SEMI_SATURATION = 2.0

#: Refractive index of sea water in the visible (Fresnel reflectance of the
#: sea, which lights the islands from below with reflected skylight).
WATER_REFRACTIVE_INDEX = 1.34

#: Samples of the component of an island normal along W (the code keeps only
#: the sun-plane angle ψ; the skylight is averaged over the normals with that ψ).
ISLAND_NORMAL_SAMPLES = 12

#: Sub-samples per pixel side for the sun disk's anti-aliased rim.
SUN_SUPERSAMPLE = 16

#: Format version of tape files written by sunset/tape/tapefile.py.
TAPE_FORMAT_VERSION = 2

#: Film defaults: frames per second and hours before sunset at the start/end.
FILM_FPS = 24
FILM_FROM_HOURS = 1.5
FILM_TO_HOURS = -0.25

# --- height field and islands (sunset/vector/heightfield.py, sunset/model/islands.py) -----

#: Near clipping plane of the direct rays, as a fraction of the distance
#: h/|ζ| at which a ray at the steepest picture angle meets mean sea level.
#: The sea's nearest sample is at (h − d)/|ζ_min| unless waves reach this
#: close to the eye (d > (1 − NEAR_PLANE_FRACTION) h); then the plane clips.
NEAR_PLANE_FRACTION = 0.25

#: Samples (scan lines × samples) the vectorized scan line holds at once:
#: the memory bound of sunset.vector.heightfield (about 1 MB per float32 array, so that
#: a strip of scan lines stays in the cache while its profile is built and scanned).
SCANLINE_CHUNK_ELEMENTS = 1 << 18

#: Pixels in one strip of rows that a thread works on at a time (sunset.kernels.row_strips):
#: the strips' temporaries (the reflected rays, the dither) stay this small at any picture size.
STRIP_PIXELS = 1 << 16

#: Most refinement steps of the island lattice per sea sample (σ/m).
ISLAND_MAX_REFINEMENT = 4096

#: Most island samples per scan line and island, as a multiple of the
#: sea's samples per scan line (a memory and time bound for islands very
#: close to the eye; the refinement m is lowered to respect it).
ISLAND_SAMPLE_BUDGET = 4

#: Samples across an island's widest chord in the probe pass that chooses
#: the island lattice's refinement m (sunset.vector.heightfield).
ISLAND_PROBE_SAMPLES = 64

# --- Stokes waves (sunset/model/stokes.py). Appended by the waves-and-Stokes helper.

#: Largest step in k·H (wave height times wave number) between two solutions
#: of the continuation that leads the exact solver from a small wave to the
#: requested one; a step is halved if Newton's method fails to converge.
STOKES_CONTINUATION_STEP = 0.04

#: Newton's method on Babenko's equation stops when its step is below this
#: (dimensionless, in units of 1/k), after at most STOKES_NEWTON_ITERATIONS.
STOKES_NEWTON_TOLERANCE = 1e-12
STOKES_NEWTON_ITERATIONS = 40

#: The exact wave is accepted when every Fourier coefficient of its surface
#: in the last quarter of the resolved modes is below this (units of 1/k);
#: otherwise the number of modes is doubled, up to STOKES_MAX_MODES.
STOKES_TAIL_TOLERANCE = 1e-13
STOKES_MIN_MODES = 16
STOKES_MAX_MODES = 1024
#: Most points of StokesWave.surface (its cost grows as points × modes: 65,536 points of a 1024-mode
#: wave take about 1.5 s; a billion ran until killed).
STOKES_MAX_SURFACE_POINTS = 1 << 16
#: Largest |x| at which a series in α, ε or ω is summed (StokesSeries.partial_sum, .pade): every wave
#: has α, ε = π H/λ and ω in [0, 1]; far beyond it the sums overflow float64.
STOKES_SERIES_MAX_X = 1.0
#: Most amplitudes StokesSeries.at_steepness sums (each is an exact Padé approximant of its own series:
#: 16 of the order-80 series took about 30 s here, 80 of them would take minutes).
STOKES_MAX_AMPLITUDES = 16

# --- Stokes' series by computer (sunset/model/series.py, issue 13).

#: Largest order of the exact (rational) series: about a minute at 80 on one core.
STOKES_SERIES_MAX_ORDER_EXACT = 80
#: Largest order of the float64 series (its coefficients grow like 2.3^order,
#: and lose about a digit every eight orders to round-off; see the series module).
STOKES_SERIES_MAX_ORDER_FLOAT = 400

#: Modes of the coarse grid on which the continuation runs; finer grids are
#: reached by doubling, with one Newton solve each at the final height.
STOKES_COARSE_MODES = 64

#: Auxiliary conformal map u = 2 arctan(L tan(q/2)) (Lushnikov, Dyachenko &
#: Silantyev 2017) that crowds collocation points at the crest: by default
#: L = min(1, STOKES_MAP_FACTOR * sqrt(STOKES_MAP_STEEPNESS - H/λ)).
STOKES_MAP_FACTOR = 1.5

# --- Limits on what a scene or a command may ask for (sunset/model/camera.py,
# sunset/model/waves.py, sunset/model/scene.py, sunset/cli.py). Beyond them a request is
# refused with one error line instead of running out of memory or producing
# a picture the model cannot make.


#: Range of σ, the spacing of the height-field samples in pixels: from 16
#: samples per pixel (the sample arrays grow as 1/σ) to one every 16 pixels.
SIGMA_MIN = 1.0 / 16.0
SIGMA_MAX = 16.0

#: Highest eye, metres. The sea is a plane: at 10 km the true horizon dips
#: 3.2° below the flat model's, a sixth of the default picture's height.
MAX_EYE_HEIGHT = 10_000.0

#: Shortest wave, metres. Below about 1.7 cm surface tension, not gravity,
#: sets the speed of ripples, and ω = √(g k) (eq. 1's dispersion) no longer holds.
MIN_WAVELENGTH = 0.02

#: Most bytes of codes one film's tape may hold (frames × width × height).
MAX_TAPE_BYTES = 2**31

#: Most frames per second of a film.
MAX_FPS = 240

# ---------------------------------------------------------------------------
# Clouds by height functions (sunset/model/clouds.py, sunset/vector/clouds.py), the paper's last proposal.

#: Albedo of a cloud (single-scattering albedo of water droplets is ≈ 1; a thick
#: cloud reflects 0.6–0.9 of the light falling on it): chosen, not measured.
CLOUD_ALBEDO = 0.8
#: Depth below the mean cloud level over which the direct sunlight inside a cloud falls by 1/e, metres (chosen).
CLOUD_ATTENUATION_LENGTH = 150.0
#: Share of the direct sunlight that multiple scattering carries to any depth of a cloud (chosen).
CLOUD_MULTIPLE_SCATTERING = 0.12
#: Most cells in one cloud layer, and the highest mean level (the top of the troposphere), metres.
CLOUD_MAX_CELLS = 64
CLOUD_MAX_LEVEL = 15000.0
#: Smallest semi-axis of a cloud cell, and its smallest top or bottom but 0, metres (a length has a
#: physical minimum, not only a positive one).
CLOUD_MIN_SIZE = 1.0
#: Code map of a scene with clouds: the cloud range (by depth below the mean level) takes
#: codes from the islands and the sky; the track and halo keep theirs. Sums to N_CODES.
CLOUDY_CODES_HILL = 32
CLOUDY_CODES_CLIFF = 32
CLOUDY_CODES_BEACH = 16
CLOUDY_CODES_CLOUD = 32
CLOUDY_CODES_SKY = 48

# ---------------------------------------------------------------------------
# Posts in the water and the ripples of light on them (sunset/model/posts.py, sunset/light/ripples.py).

#: What a ray meets on a post (sunset/model/posts.py), in Frame.surface and Frame.final_surface.
POST = -3
#: Largest radius and height (above or below the water) of a post, metres.
POST_MAX_RADIUS = 20.0
POST_MAX_TOP = 100.0
#: Smallest radius, top and (unless 0) depth of a post, metres: a millimetre.
POST_MIN_SIZE = 0.001
#: Most posts in one scene.
POST_MAX_COUNT = 16
#: Light tracing of the ripples: the kernel's radius in texel heights, the most sun rays in one
#: texture (memory: about 200 bytes a ray), and the farthest reach of the water patch, metres.
RIPPLE_BANDWIDTH_TEXELS = 1.5
RIPPLE_MAX_RAYS = 1 << 23
RIPPLE_MAX_REACH = 80.0
#: The beams' side on the water for the wavefront tracer of the ripples, metres, and the most corners its mesh
#: takes by default (a larger patch gets larger cells: sunset/light/ripples.py, sunset/light/caustics.py).
RIPPLE_CELL = 0.05
RIPPLE_MESH = 1 << 18
#: How many rms slopes the water patch allows for (sunset/light/ripples.py).
RIPPLE_SLOPE_SIGMAS = 2.0
#: How far inland of the mean water line an island's shore band runs, metres (sunset/light/shore.py).
SHORE_INLAND = 120.0
#: The beams' side on the water along a shore, metres, and the most corners its mesh takes by default
#: (sunset/light/shore.py).
SHORE_CELL = 0.5
SHORE_MESH = 1 << 16
#: The beams along a shore are at least this many to a texel's height by default, no more (sunset/light/shore.py).
SHORE_TEXEL_CELLS = 5
#: The RGB back end's shore textures: a texel about SHORE_TEXEL_PIXELS pixels across at the island's nearest
#: water line, between SHORE_MIN_TEXELS and SHORE_TEXELS across the band (sunset/light/shore.py).
SHORE_TEXEL_PIXELS = 2.0
SHORE_MIN_TEXELS = 4
SHORE_TEXELS = 32
#: Depths at which the RGB back end tabulates a cloud's light for an hour (sunset/light/lighting.py).
CLOUD_TABLE_DEPTHS = 64

# --- Hostile input (issue 12): the physical range of every scene field, the
# most a scene, a tape or a command may ask for, and the work a frame may cost
# (sunset/model/*.py, sunset/vector/budget.py, sunset/tape/tapefile.py, sunset/cli.py).

#: Lowest eye, metres (a millimetre above the sea).
MIN_EYE_HEIGHT = 0.001

#: The picture window's edges s = x/y and ζ = z/y lie within ±MAX_WINDOW_SLOPE
#: (about 84° from the view axis).
MAX_WINDOW_SLOPE = 10.0
#: Narrowest picture window, either way (s_max − s_min, zy_max − zy_min): a nanoradian; a window of
#: 1e-300 makes the sea's lattice step denormal and its sample count overflow.
MIN_WINDOW_SPAN = 1e-9
#: Latest time t (and earliest, −t) of a frame, seconds: about 32 years. The fastest wave allowed
#: (MIN_WAVELENGTH) turns ω ≈ 56 rad/s under standard gravity (307 at MAX_GRAVITY), so its phase ω t
#: stays below 3.1e11 rad, kept to 1e-4 rad in float64; at 1e308 s, ω t overflowed to infinity and
#: the sea's phase raised a traceback.
MAX_TIME = 1e9

#: Longest wave, metres (ocean swell is at most about a kilometre long).
MAX_WAVELENGTH = 10_000.0

#: Steepest wave train: k·a, the slope of its first harmonic, at most 1 (45°,
#: more than twice the steepest wave that exists, k·a ≈ 0.44).
MAX_WAVE_SLOPE = 1.0

#: Directions and the sun's azimuth are degrees in [−360, 360]; phases radians
#: in [−MAX_PHASE, MAX_PHASE].
MAX_DEGREES = 360.0
MAX_PHASE = 1000.0

#: Smallest sun radius, degrees (the true sun is 0.27°; a smaller disk is
#: narrower than the track's dither and its colour tables lose meaning).
MIN_SUN_RADIUS = 0.01

#: Islands: apex within MAX_DISTANCE metres of the eye; heights (apexes, cliff
#: top, hill amplitudes) within ±MAX_ISLAND_HEIGHT metres; paraboloid
#: curvatures e, g in [MIN_CURVATURE, MAX_CURVATURE] m⁻¹; hill wave numbers
#: ℓ, m within ±MAX_HILL_WAVENUMBER rad m⁻¹ (hills at least 6 cm long).
MAX_DISTANCE = 1.0e6
MAX_ISLAND_HEIGHT = 1.0e4
MIN_CURVATURE = 1.0e-8
MAX_CURVATURE = 100.0
MAX_HILL_WAVENUMBER = 100.0

#: Most islands in a scene: the depth buffer keeps each pixel's surface as
#: one signed byte (−1 sky, 0 sea, 1 … 127 the islands).
MAX_ISLANDS = 127

#: Most wave trains in a sea and cosine terms on an island.
MAX_TRAINS = 64
MAX_COSINES = 64

#: Largest scene file, bytes, and deepest nesting of its tables and arrays.
MAX_SCENE_BYTES = 1 << 20
MAX_SCENE_DEPTH = 16

#: Longest text field of a scene (its title, an island's name), characters;
#: each must be printable (sunset.model.scene.check_text).
MAX_TEXT_CHARS = 200

#: Largest tape header (the scene's TOML and the times), bytes.
MAX_TAPE_HEADER_BYTES = 1 << 24

#: Most frames in a film's wave cycle (``--frames``), and most times a film shows the cycle.
MAX_CYCLE_FRAMES = 1000
MAX_FILM_CYCLES = 100

#: The work of one frame. Sea samples per pixel: the samples of the height
#: field along every scan line divided by the pixels (the sample count
#: depends on the picture window, not on the pixel count, so a window close to
#: and far below the horizon asks for millions per pixel; such a window is
#: refused). Each island adds at most ISLAND_SAMPLE_BUDGET times the sea's
#: samples (or one per pixel) per scan line.
MAX_SEA_SAMPLES_PER_PIXEL = 256

#: Peak memory of a frame, bytes per pixel: render, codes and the film
#: recorder's RGB together (sunset.bench.memory.measure_bytes_per_pixel
#: measures it; tests/test_hostile_input.py and chapter 11 check it), and the
#: memory a frame may take in all: the largest picture is MAX_FRAME_BYTES /
#: FRAME_BYTES_PER_PIXEL pixels.
FRAME_BYTES_PER_PIXEL = 320
MAX_FRAME_BYTES = 6 << 30

#: The rest of a command's memory (sunset.vector.budget; the bench's "budget"
#: row measures both in fresh processes): the interpreter's own, Python,
#: NumPy, Numba and the compiled kernels loaded and the colour tables made
#: (the peak resident memory of a process that rendered an 8 × 8 frame,
#: measured at 125–272 MiB), and what a frame's work takes whatever its size
#: (the tables of its hour, the encoder, the code it runs; 6–12 MiB measured).
INTERPRETER_BYTES = 384 << 20
FRAME_FIXED_BYTES = 16 << 20

#: The most samples one frame may take in all (sea, islands at their budget,
#: cloud samples and the pixels they cover, post tests: sunset.vector.budget);
#: about 0.05–0.2 µs each on two cores, so a frame at the bound takes minutes,
#: not hours. The cloud layer's memory per sample and per (sample, pixel) pair,
#: bytes (measured at 6–70 bytes per bounded pair; tests/test_hostile_input.py
#: checks the bound).
MAX_FRAME_SAMPLES = 2**31
CLOUD_BYTES_PER_SAMPLE = 256
CLOUD_BYTES_PER_PAIR = 64
#: The cloud layer is scanned in strips of scan lines of at most this many
#: samples and bounded pairs (one scan line at least): 256 MiB at most.
CLOUD_STRIP_PAIRS = 1 << 22

#: The RGB back end (sunset/light, ``--shading rgb``): peak bytes per traced
#: ray (samples × pixels; the geometry kept, shaded, filtered and encoded) and
#: the bytes of one hour's light (its sky grid) that do not grow with the
#: picture; sunset.bench.memory.measure_rgb_bytes measures both.
RGB_BYTES_PER_RAY = 400
RGB_LIGHT_BYTES = 384 << 20

#: Most pixels in one frame (width × height): MAX_FRAME_BYTES / FRAME_BYTES_PER_PIXEL,
#: about 20 megapixels (4,480 × 4,480; 19 of the paper's 1020 × 1023 frames).
MAX_PIXELS = MAX_FRAME_BYTES // FRAME_BYTES_PER_PIXEL
