"""What the figures of one ``sunset figures`` run compute once and share.

Several figures draw the same frame: Figure 6's tape is the left half of
``fig6-rgb.png`` (exposed at the same hour), the traced frame behind
``quantisation.png``, and the cloudy frame of ``clouds.png`` is the geometry
of ``clouds-rgb.png``. Inside :func:`sharing` (which
:func:`sunset.figures.make_figures` opens around a run) each of them is
computed by the first figure that needs it and handed to the others;
outside it, every call computes afresh. Either way the values are the ones
the figure would compute itself, by the same functions (the tests compare the
figures' bytes both ways), so the figures are byte-identical.

Shared values are never modified by the figures: arrays are handed out
read-only, and a :class:`~sunset.light.lighting.Lighting` is shared only
where a figure adds no light source to it.
"""

from __future__ import annotations

import contextlib

import numpy as np

__all__ = ["sharing", "once", "frame", "codes", "exposure"]

#: (kind, key, value) of the run in progress; None outside :func:`sharing`.
_STORE: list | None = None


@contextlib.contextmanager
def sharing():
    """Share frames, codes, exposures and lights between the figures made inside the block (nested: the outer one)."""
    global _STORE
    if _STORE is not None:
        yield
        return
    _STORE = []
    try:
        yield
    finally:
        _STORE = None


def once(kind: str, key: tuple, make):
    """``make()``, computed once per ``(kind, key)`` inside :func:`sharing` (keys compare with ``==``)."""
    if _STORE is None:
        return make()
    for k, kk, value in _STORE:
        if k == kind and kk == key:            # scenes compare by value (frozen dataclasses)
            return value
    value = make()
    if isinstance(value, np.ndarray):
        value.setflags(write=False)
    _STORE.append((kind, key, value))
    return value


def _cached(kind: str, key: tuple):
    if _STORE is not None:
        for k, kk, value in _STORE:
            if k == kind and kk == key:
                return value
    return None


def frame(scene, t: float, reflections: int, work=None):
    """:func:`sunset.pipeline.frame.render` of ``scene`` at ``t`` (the whole frame, with the sea's bounces).

    ``work``: the frame's budget when the figure checked it already (:func:`sunset.pipeline.budget.rgb_work`).
    """
    from ..pipeline.frame import render

    return once("frame", (scene, float(t), int(reflections)),
                lambda: render(scene, float(t), int(reflections), sea_bounces=True, work=work))


def codes(scene, t: float, reflections: int, seed: int) -> np.ndarray:
    """The 8-bit codes (H, W) of ``scene`` at ``t``: :func:`sunset.pipeline.frame.code_frame`.

    From the shared frame when a figure traced it already (:func:`sunset.pipeline.frame.encode` of it: the
    same bytes).
    """
    from ..pipeline.frame import code_frame, encode

    def make():
        whole = _cached("frame", (scene, float(t), int(reflections)))
        if whole is not None:
            return encode(scene, whole, seed=seed)
        return code_frame(scene, float(t), int(reflections), seed)

    return once("codes", (scene, float(t), int(reflections), int(seed)), make)


def exposure(scene, t: float, reflections: int, seed: int, hours: float) -> np.ndarray:
    """:func:`sunset.pipeline.frame.expose` of :func:`codes` through the tables ``hours`` before sunset."""
    from ..pipeline.frame import expose

    return once("exposure", (scene, float(t), int(reflections), int(seed), float(hours)),
                   lambda: expose(scene, codes(scene, t, reflections, seed), float(hours)))
