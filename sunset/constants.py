"""Physical and historical constants, each named once.

Every number that the paper prints, or that physics fixes, lives here so that
the rest of the package (and the book) can cite it by name.
"""

from __future__ import annotations

import math

#: Standard acceleration of gravity g, in m s⁻² (deep-water dispersion ω² = g k).
GRAVITY = 9.80665

#: Hour angle rate of the sun: 2π/24 radians per hour, i.e. 15° per hour
#: (the paper's garbled "2π/2μ", READING-NOTES.md).
RADIANS_PER_HOUR = 2.0 * math.pi / 24.0

#: The sun's true angular radius, about 0.267°, in radians.
SUN_TRUE_RADIUS = math.radians(0.2666)

#: The paper's enlarged sun radius δ ("about .75" degrees), in radians.
SUN_PAPER_RADIUS = math.radians(0.75)

#: Image size printed in the paper for Figures 6 and 7: width × height pixels.
PAPER_WIDTH = 1020
PAPER_HEIGHT = 1023

#: Cray-1 computation time for one Figure 6 frame, seconds.
CRAY1_SECONDS_FIGURE6 = 34.0

#: Dicomed D-48 plotting time for the three colour passes, seconds.
DICOMED_SECONDS = 5 * 60.0

#: The paper's projected sample spacing σ (text: "σ = 1/4"), in pixels.
PAPER_SIGMA = 0.25

#: Number of codes on the tape: 8 bits per pixel.
N_CODES = 256

#: Highest deep-water Stokes wave, steepness H/λ (Schwartz 1974; Williams 1981).
STOKES_MAX_STEEPNESS = 0.1411

#: Surface classes in Frame.surface.
SKY = -1
SEA = 0

#: Island parts in Frame.part.
PART_NONE = 0
PART_BEACH = 1
PART_CLIFF = 2
PART_HILL = 3
PART_NAMES = {PART_NONE: "none", PART_BEACH: "beach", PART_CLIFF: "cliff", PART_HILL: "hill"}
