"""The Cray-1 made concrete: the renderer's loops counted, and timed on a model of the machine.

The paper reports 34 s of Cray-1 time for one 1020 × 1023 frame of Figure 6.
This module turns the renderer's loops into operation counts per frame, from
the scene and from the frame the renderer actually traces (how many samples
per scan line, how many island samples, how many rays reflect twice), and
times them on a simple model of the Cray-1's vector unit.

What is taken from the machine's documentation (book, chapter *History*):
a clock period of 12.5 ns; vector registers of 64 elements, longer loops
being run in strips of 64 and a remainder; at most one result per clock from
each functional unit once its pipeline is full, and two (an add and a multiply)
when one operation's results are chained into the next.

What is *assumed* here, and named so that it can be varied: how many vector
operations a cosine, a square root and a division cost (computed from
simpler vector operations: polynomials, reciprocal approximations and
corrections), the pipeline start-up paid by every vector
instruction in every strip, and the clock periods per iteration of the one
loop that does not vectorize, the scan conversion.

The result is two estimates: every operation at one result per clock (no
overlap), and at two (perfect chaining, the machine's peak). A real program
lies between them or, held back by memory and start-up, below the slower.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from ..errors import SunsetError

#: The Cray-1's clock period, seconds (12.5 ns: 80 million clock periods a second).
CLOCK_S = 12.5e-9
#: Elements in one vector register: loops are run in strips of this many.
VECTOR_LENGTH = 64


@dataclass(frozen=True)
class CrayCosts:
    """The model's assumptions, in vector operations (one result per clock each) or clock periods.

    Attributes
    ----------
    trig : float
        Vector operations per element for a cosine or a sine (range reduction
        and a polynomial). Assumed.
    sqrt : float
        Vector operations per element for a square root. Assumed.
    divide : float
        Vector operations per element for a division (reciprocal approximation,
        a Newton step, a multiply). Assumed.
    startup : float
        Clock periods to fill a pipeline, paid by every vector instruction in
        every strip of 64. Assumed.
    scalar_iteration : float
        Clock periods per iteration of the scan-conversion loop, which runs in
        scalar code. Assumed.
    """

    trig: float = 25.0
    sqrt: float = 12.0
    divide: float = 4.0
    startup: float = 10.0
    scalar_iteration: float = 10.0

    def __post_init__(self):
        for name in ("trig", "sqrt", "divide", "startup", "scalar_iteration"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v >= 0):
                raise SunsetError(f"{name} must be a finite number >= 0, got {v!r}")


@dataclass(frozen=True)
class Loop:
    """One vectorizable loop of the renderer: how many elements, and what each costs.

    Counts are per element: floating adds (and subtracts, compares), multiplies,
    divisions, square roots, cosines or sines, and memory words loaded or stored.
    """

    name: str
    elements: int
    adds: int = 0
    muls: int = 0
    divides: int = 0
    sqrts: int = 0
    trig: int = 0
    memory: int = 0
    vector: bool = True

    def operations(self, costs: CrayCosts) -> float:
        """Vector operations per element, library functions expanded."""
        return (self.adds + self.muls + costs.divide * self.divides + costs.sqrt * self.sqrts
                + costs.trig * self.trig + self.memory)

    def strips(self) -> int:
        """Strips of 64 (the last one partial) the loop runs in."""
        return -(-int(self.elements) // VECTOR_LENGTH)

    def clocks(self, costs: CrayCosts, results_per_clock: float) -> float:
        """Clock periods: the operations at ``results_per_clock``, plus start-up per instruction per strip."""
        if not self.vector:
            return self.elements * costs.scalar_iteration
        ops = self.operations(costs)
        return self.elements * ops / results_per_clock + self.strips() * ops * costs.startup


@dataclass
class FrameCount:
    """The loops of one Figure 6 frame, with the counts that sized them."""

    width: int
    height: int
    samples: int
    island_samples: int
    sea_pixels: int
    twice: int
    trains: int
    harmonics: int
    islands: int
    cosines: int
    loops: list[Loop] = field(default_factory=list)

    @property
    def pixels(self) -> int:
        """Pixels in the frame."""
        return self.width * self.height

    def operations(self, costs: CrayCosts | None = None) -> float:
        """Vector operations in the frame's vectorizable loops."""
        costs = costs or CrayCosts()
        return sum(lp.elements * lp.operations(costs) for lp in self.loops if lp.vector)

    def per_pixel(self, costs: CrayCosts | None = None) -> float:
        """Vector operations per pixel."""
        return self.operations(costs) / self.pixels

    def seconds(self, costs: CrayCosts | None = None, results_per_clock: float = 1.0) -> float:
        """Estimated Cray-1 seconds for the frame at ``results_per_clock`` (1: no overlap; 2: chained)."""
        if not results_per_clock > 0:
            raise SunsetError(f"results_per_clock must be positive, got {results_per_clock!r}")
        costs = costs or CrayCosts()
        return sum(lp.clocks(costs, results_per_clock) for lp in self.loops) * CLOCK_S

    def table(self, costs: CrayCosts | None = None) -> list[tuple[str, int, float, float, float]]:
        """(loop, elements, operations per element, seconds unchained, seconds chained) for every loop."""
        costs = costs or CrayCosts()
        return [(lp.name, lp.elements, lp.operations(costs) if lp.vector else math.nan,
                 lp.clocks(costs, 1.0) * CLOCK_S, lp.clocks(costs, 2.0) * CLOCK_S) for lp in self.loops]


def count_frame(scene, t: float = 0.0) -> FrameCount:
    """Count the loops of one Figure 6 frame of ``scene`` (at its camera's size) at time ``t``.

    The sizes come from the renderer itself: the scan lines' sample count and
    island samples from :func:`sunset.pipeline.frame.trace_direct`, the sea
    pixels and the twice-reflected rays from :func:`sunset.pipeline.frame.trace_reflections`.
    The operations per element are counted from the formulas the loops
    evaluate (the module's docstrings and the book's chapter *History* show
    them as FORTRAN beside the NumPy).
    """
    from ..constants import SEA
    from .frame import trace_direct, trace_reflections

    info: dict = {}
    frame = trace_reflections(scene, trace_direct(scene, t, info=info), 2)
    cam = scene.camera
    W, H = cam.width, cam.height
    trains = [tr for tr in scene.sea.trains if tr.amplitude > 0]
    J = len(trains)
    harm = sum(len(tr.harmonic_amplitudes()) - 1 for tr in trains)   # extra Stokes harmonics, all trains
    n = int(info["sea_samples"])
    isl = int(info["island_samples"])
    sea = int((frame.surface == SEA).sum())
    twice = int((frame.bounces == 2).sum())
    K = len(scene.islands)
    cos_terms = sum(len(i.cosines) for i in scene.islands)
    mean_cos = cos_terms / K if K else 0.0

    loops = [
        # g(y_i) = (Σ_j a_j cos(b_j y_i + c_j) − h)·u_i: per train a multiply-add and a cosine,
        # Horner over the harmonics (a multiply and an add each), an add into the sum
        Loop("sea profile g(y_i)", n * W, adds=2 * J + harm + 1, muls=J + harm + 1, trig=J, memory=2),
        # the lost loop: one scalar iteration per sample and per pixel of every scan line
        Loop("scan conversion (scalar)", (n + H) * W, vector=False),
        # Q = P_c + Σ a cos(ℓx + my), beach P_b, hill factor, max/min: per island sample
        Loop("island profiles", isl, adds=9 + 3 * round(mean_cos) + 4, muls=8 + 3 * round(mean_cos) + 2,
             trig=round(mean_cos), memory=3),
        # the point and the normal: f_x, f_y = −Σ a ℓ sin, −Σ a m sin; N = (−f_x, −f_y, 1)/√(f_x² + f_y² + 1)
        Loop("sea normals", sea, adds=3 * J + 2 * harm + 2, muls=3 * J + 2 * harm + 4, divides=1, sqrts=1,
             trig=J, memory=6),
        # R = D − 2(D·N)N
        Loop("reflection R", sea, adds=5, muls=7, memory=9),
        # eqs. 5-6 for the crest cylinder: a, b, c, the discriminant, the smaller root
        Loop("crest cylinder quadratic", sea, adds=10, muls=12, divides=1, sqrts=1, memory=7),
        # gathered: the true normal at the piercing point and the second reflection, scattered back
        Loop("second reflection (gathered)", twice, adds=3 * J + 2 * harm + 7 + 5, muls=3 * J + 2 * harm + 4 + 7,
             divides=1, sqrts=1, trig=J, memory=12),
        # eqs. 5-6 for each island's two paraboloids, and the nearest hit kept
        Loop("island quadratics", sea * K * 2, adds=12, muls=14, divides=1, sqrts=1, memory=8),
        # ρ̂(N) or |W·R| and the elevation, the dither, the code
        Loop("codes", W * H, adds=8, muls=10, sqrts=1, trig=1, memory=5),
    ]
    return FrameCount(width=W, height=H, samples=n, island_samples=isl, sea_pixels=sea, twice=twice,
                      trains=J, harmonics=harm, islands=K, cosines=cos_terms, loops=loops)
