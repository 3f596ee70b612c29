"""The scene in POV-Ray's scene language: an independent ray tracer for the same sea and islands.

:func:`pov_scene` writes a scene (at one time t) for POV-Ray 3.7 so that a
general-purpose ray tracer can render what this package renders with the
paper's special-purpose methods, and the two pictures can be held side by side
(``sunset export pov``; the speed chapter times both and compares them).

What is the same
----------------
* The camera window: the eye at the origin and the picture plane at distance
  1, so that the ray through the picture point (s, ζ) is (s, 1, ζ) in this
  package's coordinates, exactly as :class:`sunset.model.camera.Camera`.
  POV-Ray's coordinates are left-handed with y up; this package's are x right,
  y forward, z up, so a point (x, y, z) here is <x, z, y> there (the swap of
  two axes turns one handedness into the other). POV-Ray's camera shoots the
  ray ``direction + u·right + v·up`` for u, v in [−½, ½]; with
  ``direction`` = the window's centre and ``right``, ``up`` its width and
  height, that is the ray through (s, ζ).
* The sea: an isosurface of the same function, the sum over the wave trains
  of their Stokes harmonics a_n cos n(ℓx + my − ωt + φ) (eq. 1), below the
  eye by h; out to the farthest sample of the scan line, then the plane of
  mean sea level to the horizon (the far tail of the scan line).
* The islands: isosurfaces of H = max(P_b, min(Q, c + φ(Q − c))) with the
  cliff equation Q = P_c + Σ a cos(ℓx + my) (eqs. 3 and 4), each in a box
  that holds everything of it above the lowest sea.

What differs on purpose
-----------------------
The sea is a perfect mirror traced to two reflections (``max_trace_level``
3), with no |R_z| rule and no crest cylinders: POV-Ray reflects off the true
surface as often as the trace level allows. Every surface is painted in one
flat, self-lit colour, so that the picture says where each ray went:

=======================  ===========================================
colour                   meaning
=======================  ===========================================
blue  <0, 0, 1>          a direct ray to the sky
red   <1, 0, 0>          a direct ray to an island
green + what it reflects a direct ray to the sea (green <0, 1, 0>), plus the
                         colour its reflected ray finally meets: + blue, the
                         sky; + red, an island; only green, the sea again
                         after the second reflection
=======================  ===========================================

(:func:`sunset.figures.povray.pov_classes` reads a rendered picture back in
these terms.)

What is not exported: a scene's clouds and posts (the file says so in a
comment when the scene has them), and the sun, whose light the flat colours
do not need. The scene's title and its islands' names go into ``//``
comments through :func:`sunset.escape.pov_comment` (printable ASCII only:
no line break can end the comment and make POV-Ray read what follows).
"""

from __future__ import annotations

import math

import numpy as np

from ..constants import NEAR_PLANE_FRACTION
from .scene import Scene

__all__ = ["POV_COLOURS", "pov_scene", "sea_function", "island_function", "sea_reach", "island_box"]

#: The flat colours of the exported scene, by what a ray meets.
POV_COLOURS = {"sky": (0.0, 0.0, 1.0), "sea": (0.0, 1.0, 0.0), "island": (1.0, 0.0, 0.0)}


def _n(x: float) -> str:
    """A number as POV-Ray reads it back exactly (shortest round-trip repr)."""
    x = float(x)
    if x == 0.0:
        return "0"
    return repr(x).replace("e+", "e")


def _vec(*v) -> str:
    return "<" + ", ".join(_n(c) for c in v) + ">"


def sea_function(scene: Scene, t: float = 0.0) -> str:
    """The sea's surface as a POV-Ray function of x, y, z: ``y − (elevation − h)``, negative inside the water.

    The elevation is Σ_j Σ_n a_jn cos(n θ_j), θ_j = ℓ_j x + m_j z − ω_j t + φ_j
    (POV-Ray's z is this package's y); the phase constant −ω_j t + φ_j is
    written as one number.
    """
    h = scene.camera.eye_height
    terms = []
    for train in scene.sea.trains:
        if train.amplitude <= 0:
            continue
        l, m = train.wave_vector
        c = train.phase - train.omega * float(t)
        theta = f"({_n(l)}*x + {_n(m)}*z + {_n(c)})"
        for n, a in enumerate(train.harmonic_amplitudes(), start=1):
            if a != 0.0:
                terms.append(f"{_n(a)}*cos({n}*{theta})" if n > 1 else f"{_n(a)}*cos{theta}")
    elevation = " + ".join(terms) if terms else "0"
    return f"y - ({elevation} - {_n(h)})"


def island_function(island, eye_height: float) -> str:
    """An island's surface as a POV-Ray function: ``y − (H − h)``, negative inside the island (eqs. 3, 4)."""
    cl, bc = island.cliff, island.beach
    dx, dz = f"(x - {_n(island.x)})", f"(z - {_n(island.y)})"

    def paraboloid(p) -> str:
        return f"({_n(p.height)} - ({_n(p.e)}*{dx}*{dx} + {_n(p.f)}*{dx}*{dz} + {_n(p.g)}*{dz}*{dz}))"

    q = paraboloid(cl) + "".join(f" + {_n(c.amplitude)}*cos({_n(c.l)}*x + {_n(c.m)}*z)" for c in island.cosines)
    q = f"({q})"
    ct, phi = _n(island.cliff_top), _n(island.hill_factor)
    upper = f"min({q}, {ct} + {phi}*({q} - {ct}))"
    return f"y - (max({paraboloid(bc)}, {upper}) - {_n(eye_height)})"


def sea_reach(scene: Scene) -> tuple[float, float]:
    """(nearest, farthest) distance y of the sea's isosurface, metres: the scan line's clip and farthest sample."""
    cam = scene.camera
    dz = cam.pixel_pitch[1]
    y_far = cam.eye_height / (cam.sigma * dz)
    reach = max(abs(cam.zy_min), abs(cam.zy_max), dz)
    return NEAR_PLANE_FRACTION * cam.eye_height / reach, y_far


def island_box(island, eye_height: float, sea_max_elevation: float) -> tuple[tuple, tuple]:
    """The box (POV-Ray coordinates) that holds all of an island above the lowest sea.

    Outside the circle of radius ``island.smooth_radius(−(d + d_k))`` about
    the apex both paraboloids, the cosine terms added, lie below −d (d the
    sea's largest elevation, d_k the island's cosine amplitudes), where the sea
    hides them.
    """
    d = sea_max_elevation
    r = island.smooth_radius(-(d + island.max_perturbation)) + 1.0
    lo = (island.x - r, -eye_height - d - 1.0, island.y - r)
    hi = (island.x + r, island.max_height - eye_height + 1.0, island.y + r)
    return lo, hi


def _island_gradient_bound(island, radius: float) -> float:
    """A bound on |∇(y − H)| in the island's box: √(1 + G²), G the steepest paraboloid at the box's corner
    plus the cosines' slopes (H's slope is one of its parts', and the hill's is φ <= 1 times the cliff's)."""
    steepest = 0.0
    for p in (island.cliff, island.beach):
        lam_max = 0.5 * (p.e + p.g + math.hypot(p.e - p.g, p.f))
        steepest = max(steepest, 2.0 * lam_max * radius * math.sqrt(2.0))
    g = steepest + sum(c.amplitude * math.hypot(c.l, c.m) for c in island.cosines)
    return math.sqrt(1.0 + g * g)


def _sea_gradient_bound(scene: Scene) -> float:
    """A bound on |∇(y − elevation)|: √(1 + G²) with G = Σ_j Σ_n |a_jn| n k_j, the steepest the sea can be."""
    g = 0.0
    for train in scene.sea.trains:
        amps = np.abs(np.asarray(train.harmonic_amplitudes(), float))
        g += float(np.sum(amps * np.arange(1, len(amps) + 1))) * train.k
    return math.sqrt(1.0 + g * g)


def pov_scene(scene: Scene, t: float = 0.0) -> str:
    """The scene at time ``t`` (seconds) as a POV-Ray 3.7 scene file (text); see the module docstring."""
    from ..errors import require_time
    from ..escape import pov_comment
    from ..provenance import provenance_json

    require_time("t", t)
    if scene.sea.wind is not None:
        from ..errors import SunsetError
        from .windsea import NOT_EXPORTED
        raise SunsetError(NOT_EXPORTED)
    cam = scene.camera
    h = cam.eye_height
    d = scene.sea.max_elevation
    s_c, z_c = 0.5 * (cam.s_min + cam.s_max), 0.5 * (cam.zy_min + cam.zy_max)
    near, far = sea_reach(scene)
    half_width = max(abs(cam.s_min), abs(cam.s_max)) * far + 10.0
    sky, sea, isl = (_vec(*POV_COLOURS[k]) for k in ("sky", "sea", "island"))
    out = [
        f"// {pov_comment(scene.title or 'sunset scene')} at t = {_n(t)} s, written by `sunset export pov` for "
        f"POV-Ray 3.7.",
        "// This package's point (x, y, z) (x right, y forward, z up) is POV-Ray's <x, z, y>.",
        f"// Render at the scene's size: povray +I<this file> +W{cam.width} +H{cam.height} -A +FN",
        f"// made by: {pov_comment(provenance_json())}",
        *([f"// not exported: {', '.join(k for k, v in (('clouds', scene.clouds), ('posts', scene.posts)) if v)}"]
          if scene.clouds is not None or scene.posts else []),
        "#version 3.7;",
        "global_settings { assumed_gamma 1.0 max_trace_level 3 ambient_light 0 }",
        f"background {{ rgb {sky} }}",
        "camera {",
        "  perspective",
        "  location <0, 0, 0>",
        f"  direction {_vec(s_c, z_c, 1.0)}",
        f"  right {_vec(cam.s_max - cam.s_min, 0.0, 0.0)}",
        f"  up {_vec(0.0, cam.zy_max - cam.zy_min, 0.0)}",
        "}",
        "#declare Flat = finish { ambient 0 emission 1 diffuse 0 specular 0 phong 0 };",
        "#declare Mirror = finish { ambient 0 emission 1 diffuse 0 specular 0 phong 0 reflection { 1 } };",
        "// the sea, eq. 1, out to the farthest sample of the scan line",
        "isosurface {",
        f"  function {{ {sea_function(scene, t)} }}",
        f"  contained_by {{ box {{ {_vec(-half_width, -h - d - 0.01, near)}, "
        f"{_vec(half_width, -h + d + 0.01, far)} }} }}",
        f"  max_gradient {_n(_sea_gradient_bound(scene))}",
        "  accuracy 0.001",
        f"  pigment {{ rgb {sea} }} finish {{ Mirror }}",
        "}",
        "// beyond it, mean sea level to the horizon (the scan line's far tail)",
        f"plane {{ y, {_n(-h)} clipped_by {{ plane {{ -z, {_n(-far)} }} }} pigment {{ rgb {sea} }} finish {{ Mirror }} }}",
    ]
    for island in scene.islands:
        lo, hi = island_box(island, h, d)
        radius = 0.5 * (hi[0] - lo[0])
        out += [
            f"// island {pov_comment(island.name)}: eqs. 3 and 4",
            "isosurface {",
            f"  function {{ {island_function(island, h)} }}",
            f"  contained_by {{ box {{ {_vec(*lo)}, {_vec(*hi)} }} }}",
            f"  max_gradient {_n(_island_gradient_bound(island, radius))}",
            "  accuracy 0.001",
            f"  pigment {{ rgb {isl} }} finish {{ Flat }}",
            "}",
        ]
    return "\n".join(out) + "\n"
