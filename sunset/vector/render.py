"""The vector stage, end to end: a scene and a time in, a :class:`Frame` out.

``render`` runs the paper's pipeline for the rays: direct rays by the
height-field scan line (:mod:`sunset.vector.heightfield`, :mod:`sunset.model.islands`),
then reflected rays (:mod:`sunset.vector.reflect`), and, when the scene
has a cloud layer or posts in the water, those seen directly and by
reflection (:mod:`sunset.vector.clouds`, :mod:`sunset.vector.posts`).

Reflection modes
----------------
0
    Reflected rays go straight to the sky: no islands are pierced and no
    secondary reflection is looked for (a diagnostic; the cheapest mode).
1
    One reflection from the waves, each reflected R_z replaced by |R_z|, then
    the islands or the sky (Figure 5; Figure 4 is this mode on still water).
2
    Up to two reflections: secondary reflections off a parabolic cylinder
    fitted to the crest ahead, gathered and scattered (Figure 6).
"""

from __future__ import annotations


from ..errors import real_number, require_bool, require_instance, require_int_range, require_time
from .direct import IslandPass
from .frame import Frame
from ..model.scene import SceneLike, as_scene


def render(scene: SceneLike, t: float = 0.0, reflections: int = 2, *, islands: IslandPass | None = None,
           sea_bounces: bool = True) -> Frame:
    """Trace every pixel of ``scene`` at time ``t`` (seconds).

    Parameters
    ----------
    scene : Scene, str or path
        A scene, the name of a packaged scene (``"storm-swell"``) or a scene TOML file.
    t : float
        Time in seconds (the sea moves; nothing else does).
    reflections : {0, 1, 2}
        See the module docstring.
    islands : IslandPass, optional
        The islands' share of the direct rays, which does not change with
        time (:func:`sunset.vector.direct.island_pass`): a wave cycle
        computes it once and passes it to every frame.
    sea_bounces : bool
        Record each sea bounce (``Frame.incidence``, ``Frame.sea_rays``) for
        the RGB back end; the 8-bit tape does without them (32 bytes a pixel).

    Returns
    -------
    Frame
        Direct-ray and final-ray fields for every pixel.
    """
    from .clouds import add_clouds, reflected_clouds
    from .direct import trace_direct
    from .posts import add_posts, reflected_posts
    from .reflect import trace_reflections

    scene = as_scene(scene)
    require_time("t", real_number("t", t))
    require_int_range("reflections", reflections, 0, 2)
    require_bool("sea_bounces", sea_bounces)
    if islands is not None:
        require_instance("islands", islands, IslandPass)
    frame = trace_direct(scene, t, islands=islands)
    if scene.clouds is not None:
        add_clouds(scene, frame)
    if scene.posts:
        add_posts(scene, frame)
    trace_reflections(scene, frame, reflections, sea_bounces)
    if scene.clouds is not None:
        reflected_clouds(scene, frame)
    if scene.posts:
        reflected_posts(scene, frame)
    return frame
